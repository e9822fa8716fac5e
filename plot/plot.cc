#include "plot/plot.h"

#include <spawn.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "engine/atomic_file.h"
#include "engine/number_format.h"

extern char** environ;

namespace pwsim::plot {
namespace {

namespace fs = std::filesystem;

// A colour-blind-safe palette (Okabe & Ito, 2008), then gnuplot's defaults.
constexpr unsigned kPalette[] = {0x0072B2, 0xD55E00, 0x009E73, 0xCC79A7,
                                 0xE69F00, 0x56B4E9, 0x000000, 0xF0E442};

// gnuplot string literal in single quotes: only the quote itself needs doubling.
std::string Quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += "''";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out + "'";
}

std::string Hex(unsigned rgb) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%06X", rgb & 0xFFFFFFu);
  return buf;
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

void Validate(const Figure& figure) {
  if (figure.panels.empty()) throw std::invalid_argument("plot: a figure needs at least one panel");
  for (const Panel& panel : figure.panels)
    for (const Series& s : panel.series)
      if (s.x.size() != s.y.size())
        throw std::invalid_argument("plot: series '" + s.label + "' has " +
                                    std::to_string(s.x.size()) + " x values and " +
                                    std::to_string(s.y.size()) + " y values");
}

// The data file: one gnuplot dataset (separated by two blank lines) per series or box, in
// figure order, so `index k` addresses the k-th. A non-finite y becomes one blank line: a gap.
std::string DataText(const Figure& figure) {
  std::ostringstream out;
  for (const Panel& panel : figure.panels) {
    if (!panel.boxes.empty()) {
      for (std::size_t b = 0; b < panel.boxes.size(); ++b) {
        for (double v : panel.boxes[b].values)
          if (std::isfinite(v)) out << (b + 1) << ' ' << FormatDouble(v) << '\n';
        out << "\n\n";
      }
      continue;
    }
    for (const Series& s : panel.series) {
      bool any = false;
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
          out << '\n';
          continue;
        }
        out << FormatDouble(s.x[i]) << ' ' << FormatDouble(s.y[i]) << '\n';
        any = true;
      }
      // gnuplot refuses an empty dataset; an undefined point keeps the index numbering.
      if (!any) out << "0 NaN\n";
      out << "\n\n";
    }
  }
  return out.str();
}

std::string CsvText(const Figure& figure) {
  std::ostringstream out;
  out << "panel,series,x,y\n";
  for (const Panel& panel : figure.panels) {
    const std::string p = CsvField(panel.title);
    if (!panel.boxes.empty()) {
      for (const BoxGroup& box : panel.boxes)
        for (double v : box.values) out << p << ',' << CsvField(box.label) << ",," << FormatDouble(v) << '\n';
      continue;
    }
    for (const Series& s : panel.series)
      for (std::size_t i = 0; i < s.x.size(); ++i)
        out << p << ',' << CsvField(s.label) << ',' << FormatDouble(s.x[i]) << ','
            << FormatDouble(s.y[i]) << '\n';
  }
  return out.str();
}

// Filled circle, square, triangle, diamond, down-triangle, then the open ones: series of one
// panel drawn with points never share a shape, so one over another stays visible.
constexpr int kPointTypes[] = {7, 5, 9, 13, 11, 6, 4, 8, 12, 10};

std::string StyleText(const Series& series, std::size_t index) {
  const int pt = kPointTypes[index % std::size(kPointTypes)];
  const std::string ps = " ps " + FormatDouble(series.point_size > 0.0 ? series.point_size : 0.6);
  std::string text;
  switch (series.style) {
    case Style::kPoints: text = "points pt " + std::to_string(pt) + ps; break;
    case Style::kLinesPoints: text = "linespoints pt " + std::to_string(pt) + ps; break;
    case Style::kSteps: text = "steps"; break;
    case Style::kLines: text = "lines"; break;
  }
  if (series.dash > 1) text += " dt " + std::to_string(series.dash);
  return text;
}

// The finite y values' range of a panel's series; lo > hi when there is none.
std::pair<double, double> YRange(const Panel& panel) {
  double lo = INFINITY, hi = -INFINITY;
  for (const Series& s : panel.series)
    for (double y : s.y)
      if (std::isfinite(y)) lo = std::min(lo, y), hi = std::max(hi, y);
  return {lo, hi};
}

