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
    plot::Figure figure;
    figure.title = "sweep " + manifest.name + ": fields against " + collection.variables[v];
    figure.x_label = collection.variables[v];
    for (std::size_t f = 0; f < collection.field_names.size(); ++f) {
      plot::Panel panel;
      panel.title = collection.field_names[f];
      panel.y_label = collection.field_names[f];
      std::map<std::string, std::vector<std::pair<double, double>>> groups;
      bool any = false;
      for (std::size_t r = 0; r < collection.rows.size(); ++r) {
        std::string label;
        for (std::size_t o = 0; o < n_vars; ++o) {
          if (o == v) continue;
          const std::string& key = collection.variables[o];  // its last word keeps the legend short
          label += (label.empty() ? "" : ", ") + key.substr(key.rfind('.') + 1) + "=" + collection.rows[r].values[o];
        }
        const double y = collection.rows[r].numbers[f];
        any = any || std::isfinite(y);
        groups[label].push_back({(*x)[r], y});
      }
      if (!any) continue;
      std::size_t shown = 0;
      for (auto& [label, points] : groups) {
        if (++shown > 12) break;  // a legend beyond a dozen curves is unreadable
        std::sort(points.begin(), points.end());
        plot::Series series;
        series.label = label.empty() ? collection.field_names[f] : label;
        series.style = plot::Style::kLinesPoints;
        for (const auto& [px, py] : points) {
          series.x.push_back(px);
          series.y.push_back(py);
        }
        panel.series.push_back(series);
      }
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
