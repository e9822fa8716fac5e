#pragma once
// Camera rig: where the eyes are and where they look, from the MCA's visual channel.
// Pure maths (Eigen), no OSG. Frames (docs/notation.md): W world (x forward, y left, z up),
// V chair, H head, C camera with H's axes (x along the line of sight, y left, z up); the
// OpenGL eye frame (x right, y up, looking along -z) is made from C only in osg_scene.cc.
//
//   VisualSample s{.x = 1.0, .z = 0.0, .pitch = 0.02, .tilt_pitch = 0.01};
//   Eigen::Isometry3d X_WC = EyePose(s, head_offset, /*remove_tilt=*/true, Eye::kCentre, ipd);

#include <Eigen/Geometry>
#include <array>

namespace pwsim::render {

/// One tick of the visual channel: the chair pose the visuals must show and the platform's
/// tilt-coordination angle (which the visuals must NOT show).
struct VisualSample {
  double x{0.0};           ///< [m] O_V along W's x
  double z{0.0};           ///< [m] O_V height in W
  double pitch{0.0};       ///< [rad] chair pitch to show, positive nose-up
  double tilt_pitch{0.0};  ///< [rad] platform tilt-coordination pitch, positive nose-up
  double tilt_roll{0.0};   ///< [rad] platform tilt-coordination roll, positive right side down
  // The chair in the plane (circuit scenes); 0 on a straight run.
  double y{0.0};           ///< [m] O_V across W (left)
  double yaw{0.0};         ///< [rad] heading, turning left positive
  double roll{0.0};        ///< [rad] chair roll to show, positive left side up
};

enum class Eye { kCentre, kLeft, kRight };

/// R for a nose-up pitch θ and a right-side-down roll φ: R = Ry(-θ) Rx(φ).
Eigen::Matrix3d PitchRollRotation(double pitch, double roll);
/// Inverse of PitchRollRotation for rotations without yaw: {pitch, roll} [rad].
std::array<double, 2> PitchRollOf(const Eigen::Matrix3d& R);

/// X_WV: the chair pose of a visual sample (x, z, pitch; y = 0, no yaw or roll).
Eigen::Isometry3d ChairPose(const VisualSample& sample);

/// X_WV of a chair free in the plane: (x, y, z) and R = Rz(ψ) Ry(−θ) Rx(φ).
Eigen::Isometry3d ChairPose3d(const VisualSample& sample);

/// X_WC of one eye. The eye sits at p_VH (head_offset) on the chair, shifted ±ipd/2 along the
/// head's y for the left/right eye. The head tracker of an HMD on the platform sees the
/// platform's tilt; with `remove_tilt` the renderer takes it out again (the view shows the chair
/// pitch only); without it the view is pitched and rolled by the tilt as well.
Eigen::Isometry3d EyePose(const VisualSample& sample, const std::array<double, 3>& head_offset,
                          bool remove_tilt, Eye eye = Eye::kCentre, double ipd = 0.0);
/// The same for a chair at X_WV (e.g. ChairPose3d(sample)); EyePose uses ChairPose(sample).
Eigen::Isometry3d EyePoseOn(const Eigen::Isometry3d& X_WV, const VisualSample& sample,
                            const std::array<double, 3>& head_offset, bool remove_tilt,
                            Eye eye = Eye::kCentre, double ipd = 0.0);

}  // namespace pwsim::render
