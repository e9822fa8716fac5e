#include "hardware/actuator_servo.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"
#include "mca/platform.h"

namespace pwsim::hw {

ActuatorServo::ActuatorServo(const mca::ActuatorLimits& limits, double moving_mass, ServoParams params)
    : limits_(limits), mass_(moving_mass), substep_(params.substep_s) {
  PWSIM_DEMAND(moving_mass > 0.0 && params.substep_s > 0.0 && params.position_bandwidth_hz > 0.0);
  PWSIM_DEMAND(limits.speed > 0.0 && limits.accel > 0.0 && limits.force > 0.0 && limits.min <= limits.max);
  kp_ = 2.0 * mca::kPi * params.position_bandwidth_hz;
  tv_ = 1.0 / (4.0 * kp_);
}

void ActuatorServo::SetLoad(double load, double moving_mass) {
  load_ = load;
  if (moving_mass > 0.0) mass_ = moving_mass;
}

double ActuatorServo::available_accel() const {
  const double left = (limits_.force - std::abs(load_)) / mass_;
  return std::max(0.05 * limits_.accel, std::min(limits_.accel, left));
}

void ActuatorServo::Advance(double duration, double target, bool enabled, AxisEnvelope* envelope) {
  const int steps = std::max(1, static_cast<int>(std::lround(duration / substep_)));
  const double h = duration / steps;
  const double a_bar = available_accel();
  const double gain = std::min(1.0, h / tv_);  // velocity loop, one substep
  const double v_ref = (target - previous_target_) / duration;
  const bool bounded_below = std::isfinite(limits_.min);
  const bool bounded_above = std::isfinite(limits_.max);
  for (int k = 1; k <= steps; ++k) {
    double v_star = 0.0;
    if (enabled) {
      const double alpha = static_cast<double>(k - 1) / steps;  // r at the substep's start, as q
      const double r = previous_target_ + alpha * (target - previous_target_);
      v_star = v_ref + kp_ * (r - state_.q);
    }
    const double v = state_.v;
    // W: acceleration and speed (they meet: |v| <= v_max), then the stroke.
    double lo = std::max(v - a_bar * h, -limits_.speed);
    double hi = std::min(v + a_bar * h, limits_.speed);
    const double lo_stroke =
        bounded_below ? -mca::StoppableSpeed(state_.q - limits_.min, a_bar, h) : -limits_.speed;
    const double hi_stroke =
        bounded_above ? mca::StoppableSpeed(limits_.max - state_.q, a_bar, h) : limits_.speed;
    if (hi_stroke < lo) {
      lo = hi = hi_stroke;  // the stroke wins over the acceleration
    } else if (lo_stroke > hi) {
      lo = hi = lo_stroke;
    } else {
      lo = std::max(lo, lo_stroke);
      hi = std::min(hi, hi_stroke);
    }
    const double v_next = std::clamp(v + gain * (v_star - v), lo, hi);
    state_.a = (v_next - v) / h;
    state_.v = v_next;
    state_.q += v_next * h;
    state_.effort = mass_ * state_.a + load_;
    if (envelope) envelope->Add(state_.q, state_.v, state_.a, state_.effort);
  }
  previous_target_ = target;
}

}  // namespace pwsim::hw
