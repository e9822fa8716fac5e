#include "render/dashboard.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace pwsim::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

cv::Point At(cv::Point centre, double radius, double angle) {
  return {centre.x + static_cast<int>(std::lround(radius * std::cos(angle))),
          centre.y - static_cast<int>(std::lround(radius * std::sin(angle)))};
}

void Gauge(cv::Mat& m, cv::Point c, int r, double value, double full, double red_from, double major,
           const std::string& label, double scale_label) {
  cv::circle(m, c, r + 4, cv::Scalar(40, 40, 40, 255), cv::FILLED, cv::LINE_AA);
  cv::circle(m, c, r + 4, cv::Scalar(170, 170, 170, 255), 2, cv::LINE_AA);
  for (double v = 0.0; v <= full + 1e-9; v += major / 2.0) {
    const bool is_major = std::fmod(v + 1e-9, major) < 1e-6;
    const double a = GaugeAngle(v, full);
    const cv::Scalar colour = v >= red_from ? cv::Scalar(40, 40, 230, 255) : cv::Scalar(235, 235, 235, 255);
    cv::line(m, At(c, r * (is_major ? 0.78 : 0.86), a), At(c, r * 0.95, a), colour, is_major ? 2 : 1, cv::LINE_AA);
    if (is_major) {
      const std::string text = std::to_string(static_cast<int>(std::lround(v / scale_label)));
      const double fs = std::max(0.3, r / 120.0);
      int base = 0;
      const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, fs, 1, &base);
      const cv::Point p = At(c, r * 0.62, a);
      cv::putText(m, text, {p.x - size.width / 2, p.y + size.height / 2}, cv::FONT_HERSHEY_SIMPLEX, fs,
                  cv::Scalar(235, 235, 235, 255), 1, cv::LINE_AA);
    }
  }
  const double a = GaugeAngle(std::clamp(value, 0.0, full), full);
  cv::line(m, c, At(c, r * 0.9, a), cv::Scalar(30, 120, 255, 255), 3, cv::LINE_AA);
  cv::circle(m, c, std::max(3, r / 12), cv::Scalar(200, 200, 200, 255), cv::FILLED, cv::LINE_AA);
  const double fs = std::max(0.3, r / 140.0);
  int base = 0;
  const cv::Size size = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, fs, 1, &base);
  cv::putText(m, label, {c.x - size.width / 2, c.y + static_cast<int>(0.8 * r)}, cv::FONT_HERSHEY_SIMPLEX, fs,
              cv::Scalar(200, 200, 200, 255), 1, cv::LINE_AA);
}

}  // namespace

double GaugeAngle(double value, double full_scale) {
  const double start = 225.0 * kPi / 180.0;
  const double sweep = 270.0 * kPi / 180.0;
  return start - sweep * value / full_scale;
}

void DrawDashboard(Image& image, const DashboardReading& reading) {
  if (image.width <= 0 || image.height <= 0) return;
  cv::Mat m(image.height, image.width, CV_8UC4, image.bgra.data());
  const int r = std::max(20, image.height / 9);
  const int cy = image.height - r - 12;
  const cv::Point rev(image.width / 2 - 2 * r - 20, cy);
  const cv::Point speed(image.width / 2 + 2 * r + 20, cy);
  Gauge(m, rev, r, reading.engine_rpm, 8000.0, reading.redline_rpm, 1000.0, "x1000 rpm", 1000.0);
  Gauge(m, speed, r, reading.speed_kmh, 200.0, 1e9, 20.0, "km/h", 1.0);
  // gear box between the two gauges
  const int box = r;
  const cv::Rect rect(image.width / 2 - box / 2, cy - box / 2, box, box);
  cv::rectangle(m, rect, cv::Scalar(40, 40, 40, 255), cv::FILLED);
  cv::rectangle(m, rect, cv::Scalar(170, 170, 170, 255), 2);
  const std::string gear = reading.gear < 0 ? "R" : reading.gear == 0 ? "N" : std::to_string(reading.gear);
  const double fs = box / 32.0;
  int base = 0;
  const cv::Size size = cv::getTextSize(gear, cv::FONT_HERSHEY_SIMPLEX, fs, 2, &base);
  cv::putText(m, gear, {rect.x + (box - size.width) / 2, rect.y + (box + size.height) / 2}, cv::FONT_HERSHEY_SIMPLEX,
              fs, cv::Scalar(80, 230, 120, 255), 2, cv::LINE_AA);
  if (!reading.engine_running) {
    cv::circle(m, {rect.x + box / 2, rect.y - box / 3}, std::max(4, box / 8), cv::Scalar(30, 30, 235, 255), cv::FILLED,
               cv::LINE_AA);
  }
}

}  // namespace pwsim::render
