#pragma once
// OffscreenRenderer: draws a RenderScene into memory with OpenSceneGraph on an OSMesa context
// (llvmpipe; compatibility profile, BGRA, no X server, no GPU). Mono or side-by-side stereo
// HMD eyes; near/far fixed; warm-up frames drawn before the first real one. OSG and OSMesa
// types stay in the .cc.
//
//   OffscreenRenderer renderer(render_scene, config);       // throws RenderError if no real GL
//   ImageView frame = renderer.Render(X_WV, X_WC, t);         // BGRA, row 0 at the top
//
// The constructor checks GL_RENDERER: a NULL or stub renderer string means the gl* symbols
// bound to the wrong library (libGL before libOSMesa on the link line), and rendering stops
// with a clear error instead of writing empty frames.

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "render/render_config.h"
#include "render/render_scene.h"

namespace pwsim::render {

class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A BGRA8 image owned by someone else (rows top to bottom, stride = 4·width).
struct ImageView {
  const std::uint8_t* bgra{nullptr};
  int width{0};
  int height{0};
};

class OffscreenRenderer final {
 public:
  /// @throws RenderError when no OSMesa context can be made or GL_RENDERER is not a real one.
  OffscreenRenderer(const RenderScene& scene, const RenderConfig& config);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  /// Draws one frame with the chair at X_WV and the head camera at X_WC (stereo: the eyes are
  /// ±ipd/2 along C's y). The view is valid until the next call.
  ImageView Render(const Eigen::Isometry3d& X_WV, const Eigen::Isometry3d& X_WC, double time);

  int width() const;
  int height() const;
  const std::string& gl_renderer() const;  ///< e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  const std::string& gl_version() const;
  /// The textures' max anisotropy in effect: config.anisotropy clamped by the context's
  /// GL_MAX_TEXTURE_MAX_ANISOTROPY (1 without GL_EXT_texture_filter_anisotropic).
  double texture_anisotropy() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Column-major 4×4 projection of an asymmetric frustum from half-angles [rad] (OpenGL).
Eigen::Matrix4d FrustumProjection(double left, double right, double down, double up, double near,
                                  double far);

}  // namespace pwsim::render
