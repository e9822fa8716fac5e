#pragma once
// Report-quality figures drawn by gnuplot (Debian `gnuplot-nox`): stacked panels sharing one x
// axis, line/point series or box plots, linear or logarithmic axes. gnuplot picks round tick
// values; the key sits outside the plot area so it never covers or loses a curve.
//
// One call writes four files next to each other, each under a temporary name first and then
// renamed, so a failed call never leaves a half-written figure that looks complete:
//   STEM.png   pngcairo, for reports
//   STEM.svg   svg, for papers
//   STEM.plot.csv  the plotted data in long form: panel,series,x,y (one row per point)
//   STEM.gp        the gnuplot script that drew both images, reading STEM.plot.dat (the same
//                  data in gnuplot's block format): rerun `gnuplot STEM.gp` to restyle a figure
// (".plot.csv", so a figure never overwrites a command's own STEM.csv table.)
//
//   plot::Figure fig{.x_label = "t [s]"};
//   fig.panels.push_back({.title = "heave", .y_label = "a_z [m/s^2]",
//                         .series = {{"vehicle", t, y1}, {"platform", t, y2}}});
//   plot::WriteFigure("out/mca", fig);   // out/mca.png, .svg, .plot.csv, .gp
//
// Labels are printed literally (no gnuplot "enhanced text" markup), so `a_z` stays `a_z`.

#include <filesystem>
#include <string>
#include <vector>

namespace pwsim::plot {

enum class Style { kLines, kPoints, kLinesPoints, kSteps };

/// The palette every figure draws from (Okabe & Ito 2008, safe for colour-blind readers), and
/// the roles that keep one meaning across figures: the vehicle (what the occupant would feel in
/// the real chair or car) always blue, the platform always vermillion, tilt coordination orange.
namespace color {
inline constexpr unsigned kBlue = 0x0072B2, kVermillion = 0xD55E00, kGreen = 0x009E73,
                          kPurple = 0xCC79A7, kOrange = 0xE69F00, kSkyBlue = 0x56B4E9,
                          kBlack = 0x111111, kGrey = 0x777777;  // (0 means "the next colour")
inline constexpr unsigned kVehicle = kBlue, kPlatform = kVermillion, kTilt = kOrange;
/// A simulation checked against a closed form or a measurement: the simulation blue, the
/// reference vermillion.
inline constexpr unsigned kSimulated = kBlue, kReference = kVermillion;
}  // namespace color

struct Series {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;  ///< same length as x; a non-finite y leaves a gap in the curve
  Style style{Style::kLines};
  unsigned color{0};  ///< 0xRRGGBB; 0 = the next colour of the palette
  /// gnuplot dash type (0 or 1: solid; 2: dashed, 3: dotted, 4: dash-dot), so that a curve drawn
  /// over an equal one leaves it visible. Points take a different shape per series (filled
  /// circle, square, triangle, diamond, ...), for the same reason.
  int dash{0};
  double point_size{0.0};  ///< of points, in gnuplot's units; 0: 0.6
};

/// One box of a box plot: the box spans the quartiles, the whiskers reach the most extreme
/// values within 1.5 IQR, points beyond are drawn as outliers (gnuplot's `boxplot` style,
/// Tukey's convention, as R's boxplot()).
struct BoxGroup {
  std::string label;  ///< the category name under the box
  std::vector<double> values;
};

struct Panel {
  std::string title;
  std::string y_label;  ///< with its unit, e.g. "pitch [deg]"
  std::vector<Series> series;
  std::vector<BoxGroup> boxes;  ///< if non-empty, the panel is a box plot (series ignored)
  bool log_y{false};
  /// Fixed y range when y_min < y_max. Otherwise autoscaled with 5 % of the height free above
  /// and below the data, so that no peak touches the frame (values starting from zero keep zero
  /// as the axis' end on that side); a linear axis whose values all share
  /// one sign and span less than 5 % of their size says so in the panel title (the axis magnifies
  /// a small change).
  double y_min{0.0}, y_max{0.0};
  /// Spacing of the y tics, e.g. 1 for a gear or a count; 0: gnuplot's choice.
  double y_tic_step{0.0};
  /// Box plots: whiskers reach the smallest and largest values (no outliers drawn), as a
  /// "median, quartiles and extremes" figure, instead of Tukey's 1.5 IQR.
  bool box_whiskers_to_extremes{false};
  /// Box plots: every value drawn as a point over its box (jittered where values repeat).
  bool box_show_points{false};
  /// One metre is as long on x as on y (a map, e.g. a top view of a path).
  bool equal_axes{false};
};

struct Figure {
  std::string title;
  std::string x_label;  ///< with its unit, e.g. "t [s]"
  bool log_x{false};
  /// Fixed x range when x_min < x_max (e.g. counted attempts 1..n with half a step free on each
  /// side, which autoscale would spread over 0.99-1.01 for a single one); else autoscaled.
  /// Integer tics when x_integer_tics.
  double x_min{0.0}, x_max{0.0};
  bool x_integer_tics{false};
  std::vector<Panel> panels;
  int width_px{1100};
  int panel_height_px{320};
};

/// Writes STEM.png, STEM.svg, STEM.plot.csv, STEM.plot.dat and STEM.gp (STEM may carry a ".png" extension, which
/// is dropped). @throws std::runtime_error naming the file or the failing gnuplot command.
/// @throws std::invalid_argument if a series has x and y of different lengths or the figure
/// has no panel (a bug in the caller).
void WriteFigure(const std::filesystem::path& stem, const Figure& figure);

/// The common case: every series of every panel over one shared x.
struct SharedXSeries {
  std::string label;
  std::vector<double> y;
  unsigned color{0};
};
struct SharedXPanel {
  std::string title;
  std::string y_label;
  std::vector<SharedXSeries> series;
};
void WriteSharedXFigure(const std::filesystem::path& stem, const std::vector<double>& x,
                        const std::vector<SharedXPanel>& panels,
                        const std::string& x_label = "time [s]", int width_px = 1100,
                        int panel_height_px = 300, const std::string& title = "");

/// The paths WriteFigure writes for `stem`.
struct FigureFiles {
  std::filesystem::path png, svg, csv, gp;
};
FigureFiles FigureFilesFor(const std::filesystem::path& stem);

/// True when a `gnuplot` executable is on PATH.
bool GnuplotAvailable();

}  // namespace pwsim::plot
