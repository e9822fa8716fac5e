#include "render/image_io.h"

#include <algorithm>
#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace pwsim::render {
namespace {

cv::Mat Wrap(const ImageView& image) {
  return cv::Mat(image.height, image.width, CV_8UC4, const_cast<std::uint8_t*>(image.bgra));
}

}  // namespace

Image CopyImage(const ImageView& view) {
  Image out{view.width, view.height, {}};
  out.bgra.assign(view.bgra, view.bgra + static_cast<std::size_t>(view.width) * view.height * 4);
  return out;
}

void WritePng(const std::filesystem::path& file, const ImageView& image) {
  cv::Mat bgr;
  cv::cvtColor(Wrap(image), bgr, cv::COLOR_BGRA2BGR);
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  if (!cv::imwrite(file.string(), bgr)) {
    throw std::runtime_error("render: could not write PNG " + file.string());
  }
}

Image ReadPng(const std::filesystem::path& file) {
  const cv::Mat bgr = cv::imread(file.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) throw std::runtime_error("render: could not read PNG " + file.string());
  Image out{bgr.cols, bgr.rows, std::vector<std::uint8_t>(bgr.total() * 4)};
  cv::Mat bgra(bgr.rows, bgr.cols, CV_8UC4, out.bgra.data());
  cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
  return out;
}

PixelDelta ComparePixels(const ImageView& a, const ImageView& b) {
  PixelDelta delta;
  if (a.width != b.width || a.height != b.height) {
    delta.same_size = false;
    delta.max = 255;
    delta.mean = 255.0;
    return delta;
  }
  const std::size_t pixels = static_cast<std::size_t>(a.width) * a.height;
  double sum = 0.0;
  for (std::size_t i = 0; i < pixels; ++i) {
    for (std::size_t c = 0; c < 3; ++c) {
      const int d = std::abs(int{a.bgra[4 * i + c]} - int{b.bgra[4 * i + c]});
      delta.max = std::max(delta.max, d);
      sum += d;
    }
  }
  delta.mean = pixels > 0 ? sum / (3.0 * static_cast<double>(pixels)) : 0.0;
  return delta;
}

}  // namespace pwsim::render
