#pragma once
// The PW controller (power module) between the joystick and the motors: the programmable
// profile a therapist sets on commercial controllers. The joystick's deflection (f forward,
// t turn, each in [-1, 1], turn positive left) becomes a speed set-point v* and a yaw-rate
// set-point ω* of the chair, each ramped at the programmed rates:
//
//   shaped(d) = sgn(d) · ((|d| - d0) / (1 - d0))^e   for |d| > d0 (deadband d0), else 0
//   v_target  = shaped(f) · (f >= 0 ? v_fwd : v_rev)
//   ω_target  = clamp(G_t · shaped(t), -1, 1) · ω_max · (1 - (1 - ρ) |v_target| / v_fwd)
//               (G_t the turn gain, ρ the share of the turn rate kept at full forward speed)
//   v* moves toward v_target at most a_acc dt per tick when |v*| grows and a_dec dt when it
//   shrinks (forward and reverse have their own rates); ω* likewise with α_acc, α_dec.
//
// Everything is exact arithmetic on the previous set-point: no allocation, same bits.

#include <string>

#include "engine/yaml_reader.h"

namespace pwsim {

struct ControllerProfile {
  double max_forward_speed{1.6};  ///< v_fwd [m/s] at full forward deflection
  double max_reverse_speed{0.6};  ///< v_rev [m/s] at full reverse deflection (positive)
  double max_turn_rate{1.2};      ///< ω_max [rad/s] at full turn deflection, standing still
  double turn_rate_at_speed{0.5}; ///< ρ [-] share of ω_max kept at full forward speed, (0, 1]
  double turn_gain{1.0};          ///< G_t [-] turn sensitivity (> 1 reaches ω_max sooner)
  double forward_accel{0.8};      ///< [m/s^2] |v*| growing, forward
  double forward_decel{1.2};      ///< [m/s^2] |v*| shrinking, forward
  double reverse_accel{0.5};      ///< [m/s^2] |v*| growing, reverse
  double reverse_decel{0.8};      ///< [m/s^2] |v*| shrinking, reverse
  double turn_accel{2.0};         ///< α_acc [rad/s^2]
  double turn_decel{3.0};         ///< α_dec [rad/s^2]
  double deadband{0.05};          ///< d0 [-] deflection read as zero, [0, 0.5)
  double exponent{1.0};           ///< e [-] response curve, [1, 3] (1 linear)

  /// Empty when consistent; otherwise the first field that is wrong and why.
  std::string Validate() const;
};

/// The joystick's deflection, each axis in [-1, 1].
struct JoystickInput {
  double forward{0.0};  ///< f: +1 full forward, -1 full reverse
  double turn{0.0};     ///< t: +1 full left, -1 full right
  bool operator==(const JoystickInput&) const = default;
};

/// The controller's ramped set-points.
struct ControllerState {
  double speed{0.0};      ///< v* [m/s]
  double yaw_rate{0.0};   ///< ω* [rad/s]
  double accel{0.0};      ///< dv*/dt over the last tick [m/s^2]
  double yaw_accel{0.0};  ///< dω*/dt over the last tick [rad/s^2]
  bool operator==(const ControllerState&) const = default;
};

/// shaped(d) of the comment above.
double ShapeDeflection(const ControllerProfile& profile, double deflection);
/// The unramped targets (v_target, ω_target) for a deflection.
ControllerState ControllerTarget(const ControllerProfile& profile, const JoystickInput& input);
/// One tick of `dt` [s]: the set-points ramped toward the targets. Deflections outside
/// [-1, 1] or NaN are read as 0 (the safe reaction of the real-time path).
ControllerState StepController(const ControllerProfile& profile, const ControllerState& state,
                               const JoystickInput& input, double dt);
/// The same tick toward targets already computed by ControllerTarget (a caller that holds the
/// deflection over many ticks computes them once): StepController(profile, state, input, dt)
/// is StepControllerToward(profile, state, ControllerTarget(profile, input), dt), bit for bit.
ControllerState StepControllerToward(const ControllerProfile& profile, const ControllerState& state,
                                     const ControllerState& target, double dt);

/// Reads a profile mapping (every field optional, defaults above):
///   {max_forward_speed_mps, max_reverse_speed_mps, max_turn_rate_degps, turn_rate_at_speed,
///    turn_gain, forward_accel_mps2, forward_decel_mps2, reverse_accel_mps2, reverse_decel_mps2,
///    turn_accel_degps2, turn_decel_degps2, deadband, exponent}
/// A negative or zero acceleration is an error naming the field. @throws InputError.
ControllerProfile ParseControllerProfile(YamlMap& map);

}  // namespace pwsim