// " (y axis magnified: ...)" for a linear, autoscaled panel whose values all share one sign and
// span less than 5 % of their size, where the axis would make a small change fill the panel.
std::string MagnifiedNote(const Panel& panel) {
  if (panel.log_y || panel.y_min < panel.y_max || panel.equal_axes || !panel.boxes.empty()) return "";
  const auto [lo, hi] = YRange(panel);
  if (!(lo <= hi) || !(lo > 0.0 || hi < 0.0)) return "";
  const double size = std::max(std::abs(lo), std::abs(hi));
  const double share = (hi - lo) / size;
  if (share >= 0.05 || hi == lo) return "";
  char pct[32];
  std::snprintf(pct, sizeof pct, "%.2g", 100.0 * share);
  return std::string(" (y axis magnified: the values vary by only ") + pct + " %)";
}

// The y range of an autoscaled linear panel: 5 % of the height free above and below the data
// before gnuplot extends the range to the next tic, so that a peak never lies on the frame;
// except that values that start from zero on one side (a speed, a load, a count) keep zero as
// the axis' end there, rather than a negative tic no value reaches.
std::string AutoscaledYRange(const Panel& panel) {
  const auto [lo, hi] = YRange(panel);
  if (!panel.log_y && lo <= hi && hi > lo) {
    const double near = 0.05 * (hi - lo);
    if (lo >= 0.0 && lo <= near) return "set yrange [0:*]\nset offsets 0, 0, graph 0.05, 0\n";
    if (hi <= 0.0 && hi >= -near) return "set yrange [*:0]\nset offsets 0, 0, 0, graph 0.05\n";
  }
  return "set yrange [*:*]\nset offsets 0, 0, graph 0.05, graph 0.05\n";
}

// Where the key goes so that it never covers a curve nor leaves the image: outside, right of
// the plots when the longest label leaves the plots at least 60 % of the width (about 7 px per
// character of the 10 pt font, plus the sample line), else below them.
std::string KeyPlacement(const Figure& figure) {
  std::size_t longest = 0;
  for (const Panel& panel : figure.panels)
    for (const Series& s : panel.series) {
      std::size_t chars = 0;  // UTF-8 code points: "m/s²" is 4 characters
      for (char c : s.label) chars += (static_cast<unsigned char>(c) & 0xC0u) != 0x80u ? 1 : 0;
      longest = std::max(longest, chars);
    }
  const double key_px = 7.0 * static_cast<double>(longest) + 60.0;
  const double key_share = key_px / static_cast<double>(std::max(figure.width_px, 200));
  std::ostringstream gp;
  if (key_share <= 0.4) {
    const double right = std::clamp(1.0 - key_share, 0.6, 0.9);
    // The key's left edge just right of the plots (gnuplot would right-align it to the image
    // and, overestimating its width, push it over the plots).
    const double edge = std::round(right * 100.0) / 100.0;
    gp << "set key at screen " << FormatDouble(edge + 0.015)
       << ", graph 1 left top vertical Left reverse samplen 2 spacing 1.1\n"
       << "set rmargin at screen " << FormatDouble(edge) << "\n";
  } else {
    gp << "set key outside below center horizontal Left reverse samplen 2 spacing 1.1 maxcols 2\n"
       << "set rmargin 4\n";
  }
  return gp.str();
}

