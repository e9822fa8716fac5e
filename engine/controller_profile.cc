#include "engine/controller_profile.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pwsim {

std::string ControllerProfile::Validate() const {
  const auto positive = [](double value) { return std::isfinite(value) && value > 0.0; };
  if (!positive(max_forward_speed)) return "max_forward_speed must be > 0";
  if (!positive(max_reverse_speed)) return "max_reverse_speed must be > 0";
  if (!positive(max_turn_rate)) return "max_turn_rate must be > 0";
  if (!(turn_rate_at_speed > 0.0 && turn_rate_at_speed <= 1.0)) return "turn_rate_at_speed must be in (0, 1]";
  if (!positive(turn_gain)) return "turn_gain must be > 0";
  if (!positive(forward_accel)) return "forward_accel must be > 0";
  if (!positive(forward_decel)) return "forward_decel must be > 0";
  if (!positive(reverse_accel)) return "reverse_accel must be > 0";
  if (!positive(reverse_decel)) return "reverse_decel must be > 0";
  if (!positive(turn_accel)) return "turn_accel must be > 0";
  if (!positive(turn_decel)) return "turn_decel must be > 0";
  if (!(deadband >= 0.0 && deadband < 0.5)) return "deadband must be in [0, 0.5)";
  if (!(exponent >= 1.0 && exponent <= 3.0)) return "exponent must be in [1, 3]";
  return "";
}

double ShapeDeflection(const ControllerProfile& profile, double deflection) {
  if (!std::isfinite(deflection) || std::abs(deflection) > 1.0) return 0.0;  // safe reaction
  const double magnitude = std::abs(deflection);
  if (magnitude <= profile.deadband) return 0.0;
  double shaped = (magnitude - profile.deadband) / (1.0 - profile.deadband);
  if (profile.exponent != 1.0) shaped = std::pow(shaped, profile.exponent);
  return deflection < 0.0 ? -shaped : shaped;
}

ControllerState ControllerTarget(const ControllerProfile& profile, const JoystickInput& input) {
  ControllerState target;
  const double f = ShapeDeflection(profile, input.forward);
  target.speed = f * (f >= 0.0 ? profile.max_forward_speed : profile.max_reverse_speed);
  const double t = std::clamp(profile.turn_gain * ShapeDeflection(profile, input.turn), -1.0, 1.0);
  const double speed_share = std::min(1.0, std::abs(target.speed) / profile.max_forward_speed);
  target.yaw_rate = t * profile.max_turn_rate * (1.0 - (1.0 - profile.turn_rate_at_speed) * speed_share);
  return target;
}

namespace {

/// Moves `value` toward `target` by at most grow·dt when |value| grows (same sign) and
/// shrink·dt when it shrinks or crosses zero (crossing zero first shrinks to 0).
double Ramp(double value, double target, double grow, double shrink, double dt) {
  if (target == value) return value;
  const bool growing = (value >= 0.0 && target > value) || (value <= 0.0 && target < value);
  if (growing) {
    const double step = grow * dt;
    return target > value ? std::min(target, value + step) : std::max(target, value - step);
  }
  const double step = shrink * dt;
  double next = target > value ? std::min(target, value + step) : std::max(target, value - step);
  // shrinking through zero stops at zero for this tick (the next tick grows the other way)
  if ((value > 0.0 && next < 0.0) || (value < 0.0 && next > 0.0)) next = 0.0;
  return next;
}

}  // namespace

ControllerState StepController(const ControllerProfile& profile, const ControllerState& state,
                               const JoystickInput& input, double dt) {
  return StepControllerToward(profile, state, ControllerTarget(profile, input), dt);
}

ControllerState StepControllerToward(const ControllerProfile& profile, const ControllerState& state,
                                     const ControllerState& target, double dt) {
  ControllerState next;
  const bool reverse = state.speed < 0.0 || (state.speed == 0.0 && target.speed < 0.0);
  next.speed = Ramp(state.speed, target.speed, reverse ? profile.reverse_accel : profile.forward_accel,
                    reverse ? profile.reverse_decel : profile.forward_decel, dt);
  next.yaw_rate = Ramp(state.yaw_rate, target.yaw_rate, profile.turn_accel, profile.turn_decel, dt);
  next.accel = (next.speed - state.speed) / dt;
  next.yaw_accel = (next.yaw_rate - state.yaw_rate) / dt;
  return next;
}

ControllerProfile ParseControllerProfile(YamlMap& map) {
  ControllerProfile p;
  constexpr double kDeg = std::numbers::pi / 180.0;
  // Accelerations are read with an open range below at 0 so "negative" names the field.
  const Range speed = Range::Positive(5.0, "m/s");
  const Range accel = Range::Positive(10.0, "m/s^2 (a positive rate: decelerations are given positive)");
  const Range turn_accel = Range::Positive(2000.0, "deg/s^2 (positive)");
  p.max_forward_speed = map.NumberOr("max_forward_speed_mps", p.max_forward_speed, speed);
  p.max_reverse_speed = map.NumberOr("max_reverse_speed_mps", p.max_reverse_speed, speed);
  p.max_turn_rate = kDeg * map.NumberOr("max_turn_rate_degps", p.max_turn_rate / kDeg, Range::Positive(360.0, "deg/s"));
  p.turn_rate_at_speed = map.NumberOr("turn_rate_at_speed", p.turn_rate_at_speed, Range::Positive(1.0));
  p.turn_gain = map.NumberOr("turn_gain", p.turn_gain, Range::Positive(10.0));
  p.forward_accel = map.NumberOr("forward_accel_mps2", p.forward_accel, accel);
  p.forward_decel = map.NumberOr("forward_decel_mps2", p.forward_decel, accel);
  p.reverse_accel = map.NumberOr("reverse_accel_mps2", p.reverse_accel, accel);
  p.reverse_decel = map.NumberOr("reverse_decel_mps2", p.reverse_decel, accel);
  p.turn_accel = kDeg * map.NumberOr("turn_accel_degps2", p.turn_accel / kDeg, turn_accel);
  p.turn_decel = kDeg * map.NumberOr("turn_decel_degps2", p.turn_decel / kDeg, turn_accel);
  p.deadband = map.NumberOr("deadband", p.deadband, Range{0.0, 0.5, false, true, ""});
  p.exponent = map.NumberOr("exponent", p.exponent, Range::Closed(1.0, 3.0));
  return p;
}

}  // namespace pwsim
