#pragma once
// The straight-line servo of seed 000 Fig. 4: a unicycle (differential-drive chair) commanded
// at forward speed u drifts sideways (wheel mismatch, floor slope); a proportional-integral
// correction on the measured lateral speed ẏ (target 0) adds a yaw-rate command ω.
//   ẋ = u cos ψ,  ẏ = u sin ψ + v_d,  ψ̇ = ω + ω_d
//   ω = -(k_p ẏ + k_i ∫ẏ dt) = -(k_p ẏ + k_i (y - y0))
// v_d [m/s] is a lateral slip, ω_d [rad/s] a yaw bias; both are the disturbance.

namespace pwsim {

struct ServoParams {
  double kp{2.0};              ///< [rad/m] gain on ẏ
  double ki{1.0};              ///< [rad/(m s)] gain on ∫ẏ
  bool enabled{true};          ///< false: open loop, ω = 0
  double drift_yaw_rate{0.02}; ///< ω_d [rad/s] yaw bias of the drive
  double drift_lateral{0.0};   ///< v_d [m/s] lateral slip
};

struct ServoState {
  double x{0.0};    ///< [m]
  double y{0.0};    ///< [m]
  double yaw{0.0};  ///< ψ [rad]
  double integral{0.0};  ///< ∫ẏ dt [m]
  bool operator==(const ServoState&) const = default;
};

/// One explicit step of length dt [s] at forward speed u [m/s] (midpoint rule).
ServoState StepServo(const ServoParams& params, const ServoState& state, double u, double dt);

}  // namespace pwsim
