#include "engine/caster.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/small_rotation.h"

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

CasterStepConstants MakeCasterStepConstants(const CasterParams& params, double dt) {
  CasterStepConstants constants;
  constants.dt = dt;
  constants.inertia_rate = params.swivel_inertia / dt;
  constants.inv_a_grounded =
      1.0 / (constants.inertia_rate + params.trail * params.trail * params.lateral_damping + params.swivel_damping);
  constants.inv_a_lifted = 1.0 / (constants.inertia_rate + params.swivel_damping);
  return constants;
}

CasterForce StepCaster(const CasterParams& params, CasterState& state, double pivot_x,
                       double pivot_y, double vx, double vy, double yaw_rate, double load,
                       double dt) {
  return StepCaster(params, MakeCasterStepConstants(params, dt), state, std::cos(state.angle),
                    std::sin(state.angle), pivot_x, pivot_y, vx, vy, yaw_rate, load);
}

CasterForce StepCaster(const CasterParams& params, const CasterStepConstants& constants,
                       CasterState& state, double c, double s, double pivot_x, double pivot_y,
                       double vx, double vy, double yaw_rate, double load) {
  const double t = params.trail;
  const bool grounded = load > 0.0;
  const double k = grounded ? params.lateral_damping : 0.0;
  const double v_n = -vx * s + vy * c;  // pivot speed across the wheel
  const double v_e = vx * c + vy * s;   // pivot speed along the wheel

  // Implicit in δ̇:  (I_s/dt + t² k + c_s) δ̇⁺ = I_s/dt δ̇ + t k (v_n - t ω) - T_f sgn(δ̇⁺)
  const double inv_a = grounded ? constants.inv_a_grounded : constants.inv_a_lifted;
  const double b = constants.inertia_rate * state.angle_rate + t * k * (v_n - t * yaw_rate);
  const double friction = params.swivel_friction + params.scrub_per_load * std::max(load, 0.0);
  double rate = 0.0;
  if (std::abs(b) > friction) rate = (b - std::copysign(friction, b)) * inv_a;  // else: sticks
  state.angle_rate = rate;
  const double previous = state.angle;
  state.angle = WrapAngle(state.angle + rate * constants.dt);

  CasterForce force;
  force.slip = v_n - t * (yaw_rate + rate);
  const double lateral = -k * force.slip;
  const double rolling = grounded ? -params.rolling_resistance * load *
                                        std::clamp(v_e * (1.0 / kRollingSpeedScale), -1.0, 1.0)
                                  : 0.0;
  force.fx = rolling * c - lateral * s;
  force.fy = rolling * s + lateral * c;
  force.contact_x = pivot_x - t * c;
  force.contact_y = pivot_y - t * s;
  force.cos_angle = c;  // carried to the new angle (wrapping by 2π changes neither)
  force.sin_angle = s;
  if (state.angle != previous) RotateBy(force.cos_angle, force.sin_angle, rate * constants.dt);
  return force;
}

double KinematicCasterAngle(double angle0, double trail, double distance) {
  return 2.0 * std::atan(std::tan(0.5 * angle0) * std::exp(-distance / trail));
}

}  // namespace pwsim
