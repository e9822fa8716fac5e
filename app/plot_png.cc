#include "app/plot_png.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "engine/atomic_file.h"

namespace pwsim::app {
namespace {

constexpr std::array<unsigned, 10> kPalette{0x1f77b4, 0xd62728, 0x2ca02c, 0xff7f0e, 0x9467bd,
                                            0x8c564b, 0xe377c2, 0x7f7f7f, 0xbcbd22, 0x17becf};

cv::Scalar Bgr(unsigned rgb) {
  return cv::Scalar((rgb >> 0) & 0xFF, (rgb >> 8) & 0xFF, (rgb >> 16) & 0xFF);
}

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

/// Axis mapping, linear or log10.
struct Axis {
  double lo{0.0}, hi{1.0};
  bool log{false};
  double Map(double v) const { return log ? std::log10(v) : v; }
  bool Valid(double v) const { return std::isfinite(v) && (!log || v > 0.0); }
};

Axis Fit(const std::vector<const std::vector<double>*>& data, bool log) {
  Axis axis;
  axis.log = log;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto* values : data) {
    for (double v : *values) {
      if (!axis.Valid(v)) continue;
      lo = std::min(lo, axis.Map(v));
      hi = std::max(hi, axis.Map(v));
    }
  }
  if (!std::isfinite(lo)) lo = 0.0, hi = 1.0;
  if (hi - lo < 1e-12) lo -= 0.5 * std::max(1e-9, std::abs(lo)), hi += 0.5 * std::max(1e-9, std::abs(hi));
  axis.lo = lo;
  axis.hi = hi;
  return axis;
}

}  // namespace

void WriteFigurePng(const std::filesystem::path& file, const PngFigure& figure) {
  const int header = figure.title.empty() ? 0 : 30;
  const int height = header + figure.panel_height * static_cast<int>(figure.panels.size()) + 20;
  cv::Mat image(height, figure.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar ink(40, 40, 40), grid(228, 228, 228);
  const int left = 86, right = 24, top = 30, bottom = 44;
  const int plot_w = figure.width - left - right;
  const int plot_h = figure.panel_height - top - bottom;
  if (!figure.title.empty()) {
    cv::putText(image, figure.title, {left, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, ink, 1, cv::LINE_AA);
  }
  std::vector<const std::vector<double>*> xs;
  for (const PngPanel& panel : figure.panels) {
    for (const PngSeries& s : panel.series) xs.push_back(&s.x);
  }
  Axis x_axis = Fit(xs, figure.log_x);
  if (figure.log_x) x_axis.lo = std::floor(x_axis.lo * 5.0) / 5.0, x_axis.hi = std::ceil(x_axis.hi * 5.0) / 5.0;

  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const PngPanel& panel = figure.panels[p];
    const int y0 = header + static_cast<int>(p) * figure.panel_height;
    std::vector<const std::vector<double>*> ys;
    for (const PngSeries& s : panel.series) ys.push_back(&s.y);
    Axis y_axis = Fit(ys, panel.log_y);
    const double pad = 0.06 * (y_axis.hi - y_axis.lo);
    y_axis.lo -= pad;
    y_axis.hi += pad;
    auto px = [&](double x) {
      return left + static_cast<int>(std::lround((x_axis.Map(x) - x_axis.lo) / (x_axis.hi - x_axis.lo) * plot_w));
    };
    auto py = [&](double y) {
      return y0 + top + static_cast<int>(std::lround((y_axis.hi - y_axis.Map(y)) / (y_axis.hi - y_axis.lo) * plot_h));
    };
    // grid and tick labels
    for (int g = 0; g <= 4; ++g) {
      const double m = y_axis.lo + (y_axis.hi - y_axis.lo) * g / 4.0;
      const double v = y_axis.log ? std::pow(10.0, m) : m;
      cv::line(image, {left, py(v)}, {left + plot_w, py(v)}, grid, 1);
      cv::putText(image, Number(v), {4, py(v) + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1, cv::LINE_AA);
    }
    const int x_ticks = figure.log_x ? static_cast<int>(std::lround((x_axis.hi - x_axis.lo) * 5.0)) : 5;
    for (int g = 0; g <= x_ticks; ++g) {
      const double m = x_axis.lo + (x_axis.hi - x_axis.lo) * g / std::max(1, x_ticks);
      const double v = figure.log_x ? std::pow(10.0, m) : m;
      cv::line(image, {px(v), y0 + top}, {px(v), y0 + top + plot_h}, grid, 1);
      cv::putText(image, Number(v), {px(v) - 14, y0 + top + plot_h + 16}, cv::FONT_HERSHEY_SIMPLEX, 0.38,
                  ink, 1, cv::LINE_AA);
    }
    cv::rectangle(image, {left, y0 + top}, {left + plot_w, y0 + top + plot_h}, ink, 1);
    cv::putText(image, panel.title + (panel.y_label.empty() ? "" : "  [" + panel.y_label + "]"),
                {left, y0 + top - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.5, ink, 1, cv::LINE_AA);
    if (p + 1 == figure.panels.size() && !figure.x_label.empty()) {
      cv::putText(image, figure.x_label, {left + plot_w / 2 - 30, y0 + top + plot_h + 36},
                  cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1, cv::LINE_AA);
    }
    // series, clipped to the plot box
    const cv::Rect clip(left, y0 + top, plot_w + 1, plot_h + 1);
    cv::Mat roi = image(clip);
    for (std::size_t s = 0; s < panel.series.size(); ++s) {
      const PngSeries& series = panel.series[s];
      const cv::Scalar color = Bgr(series.color != 0 ? series.color : kPalette[s % kPalette.size()]);
      const std::size_t n = std::min(series.x.size(), series.y.size());
      bool have_prev = false;
      cv::Point prev;
      for (std::size_t i = 0; i < n; ++i) {
        if (!x_axis.Valid(series.x[i]) || !y_axis.Valid(series.y[i])) {
          have_prev = false;
          continue;
        }
        const cv::Point point(px(series.x[i]) - left, py(series.y[i]) - (y0 + top));
        if (have_prev) cv::line(roi, prev, point, color, 1, cv::LINE_AA);
        if (series.markers) cv::circle(roi, point, 3, color, cv::FILLED, cv::LINE_AA);
        prev = point;
        have_prev = true;
      }
      // legend entry
      const int ly = y0 + top + 14 + 16 * static_cast<int>(s);
      cv::line(image, {left + plot_w - 170, ly - 4}, {left + plot_w - 150, ly - 4}, color, 2);
      cv::putText(image, series.label, {left + plot_w - 145, ly}, cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1,
                  cv::LINE_AA);
    }
  }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) {
    throw std::runtime_error("cannot encode PNG for " + file.string());
  }
  WriteFileAtomically(file, std::string(png.begin(), png.end()));
}

void WritePlotPng(const std::filesystem::path& file, const std::vector<double>& x,
                  const std::vector<PlotPanel>& panels, const std::string& x_label, int width,
                  int panel_height) {
  PngFigure figure;
  figure.x_label = x_label;
  figure.width = width;
  figure.panel_height = panel_height;
  for (const PlotPanel& panel : panels) {
    PngPanel png{panel.title, panel.y_label, {}, false};
    for (const PlotSeries& series : panel.series) {
      png.series.push_back({series.label, x, series.y, series.color, false});
    }
    figure.panels.push_back(std::move(png));
  }
  WriteFigurePng(file, figure);
}

}  // namespace pwsim::app