// The plotting commands, written once and replayed for each terminal.
std::string PlotBody(const Figure& figure, const std::string& data_file) {
  std::ostringstream gp;
  const std::size_t n = figure.panels.size();
  gp << "set termoption noenhanced\n"
     << "set datafile missing 'NaN'\n"
     << "set grid xtics ytics lc rgb '#DDDDDD' lw 1\n"
     << "set border lw 1\n"
     << KeyPlacement(figure) << "set lmargin 12\n";
  if (!figure.title.empty() || n > 1)
    gp << "set multiplot layout " << n << ",1 title " << Quote(figure.title) << "\n";
  std::size_t index = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const Panel& panel = figure.panels[p];
    gp << "unset logscale\nunset xtics\nunset ytics\nset xtics\nset ytics\nset autoscale\n";
    gp << "set title " << Quote(panel.title + MagnifiedNote(panel)) << "\n";
    gp << "set ylabel " << Quote(panel.y_label) << "\n";
    // A logarithmic axis labels its decades as numbers (0.001, 10), not in gnuplot's "% h".
    gp << (panel.log_y ? "set logscale y\nset format y '%g'\n" : "set format y '% h'\n");
    if (panel.y_min < panel.y_max)
      gp << "set yrange [" << FormatDouble(panel.y_min) << ":" << FormatDouble(panel.y_max) << "]\n"
         << "set offsets 0, 0, 0, 0\n";
    else if (!panel.boxes.empty() || panel.equal_axes)
      gp << "set yrange [*:*]\nset offsets 0, 0, 0, 0\n";
    else
      gp << AutoscaledYRange(panel);
    if (panel.y_tic_step > 0.0) gp << "set ytics " << FormatDouble(panel.y_tic_step) << "\n";
    if (!panel.boxes.empty()) {
      gp << (panel.box_show_points ? "set jitter overlap 0.5 spread 2.5 wrap 10\n" : "unset jitter\n");
      gp << "set xlabel ''\nset style data boxplot\n"
         << (panel.box_whiskers_to_extremes ? "set style boxplot fraction 1.0 nooutliers\n"
                                            : "set style boxplot range 1.5 outliers pointtype 7\n")
         << "set style fill solid 0.35 border -1\n"
         << "set boxwidth 0.5\nset xrange [0.4:" << panel.boxes.size() << ".6]\n"
         << "set xtics (";
      for (std::size_t b = 0; b < panel.boxes.size(); ++b)
        gp << (b ? ", " : "") << Quote(panel.boxes[b].label) << " " << b + 1;
      gp << ") scale 0\nset key off\nplot ";
      for (std::size_t b = 0; b < panel.boxes.size(); ++b, ++index) {
        const unsigned color = kPalette[b % std::size(kPalette)];
        gp << (b ? ", \\\n     " : "") << Quote(data_file) << " index " << index
           << " using (" << b + 1 << "):2 with boxplot lc rgb '" << Hex(color) << "' notitle";
      }
      if (panel.box_show_points) {
        for (std::size_t b = 0; b < panel.boxes.size(); ++b)
          gp << ", \\\n     " << Quote(data_file) << " index " << index - panel.boxes.size() + b
             << " using (" << b + 1 << "):2 with points pt 7 ps 0.9 lc rgb '#333333' notitle";
      }
      gp << "\nset key\nunset style data\nset style fill empty\n";
      continue;
    }
    if (figure.x_min < figure.x_max)
      gp << "set xrange [" << figure.x_min << ":" << figure.x_max << "]\n";
    else
      gp << "set xrange [*:*]\n";
    if (figure.x_integer_tics) gp << "set xtics 1\nset format x '%.0f'\n";
    if (figure.log_x) gp << "set logscale x\n";
    gp << "set xlabel " << Quote(p + 1 == n ? figure.x_label : std::string()) << "\n";
    if (panel.equal_axes) gp << "set size ratio -1\n";
    gp << "plot ";
    for (std::size_t s = 0; s < panel.series.size(); ++s, ++index) {
      const Series& series = panel.series[s];
      const unsigned color = series.color ? series.color : kPalette[s % std::size(kPalette)];
      gp << (s ? ", \\\n     " : "") << Quote(data_file) << " index " << index
         << " using 1:2 with " << StyleText(series, s) << " lw 1.5 lc rgb '" << Hex(color)
         << "' title " << Quote(series.label);
    }
    if (panel.series.empty()) gp << "NaN notitle";
    gp << "\n";
    if (panel.equal_axes) gp << "set size noratio\n";
  }
  if (!figure.title.empty() || n > 1) gp << "unset multiplot\n";
  return gp.str();
}

