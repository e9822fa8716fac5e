#include "render/textures.h"

#include <algorithm>
#include <cmath>

namespace pwsim::render {
namespace {

/// A small deterministic generator (xorshift32); never the global RNG.
class Xorshift {
 public:
  explicit Xorshift(std::uint32_t seed) : state_(seed == 0 ? 0x9E3779B9U : seed) {}
  std::uint32_t Next() {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 17;
    state_ ^= state_ << 5;
    return state_;
  }
  double Uniform() { return (Next() >> 8) * (1.0 / 16777216.0); }  ///< [0, 1)
 private:
  std::uint32_t state_;
};

/// Tileable value noise on a `cells`×`cells` lattice, smoothly interpolated, in [0, 1].
std::vector<double> ValueNoise(int size, int cells, Xorshift& rng) {
  std::vector<double> lattice(static_cast<std::size_t>(cells * cells));
  for (double& v : lattice) v = rng.Uniform();
  std::vector<double> out(static_cast<std::size_t>(size * size));
  for (int row = 0; row < size; ++row) {
    for (int col = 0; col < size; ++col) {
      const double u = static_cast<double>(col) * cells / size;
      const double v = static_cast<double>(row) * cells / size;
      const int i0 = static_cast<int>(u), j0 = static_cast<int>(v);
      const int i1 = (i0 + 1) % cells, j1 = (j0 + 1) % cells;
      auto smooth = [](double t) { return t * t * (3.0 - 2.0 * t); };
      const double fu = smooth(u - i0), fv = smooth(v - j0);
      auto at = [&](int i, int j) { return lattice[static_cast<std::size_t>(j * cells + i)]; };
      const double top = at(i0, j0) + (at(i1, j0) - at(i0, j0)) * fu;
      const double bottom = at(i0, j1) + (at(i1, j1) - at(i0, j1)) * fu;
      out[static_cast<std::size_t>(row * size + col)] = top + (bottom - top) * fv;
    }
  }
  return out;
}

std::uint8_t ToByte(double value) {
  return static_cast<std::uint8_t>(std::clamp(value, 0.0, 1.0) * 255.0 + 0.5);
}

}  // namespace

TextureImage MakeTexture(TextureKind kind, std::uint32_t seed, int size) {
  TextureImage image;
  if (kind == TextureKind::kNone) return image;
  image.size = size;
  image.rgb.resize(static_cast<std::size_t>(size * size * 3));
  Xorshift rng(seed * 2654435761U + static_cast<std::uint32_t>(kind) * 40503U);
  // Two octaves of noise for blotches, plus kind-specific structure (tile grout, panel seams,
  // speckles) that gives sharp corners at several scales.
  const std::vector<double> coarse = ValueNoise(size, 8, rng);
  const std::vector<double> fine = ValueNoise(size, 32, rng);
  std::vector<double> speckle(static_cast<std::size_t>(size * size), 0.0);
  const int speckles = size * size / 150;
  for (int s = 0; s < speckles; ++s) {
    const int r = static_cast<int>(rng.Uniform() * size),
              c = static_cast<int>(rng.Uniform() * size);
    const double value = rng.Uniform() < 0.5 ? -0.35 : 0.35;
    for (int dr = 0; dr < 2; ++dr) {
      for (int dc = 0; dc < 2; ++dc) {
        speckle[static_cast<std::size_t>(((r + dr) % size) * size + (c + dc) % size)] = value;
      }
    }
  }
  for (int row = 0; row < size; ++row) {
    for (int col = 0; col < size; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * size + col);
      double base = 0.55 + 0.30 * (coarse[i] - 0.5) + 0.25 * (fine[i] - 0.5) + speckle[i];
      double tint_r = 1.0, tint_g = 1.0, tint_b = 1.0;
      switch (kind) {
        case TextureKind::kFloor:  // tiles with grout lines every quarter texture
          if (row % (size / 4) < 3 || col % (size / 4) < 3) base *= 0.45;
          tint_r = 1.0, tint_g = 0.95, tint_b = 0.88;
          break;
        case TextureKind::kWall:  // panels with a seam and a darker skirting band
          if (col % (size / 2) < 2) base *= 0.55;
          if (row > size * 7 / 8) base *= 0.6;
          tint_r = 0.95, tint_g = 0.97, tint_b = 1.0;
          break;
        case TextureKind::kCeiling:
          if (row % (size / 2) < 2 || col % (size / 2) < 2) base *= 0.7;
          break;
        case TextureKind::kCushion:  // warning chevrons
          if (((row + col) / (size / 8)) % 2 == 0) base = 0.25 + 0.2 * fine[i];
          tint_r = 1.0, tint_g = 0.85, tint_b = 0.3;
          break;
        case TextureKind::kNone:
          break;
      }
      image.rgb[3 * i + 0] = ToByte(base * tint_r);
      image.rgb[3 * i + 1] = ToByte(base * tint_g);
      image.rgb[3 * i + 2] = ToByte(base * tint_b);
    }
  }
  return image;
}

}  // namespace pwsim::render
