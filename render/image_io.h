#pragma once
// Images in and out of render/: PNG files and the pixel comparison used by golden-image tests.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "render/offscreen_renderer.h"

namespace pwsim::render {

/// An owned BGRA8 image.
struct Image {
  int width{0};
  int height{0};
  std::vector<std::uint8_t> bgra;  ///< width * height * 4, row 0 at the top

  ImageView view() const { return ImageView{bgra.data(), width, height}; }
};

Image CopyImage(const ImageView& view);
/// Writes a PNG (BGR, alpha dropped). @throws std::runtime_error naming the file.
void WritePng(const std::filesystem::path& file, const ImageView& image);
/// Reads a PNG as BGRA. @throws std::runtime_error naming the file.
Image ReadPng(const std::filesystem::path& file);

/// Per-channel absolute difference over B, G, R (alpha ignored).
struct PixelDelta {
  int max{0};        ///< [0, 255] largest channel difference
  double mean{0.0};  ///< [0, 255] mean channel difference
  bool same_size{true};
};
PixelDelta ComparePixels(const ImageView& a, const ImageView& b);

}  // namespace pwsim::render
