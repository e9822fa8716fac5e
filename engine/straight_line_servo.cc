#include "engine/straight_line_servo.h"

#include <cmath>

namespace pwsim {
namespace {

struct Rates {
  double x, y, yaw, integral;
};

Rates Derivative(const ServoParams& p, const ServoState& s, double u) {
  const double y_rate = u * std::sin(s.yaw) + p.drift_lateral;
  const double omega = p.enabled ? -(p.kp * y_rate + p.ki * s.integral) : 0.0;
  return {u * std::cos(s.yaw), y_rate, omega + p.drift_yaw_rate, y_rate};
}

}  // namespace

ServoState StepServo(const ServoParams& params, const ServoState& state, double u, double dt) {
  const Rates k1 = Derivative(params, state, u);
  ServoState mid = state;
  mid.x += 0.5 * dt * k1.x;
  mid.y += 0.5 * dt * k1.y;
  mid.yaw += 0.5 * dt * k1.yaw;
  mid.integral += 0.5 * dt * k1.integral;
  const Rates k2 = Derivative(params, mid, u);
  ServoState next = state;
  next.x += dt * k2.x;
  next.y += dt * k2.y;
  next.yaw += dt * k2.yaw;
  next.integral += dt * k2.integral;
  return next;
}

}  // namespace pwsim
