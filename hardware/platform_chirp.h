#pragma once
// The chirp experiment of `pwsim platform-sim --chirp`: one joint of the seed-001 platform
// (hardware/platform_model.h, PID + velocity feed-forward) tracks repeated logarithmic sweeps
// of its position reference while the other joint holds 0; both joints are sampled.
//   ω(t) = ω0·(ω1/ω0)^(t/T_s),  φ(t) = ω0·T_s/ln(ω1/ω0)·((ω1/ω0)^(t/T_s) − 1),
//   r(t) = e(t)·A(ω(t))·sin φ(t),  A(ω) = min(A0, a_max/ω²)   (acceleration-limited amplitude)
// Every sweep starts at phase 0, so each is one segment of the H1 estimate. The target of each
// sample period is the reference at the period's end (the plant interpolates linearly over it).
// A raised-cosine fade over the first and last 2 % of every sweep joins the sweeps without a
// velocity step (which would saturate the actuator).

#include <array>
#include <vector>

#include "hardware/platform_model.h"

namespace pwsim::hw {

struct ChirpParams {
  int joint{1};                  ///< 0 yaw, 1 rail
  double w0_rad_s{1.0};
  double w1_rad_s{300.0};
  double sweep_s{20.0};          ///< [s] one sweep
  int sweeps{3};
  double amplitude{0.05};        ///< A0 [m] or [rad]
  /// a_max [m/s²] or [rad/s²]; 0 = half the joint's effort limit over its nominal inertia, so
  /// the PID stays linear (a saturated actuator makes the response amplitude-dependent).
  double max_accel{0.0};
  double sample_s{0.001};
  double substep_s{1e-4};
};

struct ChirpRecord {
  std::vector<double> t;
  std::array<std::vector<double>, 2> q, q_ref, tau;  ///< per joint: [rad, m], [N m, N]
  double max_accel{0.0};      ///< a_max used
  long saturated_samples{0};  ///< samples where the swept joint's effort was at its limit
};

/// @throws std::invalid_argument for parameters out of range (names the field).
ChirpRecord RunChirp(const ChirpParams& chirp, const PlatformParams& platform = {});

}  // namespace pwsim::hw
