#include "render/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace pwsim::render {
namespace {

cv::Scalar Bgr(unsigned rgb) {
  return cv::Scalar((rgb >> 0) & 0xFF, (rgb >> 8) & 0xFF, (rgb >> 16) & 0xFF);
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

}  // namespace

void WritePlotPng(const std::filesystem::path& file, const std::vector<double>& x,
                  const std::vector<PlotPanel>& panels, int width, int panel_height) {
  const int height = panel_height * static_cast<int>(panels.size());
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 80, right = 20, top = 28, bottom = 36;
  const double x_min = x.empty() ? 0.0 : x.front(), x_max = x.empty() ? 1.0 : x.back();
  const cv::Scalar ink(40, 40, 40), grid(225, 225, 225);
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const PlotPanel& panel = panels[p];
    const int y0 = static_cast<int>(p) * panel_height;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const PlotSeries& s : panel.series) {
      for (double v : s.y) {
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
      }
    }
    if (!std::isfinite(lo)) lo = -1, hi = 1;
    if (hi - lo < 1e-12) lo -= 1e-6, hi += 1e-6;
    const double pad = 0.05 * (hi - lo);
    lo -= pad, hi += pad;
    const int plot_w = width - left - right, plot_h = panel_height - top - bottom;
    auto px = [&](double t) {
      return left + static_cast<int>(std::lround((t - x_min) / (x_max - x_min) * plot_w));
    };
    auto py = [&](double v) {
      return y0 + top + static_cast<int>(std::lround((hi - v) / (hi - lo) * plot_h));
    };
    for (int g = 0; g <= 4; ++g) {
      const double v = lo + (hi - lo) * g / 4.0;
      cv::line(image, {left, py(v)}, {left + plot_w, py(v)}, grid, 1);
      cv::putText(image, Number(v), {4, py(v) + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1,
                  cv::LINE_AA);
      const double t = x_min + (x_max - x_min) * g / 4.0;
      cv::putText(image, Number(t), {px(t) - 10, y0 + top + plot_h + 16}, cv::FONT_HERSHEY_SIMPLEX,
                  0.4, ink, 1, cv::LINE_AA);
    }
    cv::rectangle(image, {left, y0 + top}, {left + plot_w, y0 + top + plot_h}, ink, 1);
    cv::putText(image, panel.title + "  [" + panel.y_label + "]", {left, y0 + 18},
                cv::FONT_HERSHEY_SIMPLEX, 0.5, ink, 1, cv::LINE_AA);
    cv::putText(image, "t [s]", {left + plot_w - 30, y0 + panel_height - 6},
                cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1, cv::LINE_AA);
    for (std::size_t s = 0; s < panel.series.size(); ++s) {
      const PlotSeries& series = panel.series[s];
      const std::size_t n = std::min(series.y.size(), x.size());
      for (std::size_t k = 1; k < n; ++k) {
        if (!std::isfinite(series.y[k - 1]) || !std::isfinite(series.y[k])) continue;
        cv::line(image, {px(x[k - 1]), py(series.y[k - 1])}, {px(x[k]), py(series.y[k])},
                 Bgr(series.color), 2, cv::LINE_AA);
      }
      const int ly = y0 + top + 16 + 16 * static_cast<int>(s);
      cv::line(image, {left + plot_w - 360, ly - 4}, {left + plot_w - 335, ly - 4},
               Bgr(series.color), 2);
      cv::putText(image, series.label, {left + plot_w - 330, ly}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
                  ink, 1, cv::LINE_AA);
    }
  }
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  if (!cv::imwrite(file.string(), image)) {
    throw std::runtime_error("render: could not write plot " + file.string());
  }
}

}  // namespace pwsim::render
