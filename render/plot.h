#pragma once
// A small line-plot writer (PNG via OpenCV): stacked panels sharing one time axis, a legend per
// panel. Enough for the visual-check figure of `pwsim run`; not a plotting library.

#include <filesystem>
#include <string>
#include <vector>

namespace pwsim::render {

struct PlotSeries {
  std::string label;
  std::vector<double> y;     ///< same length as the panel's x; NaN leaves a gap
  unsigned color{0x1f77b4};  ///< 0xRRGGBB
};

struct PlotPanel {
  std::string title;
  std::string y_label;
  std::vector<PlotSeries> series;
};

/// Writes panels stacked vertically, `x` [s] shared. @throws std::runtime_error on write error.
void WritePlotPng(const std::filesystem::path& file, const std::vector<double>& x,
                  const std::vector<PlotPanel>& panels, int width = 1000, int panel_height = 300);

}  // namespace pwsim::render
