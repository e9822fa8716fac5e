#include "report/sweep_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "engine/number_format.h"
#include "plot/labels.h"
#include "plot/plot.h"

namespace pwsim::report {
namespace {

namespace fs = std::filesystem;

/// Numbers of a column, or nothing when a value is not a number.
std::optional<std::vector<double>> Numeric(const std::vector<std::string>& texts) {
  std::vector<double> values;
  for (const std::string& text : texts) {
    const std::optional<double> value = ParseFiniteNumber(text);
    if (!value) return std::nullopt;
    values.push_back(*value);
  }
  return values;
}

std::string FileStem(const std::string& key) {
  std::string stem;
  for (char c : key) stem += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' ? c : '_';
  return stem;
}

/// One figure per numeric swept variable: a panel per numeric field, a series per combination
/// of the other variables, points joined in order of the variable.
}  // namespace

std::vector<fs::path> WriteSweepPlots(const sweep::Manifest& manifest, const sweep::Collection& collection) {
  std::vector<fs::path> written;
  if (!plot::GnuplotAvailable()) {
    std::cout << "  (no gnuplot on PATH: plots skipped)\n";
    return written;
  }
  const std::size_t n_vars = collection.variables.size();
  for (std::size_t v = 0; v < n_vars; ++v) {
    std::vector<std::string> texts;
    for (const auto& row : collection.rows) texts.push_back(row.values[v]);
    const auto x = Numeric(texts);
    if (!x || std::set<double>(x->begin(), x->end()).size() < 2) continue;
    const plot::Quantity x_quantity = plot::QuantityFromKey(collection.variables[v]);
    plot::Figure figure;
    figure.title = "Sweep " + manifest.name + ": each result against " + x_quantity.words + " (one point per task)";
    figure.x_label = plot::AxisLabel(x_quantity);
    for (std::size_t f = 0; f < collection.field_names.size(); ++f) {
      const plot::Quantity y_quantity = plot::QuantityFromKey(collection.field_names[f]);
      plot::Panel panel;
      panel.title = y_quantity.words;
      panel.y_label = plot::AxisLabel(y_quantity);
      std::map<std::string, std::vector<std::pair<double, double>>> groups;
      bool any = false, positive = false, negative = false;
      for (std::size_t r = 0; r < collection.rows.size(); ++r) {
        std::string label;
        for (std::size_t o = 0; o < n_vars; ++o) {
          if (o == v) continue;
          const plot::Quantity other = plot::QuantityFromKey(collection.variables[o]);
          const std::optional<double> value = ParseFiniteNumber(collection.rows[r].values[o]);
          label += (label.empty() ? "" : ", ") + other.words + " " +
                   (value ? FormatDouble(*value * other.scale) + (other.unit.empty() ? "" : " " + other.unit)
                          : collection.rows[r].values[o]);
        }
        const double y = collection.rows[r].numbers[f] * y_quantity.scale;
        any = any || std::isfinite(y);
        positive = positive || y > 0.0;
        negative = negative || y < 0.0;
        groups[label].push_back({(*x)[r], y});
      }
      if (!any) continue;
      // A signed result that changes sign across the sweep (the largest excursion flips from
      // one side to the other): joining the signed values would draw a swing that no task had.
      // Its size is drawn instead, and the tasks where it was negative are marked.
      const bool sign_changes = positive && negative;
      plot::Series negatives;
      negatives.label = "negative in these tasks (size drawn)";
      negatives.style = plot::Style::kPoints;
      negatives.color = plot::color::kBlack;
      negatives.point_size = 1.2;
      if (sign_changes) {
        panel.title += ": size (its sign changes across the sweep)";
        panel.y_label = "size of " + panel.y_label;
      }
      std::size_t shown = 0;
      for (auto& [label, points] : groups) {
        if (++shown > 12) break;  // a legend beyond a dozen curves is unreadable
        std::sort(points.begin(), points.end());
        plot::Series series;
        series.label = label.empty() ? "all tasks" : label;
        series.style = plot::Style::kLinesPoints;
        for (const auto& [px, py] : points) {
          series.x.push_back(px);
          series.y.push_back(sign_changes ? std::abs(py) : py);
          if (sign_changes && py < 0.0) {
            negatives.x.push_back(px);
            negatives.y.push_back(-py);
          }
        }
        panel.series.push_back(series);
      }
      if (sign_changes) panel.series.push_back(negatives);
      figure.panels.push_back(panel);
    }
    if (figure.panels.empty()) continue;
    const fs::path stem = manifest.dir / "plots" / FileStem(collection.variables[v]);
    fs::create_directories(stem.parent_path());
    plot::WriteFigure(stem, figure);
    written.push_back(plot::FigureFilesFor(stem).png);
  }
  return written;
}

}  // namespace pwsim::report
