#pragma once
// Line plots as PNG (OpenCV imgproc/imgcodecs): stacked panels sharing one x axis, linear or
// logarithmic (Bode plots), optional point markers, a legend per panel. Used for the MCA
// figures of `pwsim run` (mca.png), `pwsim omct` and `pwsim mca-validate`.
//
//   PngFigure fig{.x_label = "t [s]"};
//   fig.panels.push_back({"heave", "m/s^2", {{"vehicle", t, y1}, {"platform", t, y2}}});
//   WriteFigurePng("out/mca.png", fig);

#include <filesystem>
#include <string>
#include <vector>

namespace pwsim::app {

struct PngSeries {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;       ///< same length as x; non-finite values leave a gap
  unsigned color{0};           ///< 0xRRGGBB; 0 = next colour of the palette
  bool markers{false};         ///< draw a dot at each point
};

struct PngPanel {
  std::string title;
  std::string y_label;
  std::vector<PngSeries> series;
  bool log_y{false};
};

struct PngFigure {
  std::string title;
  std::string x_label;
  bool log_x{false};
  std::vector<PngPanel> panels;
  int width{1100};
  int panel_height{320};
};

/// @throws std::runtime_error naming the file when it cannot be written.
void WriteFigurePng(const std::filesystem::path& file, const PngFigure& figure);

/// The common case: every series of every panel over one shared x axis.
struct PlotSeries {
  std::string label;
  std::vector<double> y;  ///< same length as x; non-finite values leave a gap
  unsigned color{0};      ///< 0xRRGGBB; 0 = next colour of the palette
};

struct PlotPanel {
  std::string title;
  std::string y_label;
  std::vector<PlotSeries> series;
};

/// Panels stacked vertically over the shared `x`, labelled `x_label`.
void WritePlotPng(const std::filesystem::path& file, const std::vector<double>& x,
                  const std::vector<PlotPanel>& panels, const std::string& x_label = "t [s]",
                  int width = 1000, int panel_height = 300);

}  // namespace pwsim::app