int RunGnuplot(const fs::path& script, const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string log_name = log.string();
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_name.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  const std::string script_name = script.string();
  std::string prog = "gnuplot";
  char* argv[] = {prog.data(), const_cast<char*>(script_name.c_str()), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string ReadAll(const fs::path& file) {
  std::ifstream in(file);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

FigureFiles FigureFilesFor(const fs::path& stem_in) {
  fs::path stem = stem_in;
  if (stem.extension() == ".png" || stem.extension() == ".svg") stem.replace_extension();
  const std::string base = stem.string();
  return {base + ".png", base + ".svg", base + ".plot.csv", base + ".gp"};
}

bool GnuplotAvailable() {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':'))
    if (!dir.empty() && access((fs::path(dir) / "gnuplot").c_str(), X_OK) == 0) return true;
  return false;
}

void WriteFigure(const fs::path& stem, const Figure& figure) {
  Validate(figure);
  const FigureFiles files = FigureFilesFor(stem);
  if (!files.png.parent_path().empty()) fs::create_directories(files.png.parent_path());
  // Old outputs go first: a failure below must not leave a previous figure looking current.
  for (const fs::path& f : {files.png, files.svg, files.csv, files.gp}) fs::remove(f);

  // The data file is named relative to the script, so the .gp replays from its folder.
  const fs::path data = fs::path(files.csv).replace_extension(".dat");  // STEM.plot.dat
  const std::string data_name = data.filename().string();
  const std::string body = PlotBody(figure, data_name);
  const int height = figure.panel_height_px * static_cast<int>(figure.panels.size()) +
                     (figure.title.empty() ? 0 : 40);
  const std::string png_part = files.png.filename().string() + ".partial";
  const std::string svg_part = files.svg.filename().string() + ".partial";
  std::ostringstream script;
  script << "# Drawn by pwsim (plot/plot.cc); data in " << data_name << " (also "
         << files.csv.filename().string() << ").\n"
         << "set terminal pngcairo size " << figure.width_px << "," << height
         << " font 'DejaVu Sans,10' linewidth 1 noenhanced\n"
         << "set output " << Quote(png_part) << "\n"
         << body << "unset output\n"
         << "reset\n"
         << "set terminal svg size " << figure.width_px << "," << height
         << " font 'DejaVu Sans,10' noenhanced\n"
         << "set output " << Quote(svg_part) << "\n"
         << body << "unset output\n";

  // gnuplot runs in the output folder so the script's relative names resolve.
  const fs::path dir = files.png.parent_path().empty() ? fs::path(".") : files.png.parent_path();
  WriteFileAtomically(data, DataText(figure));
  const fs::path gp_partial = dir / (files.gp.filename().string() + ".run");
  {
    std::ofstream out(gp_partial);
    out << "cd " << Quote(fs::absolute(dir).string()) << "\n" << script.str();
    if (!out) throw std::runtime_error(gp_partial.string() + ": cannot write the gnuplot script");
  }
  const fs::path log = dir / (files.gp.filename().string() + ".log");
  const int rc = RunGnuplot(gp_partial, log);
  const std::string messages = ReadAll(log);
  fs::remove(log);
  fs::remove(gp_partial);
  if (rc != 0) {
    fs::remove(dir / png_part);
    fs::remove(dir / svg_part);
    fs::remove(data);
    if (rc < 0)
      throw std::runtime_error(files.png.string() +
                               ": cannot run gnuplot (install Debian package gnuplot-nox)");
    throw std::runtime_error(files.png.string() + ": gnuplot exited with status " +
                             std::to_string(rc) + ": " + messages);
  }
  fs::rename(dir / png_part, files.png);
  fs::rename(dir / svg_part, files.svg);
  // The kept script names the final files, so rerunning it redraws them in place.
  std::string kept = script.str();
  for (const auto& [from, to] : {std::pair{png_part, files.png.filename().string()},
                                 std::pair{svg_part, files.svg.filename().string()}}) {
    const std::string quoted = Quote(from);
    if (auto at = kept.find(quoted); at != std::string::npos)
      kept.replace(at, quoted.size(), Quote(to));
  }
  WriteFileAtomically(files.gp, kept);
  WriteFileAtomically(files.csv, CsvText(figure));
}

void WriteSharedXFigure(const fs::path& stem, const std::vector<double>& x,
                        const std::vector<SharedXPanel>& panels, const std::string& x_label,
                        int width_px, int panel_height_px, const std::string& title) {
  Figure figure;
  figure.title = title;
  figure.x_label = x_label;
  figure.width_px = width_px;
  figure.panel_height_px = panel_height_px;
  for (const SharedXPanel& in : panels) {
    Panel& panel = figure.panels.emplace_back();
    panel.title = in.title;
    panel.y_label = in.y_label;
    for (const SharedXSeries& s : in.series) {
      Series& series = panel.series.emplace_back();
      series.label = s.label;
      series.x = x;
      series.y = s.y;
      series.color = s.color;
    }
  }
  WriteFigure(stem, figure);
}

}  // namespace pwsim::plot
