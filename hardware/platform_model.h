#pragma once
// The 2-DoF rail + yaw platform of seed 001 (an RP manipulator): q1 yaw [rad] of the rotating
// base, q2 rail position [m] of the cabin along the rotated x axis.
//   M(q) q'' + C(q, q') = Q                                               (9)
//   m11 = m1 (xG1^2 + yG1^2) + I1zz + m2 yG2^2 + m2 (xG2 + q2)^2 + I2zz,
//   m12 = m21 = -m2 yG2,  m22 = m2                                        (10)-(11)
//   C = [2 m2 (xG2 + q2) q1' q2',  -m2 (xG2 + q2) q1'^2]                  (12)
//   Q = tau - tau_f,  tau_i = K_i tau_a,i,  tau_f,i = Ks_i sign(q_i') + Kv_i q_i'   (13)-(15)
// Parameters are the identified values of the seed's table. Joint PID control (seed §VI) with
// velocity feed-forward and the actuators' saturation close the loop; the servo interpolates
// its CSP target linearly over a drive cycle.

#include <array>
#include <cstdint>

#include "hardware/actuator_servo.h"

namespace pwsim::hw {

struct PlatformParams {
  double m1{415.98};        ///< [kg] body B1 (rotating base)
  double m2{359.32};        ///< [kg] body B2 (cabin on the rail)
  double inertia_zz{4.69};  ///< [kg m^2] I1zz + I2zz
  double r_g1_sq{0.162};    ///< [m^2] xG1^2 + yG1^2
  double x_g2{0.7976};      ///< [m]
  double y_g2{-0.0107};     ///< [m]
  double kv1{0.0438};       ///< [N m s/rad] viscous, yaw
  double kv2{0.175};        ///< [N s/m] viscous, rail
  double ks1{0.2361};       ///< [N m] dry, yaw
  double ks2{0.6909};       ///< [N] dry, rail
  double gear1{139.2};      ///< K1 yaw reduction
  double gear2{45.0};       ///< K2 rail reduction
  /// Joint effort limits: the seed's peak accelerations (58.151 deg/s^2 yaw with the cabin at
  /// the rail's far end, where m11 is about 800 kg m^2; 1.224 g rail) times 1.5, so the PID can
  /// track everything the safety limits allow, Coriolis coupling included.
  double tau1_max{800.0 * 1.0149 * 1.5};  ///< [N m]
  double tau2_max{359.32 * 12.0 * 1.5};   ///< [N]
  double dry_velocity_eps{1e-4};          ///< [rad/s], [m/s] sign() regularisation
};

struct JointPid {
  double kp{0.0};
  double ki{0.0};
  double kd{0.0};
};

struct PlatformState {
  std::array<double, 2> q{};     ///< [rad, m]
  std::array<double, 2> qd{};    ///< [rad/s, m/s]
  std::array<double, 2> qdd{};   ///< last acceleration
  std::array<double, 2> tau{};   ///< last joint effort [N m, N]
  std::array<double, 2> integral{};
  bool operator==(const PlatformState&) const = default;
};

/// Mass matrix (10)-(11) and Coriolis/centrifugal vector (12) at (q, q').
void PlatformMassMatrix(const PlatformParams& p, const std::array<double, 2>& q,
                        double m[2][2]);
std::array<double, 2> PlatformCoriolis(const PlatformParams& p, const std::array<double, 2>& q,
                                       const std::array<double, 2>& qd);
/// Friction (15).
std::array<double, 2> PlatformFriction(const PlatformParams& p, const std::array<double, 2>& qd);
/// Forward dynamics: q'' for joint efforts `tau` (9).
std::array<double, 2> PlatformAcceleration(const PlatformParams& p, const PlatformState& s,
                                           const std::array<double, 2>& tau);

class PlatformPlant {
 public:
  explicit PlatformPlant(PlatformParams params = {}, double substep = 0.0005);
  /// Advances `duration` [s] tracking a target that moves linearly from the previous target to
  /// `target` with velocity feed-forward; `enabled` false = no torque (coasting). Each substep's
  /// state goes to `envelope` when given (observation only: the motion is the same).
  void Advance(double duration, const std::array<double, 2>& target, bool enabled,
               std::array<AxisEnvelope, 2>* envelope = nullptr);
  /// Sets the target without motion (used when a drive becomes enabled).
  void ResetTarget(const std::array<double, 2>& target);

  const PlatformState& state() const { return state_; }
  void set_state(const PlatformState& s) { state_ = s; }
  const PlatformParams& params() const { return params_; }
  std::array<JointPid, 2>& gains() { return gains_; }

 private:
  PlatformParams params_;
  double substep_;
  std::array<JointPid, 2> gains_;
  std::array<double, 2> previous_target_{};
  PlatformState state_;
};

}  // namespace pwsim::hw
