#pragma once
// The MCA's input: the motion felt at the occupant's vestibular point H. Specific force
// fs_WH_H = R_HW (a_WH_W - g_W) and angular velocity w_WH_H, both expressed in H (x forward,
// y left, z up; H is parallel to the chair frame V). At rest fs = (0, 0, +g).
// The sagittal chair model gives surge, heave and pitch; all six axes are carried.
//
//   HeadMotion h = HeadMotionFromChair(sample, scene.occupant.head_offset);

#include <array>
#include <cmath>
#include <vector>

#include "engine/chair_simulator.h"
#include "mca/dof.h"

namespace pwsim::mca {

struct HeadMotion {
  std::array<double, 3> fs{0.0, 0.0, kGravity};  ///< fs_WH_H [m/s^2]
  /// w_WH_H [rad/s], right-handed about x, y, z. Note y points left, so a nose-up pitch rate
  /// θ̇ is w[1] = -θ̇.
  std::array<double, 3> w{};
  /// The head's attitude relative to gravity [rad]: roll φ (left side up) and pitch θ (nose-up)
  /// of H's axes, R_WH = Rz(ψ) Ry(−θ) Rx(φ) — what a slope, a ramp or a banked road sustains.
  /// 0 where the producer does not know it; then nothing is presented as bank (mca/washout.h).
  std::array<double, 2> attitude{};
  bool operator==(const HeadMotion&) const = default;
};

/// The gravity part of the specific force at an attitude: g·(sin θ, sin φ cos θ, cos φ cos θ),
/// R_WHᵀ (0, 0, g) (a vehicle at rest on a slope feels exactly this).
inline std::array<double, 3> GravityAtAttitude(const std::array<double, 2>& attitude) {
  const double sr = std::sin(attitude[0]), cr = std::cos(attitude[0]);
  const double sp = std::sin(attitude[1]), cp = std::cos(attitude[1]);
  return {kGravity * sp, kGravity * sr * cp, kGravity * cr * cp};
}

/// The rotational cue rates of a motion: (roll rate, nose-up pitch rate, yaw rate) [rad/s].
inline std::array<double, 3> CueRates(const HeadMotion& m) { return {m.w[0], -m.w[1], m.w[2]}; }

/// Pose of the eye/head point in W for the visual channel (sagittal plane).
struct HeadPose {
  double x{0.0};      ///< [m] along the path
  double z{0.0};      ///< [m] altitude
  double pitch{0.0};  ///< [rad] nose-up
};

/// Head motion of the chair at one sample: O_V moves with (drive.a, lm_acc.z) and pitches with
/// θ_M; the head sits at p_VH = head_offset from O_V in V. Exact rigid-body kinematics:
/// a_WH = a_WV + θ̈ R'(θ) p_VH - θ̇² R(θ) p_VH in the x-z plane.
HeadMotion HeadMotionFromChair(const ChairSample& sample, const std::array<double, 3>& head_offset);
/// p_WH and the chair pitch at one sample.
HeadPose HeadPoseFromChair(const ChairSample& sample, const std::array<double, 3>& head_offset);

/// A frame fixed on a rigid body, seen from W: its origin p [m] and R (row-major 3×3, columns the
/// frame's axes in W). Bodies are posed as (x, y, z, roll, pitch, yaw) like the platform's axes
/// (mca/dof.h): R = Rz(ψ) Ry(−θ) Rx(φ), roll left side up, pitch nose-up, yaw turning left.
struct PointPose {
  std::array<double, 3> p{};
  std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
};
/// The frame at p_B (in the body's axes) on a body posed at `pose` = (x, y, z, roll, pitch, yaw)
/// [m, rad], indexed like DofArray: p = (x, y, z) + R p_B.
PointPose PointOnBody(const DofArray& pose, const std::array<double, 3>& p_B);

/// The same at one tick from its neighbours (a live loop: the motion of tick k once tick k+1
/// is known, one tick late). No allocation.
HeadMotion HeadMotionAt(const PointPose& prev, const PointPose& now, const PointPose& next, double dt);
/// Motion felt at a frame that moves along `poses` (one per tick, dt apart), by central
/// differences (the end ticks copy their neighbours): fs = Rᵀ (p̈ − g_W), Ω = Rᵀ Ṙ with
/// w = (Ω₃₂, Ω₁₃, Ω₂₁). Works through any yaw (no angle wrapping: R is differenced). Allocates.
std::vector<HeadMotion> HeadMotionFromPoses(const std::vector<PointPose>& poses, double dt);
/// The head motion of a vehicle (or chair) posed at `body` per tick, the head at p_VH in V.
std::vector<HeadMotion> HeadMotionFromBodyTrack(const std::vector<DofArray>& body,
                                                const std::array<double, 3>& head_offset, double dt);

/// A tracked rigid body (e.g. motion capture of the chair) sampled on the engine's ticks.
struct SagittalTrack {
  double dt{1e-3};             ///< [s]
  std::vector<double> x;       ///< O_V along the path [m]
  std::vector<double> z;       ///< O_V altitude [m]
  std::vector<double> pitch;   ///< [rad] nose-up
};
/// Head motion from a pose track by central differences (one-sided at the ends).
/// `smooth_ticks` > 0 averages each derivative over ±smooth_ticks (measured, noisy tracks).
std::vector<HeadMotion> HeadMotionFromTrack(const SagittalTrack& track,
                                            const std::array<double, 3>& head_offset,
                                            int smooth_ticks = 0);

}  // namespace pwsim::mca
