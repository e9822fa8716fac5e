#pragma once
// Motion from the pixels: the camera's rotation (pitch, roll, yaw) and, in a room, its vertical
// displacement between two consecutive frames, estimated with OpenCV (Shi-Tomasi corners,
// pyramidal Lucas-Kanade flow), and the comparison of such a series with a reference (gain, lag,
// correlation). This closes the loop on the video itself: wrong sign, wrong axis, dropped or
// shifted frames all show up. Two models of what the camera sees:
//
//  kFloorPlane  a floor (and ceiling) plane at a known distance from the eye (a chair moving
//               along a room): with R ≈ I + [ω]×, a plane point x₁ maps to x₂ ∝ R x₁ + t w
//               (w = nᵀx₁ / d its inverse depth), linear in (ω, t); rotation and the eye's
//               vertical motion by re-weighted least squares.
//  kRigid       any rigid scene (walls, obstacles, relief of a circuit; depths unknown): the
//               rotation alone, from the 5-point essential matrix E = [t]× R (x₂ᵀ E x₁ = 0;
//               RANSAC with local optimisation, cv::USAC_ACCURATE), R the smaller rotation of
//               its twisted pair. With the eye barely moving (a turn on the spot) t is
//               undetermined, but every E of the form [t]× R still carries the right R; an
//               image that did not move at all (median flow under 0.02 px) is ω = 0.
//
//   FrameMotionEstimator estimator(width, height, fov_y_deg);
//   estimator.Push(frame0);
//   FrameMotion m = estimator.Push(frame1, /*eye_height=*/1.3);  // m.pitch_delta [rad]

#include <memory>
#include <vector>

#include "render/offscreen_renderer.h"

namespace pwsim::render {

/// Camera motion from the previous frame to this one, in the previous camera's axes.
struct FrameMotion {
  bool valid{false};
  double pitch_delta{0.0};     ///< [rad] nose-up positive
  double roll_delta{0.0};      ///< [rad] right side down positive
  double yaw_delta{0.0};       ///< [rad] about the camera's up axis, a turn to the left positive
  double vertical_delta{0.0};  ///< [m] up positive (scaled by the given eye height; kFloorPlane)
  int tracked{0};              ///< features tracked
  int inliers{0};              ///< points the model holds (plane fit or essential matrix)
};

/// What the estimator may assume about the scene (above).
enum class SceneModel { kFloorPlane, kRigid };

class FrameMotionEstimator final {
 public:
  /// Frames wider than `max_width` are halved until they fit (speed); intrinsics follow.
  FrameMotionEstimator(int width, int height, double fov_y_deg, int max_width = 640,
                       SceneModel model = SceneModel::kFloorPlane);
  ~FrameMotionEstimator();
  FrameMotionEstimator(const FrameMotionEstimator&) = delete;
  FrameMotionEstimator& operator=(const FrameMotionEstimator&) = delete;

  /// Takes the next frame; the first call returns an invalid motion. `eye_height` [m] is the
  /// camera's height above the floor, which sets the scale of the vertical displacement;
  /// `ceiling_clearance` [m] the ceiling's height above the eye (0: do not use the ceiling);
  /// kRigid uses neither.
  FrameMotion Push(const ImageView& frame, double eye_height = 1.3, double ceiling_clearance = 0.0);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// How well `estimate` follows `reference` (same sampling, step dt [s]).
struct SeriesComparison {
  double gain{0.0};         ///< least-squares slope of estimate on the lag-aligned reference
  double lag{0.0};          ///< [s] > 0: the estimate lags the reference (sub-sample, parabolic)
  double correlation{0.0};  ///< Pearson correlation at the best whole-sample lag
  double rms_error{0.0};    ///< RMS of estimate - reference at zero lag
  int samples{0};
};
/// Searches lags in [-max_lag, max_lag] samples. NaN entries are skipped.
SeriesComparison CompareSeries(const std::vector<double>& estimate,
                               const std::vector<double>& reference, double dt, int max_lag);

}  // namespace pwsim::render
