#pragma once
// RenderConfig: how a trial is rendered (image size, frame rate, field of view, stereo HMD
// eyes, clip planes, textures), read from the scene file's top-level `render:` section.
// Every field is optional in the file; the defaults below apply.
//
//   render:
//     size: [1280, 720]     # mono image [px]
//     fps: 50               # must divide the clock rate (frame k = tick k·N)
//     fov_y_deg: 60
//     anisotropy: 1         # texture anisotropic filtering, 1..16 (1: mip-mapping alone)
//     stereo: false         # side-by-side HMD eyes
//     hmd: {eye_size: [1440, 1600], ipd_m: 0.064, outer_deg: 50, inner_deg: 45,
//              up_deg: 50, down_deg: 50}

#include <cstdint>

#include "engine/scene.h"

namespace pwsim::render {

/// One HMD eye's field of view, as the four half-angles of an asymmetric frustum.
struct EyeFov {
  double outer_deg{50.0};  ///< [deg] towards the temple
  double inner_deg{45.0};  ///< [deg] towards the nose
  double up_deg{50.0};     ///< [deg]
  double down_deg{50.0};   ///< [deg]
};

struct StereoConfig {
  int eye_width{1440};   ///< [px] per eye
  int eye_height{1600};  ///< [px]
  double ipd{0.064};     ///< [m] interpupillary distance
  EyeFov fov;
};

struct RenderConfig {
  int width{1280};         ///< [px] mono image
  int height{720};         ///< [px]
  int fps{50};             ///< [frames/s]; clock.rate_hz must be a multiple
  double fov_y_deg{60.0};  ///< [deg] mono vertical field of view
  double near{0.05};       ///< [m] fixed near clip plane
  double far{100.0};       ///< [m] fixed far clip plane
  int warmup_frames{3};    ///< frames drawn and discarded before the first real one
  bool stereo{false};      ///< side-by-side HMD eyes instead of the mono view
  StereoConfig hmd;
  bool remove_tilt{true};                ///< remove the tilt-coordination angle from the view
  std::uint32_t texture_seed{20240601};  ///< procedural textures (deterministic)
  /// Textures are mip-mapped; above 1, also sampled anisotropically (up to this many taps
  /// along the floor's direction of minification: a sharper far floor). llvmpipe then takes
  /// ≈ 3.5× the CPU per frame (1280×720 circuit view: 20 → 73 ms), so 1 by default.
  int anisotropy{1};
  double cushion_width{1.8};             ///< [m] across the path
  int crf{20};                           ///< H.264 constant rate factor (0 = best, 51 = worst)

  /// Image size actually produced: mono size, or both eyes side by side.
  int image_width() const { return stereo ? 2 * hmd.eye_width : width; }
  int image_height() const { return stereo ? hmd.eye_height : height; }
  /// Ticks per frame N (frame k is tick k·N). @pre IsValid.
  int TicksPerFrame(const Clock& clock) const { return clock.rate_hz / fps; }
  /// Empty when valid against `clock`, else what is wrong (field and why).
  std::string Validate(const Clock& clock) const;
};

/// The scene's `render:` section over the defaults (defaults alone when absent).
/// @throws InputError naming file, line, field and what was expected.
RenderConfig ParseRenderConfig(const Scene& scene);

}  // namespace pwsim::render
