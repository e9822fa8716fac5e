#include "engine/caster.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pwsim {
namespace {

double WrapAngle(double angle) {
  constexpr double kPi = std::numbers::pi;
  if (angle > kPi) return angle - 2.0 * kPi;
  if (angle <= -kPi) return angle + 2.0 * kPi;
  return angle;
}

/// Rolling speed below which rolling resistance is scaled down linearly (its Coulomb sign
/// regularised so a caster at rest carries no force) [m/s].
constexpr double kRollingSpeedScale = 0.01;

}  // namespace

CasterForce StepCaster(const CasterParams& params, CasterState& state, double pivot_x,
                       double pivot_y, double vx, double vy, double yaw_rate, double load,
                       double dt) {
  const double c = std::cos(state.angle);
  const double s = std::sin(state.angle);
  const double t = params.trail;
  const bool grounded = load > 0.0;
  const double k = grounded ? params.lateral_damping : 0.0;
  const double v_n = -vx * s + vy * c;  // pivot speed across the wheel
  const double v_e = vx * c + vy * s;   // pivot speed along the wheel

  // Implicit in δ̇:  (I_s/dt + t² k + c_s) δ̇⁺ = I_s/dt δ̇ + t k (v_n - t ω) - T_f sgn(δ̇⁺)
  const double inertia_rate = params.swivel_inertia / dt;
  const double a = inertia_rate + t * t * k + params.swivel_damping;
  const double b = inertia_rate * state.angle_rate + t * k * (v_n - t * yaw_rate);
  const double friction = params.swivel_friction + params.scrub_per_load * std::max(load, 0.0);
  double rate = 0.0;
  if (std::abs(b) > friction) rate = (b - std::copysign(friction, b)) / a;  // else: sticks
  state.angle_rate = rate;
  state.angle = WrapAngle(state.angle + rate * dt);

  CasterForce force;
  force.slip = v_n - t * (yaw_rate + rate);
  const double lateral = -k * force.slip;
  const double rolling = grounded ? -params.rolling_resistance * load *
                                        std::clamp(v_e / kRollingSpeedScale, -1.0, 1.0)
                                  : 0.0;
  force.fx = rolling * c - lateral * s;
  force.fy = rolling * s + lateral * c;
  force.contact_x = pivot_x - t * c;
  force.contact_y = pivot_y - t * s;
  return force;
}

double KinematicCasterAngle(double angle0, double trail, double distance) {
  return 2.0 * std::atan(std::tan(0.5 * angle0) * std::exp(-distance / trail));
}

}  // namespace pwsim
