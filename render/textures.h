#pragma once
// Procedural textures: deterministic RGB images (own generator, fixed seed) with plenty of
// non-repeating corners, so optical flow can track the floor and walls of the rendered room.

#include <cstdint>
#include <vector>

#include "render/render_scene.h"

namespace pwsim::render {

struct TextureImage {
  int size{0};                    ///< [px] square edge
  std::vector<std::uint8_t> rgb;  ///< size * size * 3, row 0 first
};

/// The texture for `kind` (kNone gives an empty image). Same kind and seed, same bytes.
TextureImage MakeTexture(TextureKind kind, std::uint32_t seed, int size = 256);

}  // namespace pwsim::render
