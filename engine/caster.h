#pragma once
// A swivel caster: a wheel on a fork that turns freely (with friction and damping) about a
// vertical pivot fixed in the chair. Its contact trails the pivot by the trail t, at the swivel
// angle δ measured from the chair's x axis (δ = 0: rolling forward with the contact behind the
// pivot; δ = π: reversing, contact ahead). In V, with e = (cos δ, sin δ), n = (-sin δ, cos δ):
//
//   contact   p_c = p_pivot - t e                (stored as the rest contact + t (1 - cos δ, -sin δ))
//   slip      s   = v_pivot · n - t (ω + δ̇)       (sideways speed of the contact)
//   tyre      F_n = -k s      (lateral force on the wheel, k [N s/m]: sideways scrub)
//             F_e = -f_r N sgn(v_pivot · e)      (rolling resistance)
//   swivel    I_s (δ̈ + ω̇) = t k s - c_s δ̇ - T_f sgn(δ̇),   T_f = T_0 + μ_s N (bearing + scrub)
//
// The swivel is integrated implicitly in δ̇ (stable for any k, I_s): with T_f sticking when the
// torque it must resist is smaller. Its limit k → ∞ (or I_s, c_s, T_f → 0) is the kinematic
// no-slip law δ̇ = (v_pivot · n) / t - ω, whose solution at constant v_pivot = (v, 0), ω = 0 is
// tan(δ/2) = tan(δ_0/2) exp(-v τ / t): a caster realigns with the time constant t / v.
//
// The wheel's ground force F = F_n n + F_e e acts on the chair at the contact p_c (the fork
// carries the swivel torque to the frame; the fork's own inertia is neglected in the reaction).

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/small_rotation.h"

namespace pwsim {

struct CasterParams {
  double trail{0.05};            ///< t [m] pivot to contact, > 0
  double swivel_inertia{4e-4};   ///< I_s [kg m^2] fork and wheel about the pivot
  double swivel_damping{0.01};   ///< c_s [N m s/rad]
  double swivel_friction{0.05};  ///< T_0 [N m] bearing friction
  double scrub_per_load{0.004};  ///< μ_s [m] friction torque per newton of wheel load
  double lateral_damping{3000.0};///< k [N s/m] sideways scrub of the tyre
  double rolling_resistance{0.02};///< f_r [-]
};

struct CasterState {
  double angle{0.0};       ///< δ [rad], wrapped to (-π, π]
  double angle_rate{0.0};  ///< δ̇ [rad/s] relative to the chair
  bool operator==(const CasterState&) const = default;
};

/// The ground's force on one caster wheel, in V [N], and where it acts (the contact, in V [m]).
struct CasterForce {
  double fx{0.0}, fy{0.0};
  double contact_x{0.0}, contact_y{0.0};
  double slip{0.0};  ///< s [m/s]
  double cos_angle{1.0}, sin_angle{0.0};  ///< cos δ, sin δ of the new angle
};

/// One implicit step of `dt` [s]: the pivot moves at (vx, vy) in V [m/s] while the chair turns
/// at ω [rad/s]; `load` N [N] is the wheel's normal load (≤ 0: lifted, no tyre force).
/// `pivot_x`, `pivot_y`: the pivot in V [m]. Returns the force over the step (from the new δ̇)
/// and writes the new state.
CasterForce StepCaster(const CasterParams& params, CasterState& state, double pivot_x,
                       double pivot_y, double vx, double vy, double yaw_rate, double load,
                       double dt);

/// What a step of `dt` needs of the parameters, computed once (no division per step).
struct CasterStepConstants {
  double dt{1e-3};
  double inertia_rate{0.0};       ///< I_s / dt
  double inv_a_grounded{0.0};     ///< 1 / (I_s/dt + t² k + c_s)
  double inv_a_lifted{0.0};       ///< 1 / (I_s/dt + c_s)
};
CasterStepConstants MakeCasterStepConstants(const CasterParams& params, double dt);

/// The same step with cos δ and sin δ of the state's angle given (as returned by the previous
/// step) and the constants above, to spare their evaluation. Same equations; the results may
/// differ from the plain StepCaster's in the last bits (reciprocals instead of divisions).
namespace caster_detail {

/// The angle wrapped back into (-π, π] after a step of less than 2π.
inline double WrapAngle(double angle) {
  constexpr double kPi = std::numbers::pi;
  if (angle > kPi) return angle - 2.0 * kPi;
  if (angle <= -kPi) return angle + 2.0 * kPi;
  return angle;
}

/// Rolling speed below which rolling resistance is scaled down linearly (its Coulomb sign
/// regularised so a caster at rest carries no force) [m/s].
constexpr double kRollingSpeedScale = 0.01;

}  // namespace caster_detail

/// (Inline: four casters step in every full-DoF chair tick.)
inline CasterForce StepCaster(const CasterParams& params, const CasterStepConstants& constants,
                              CasterState& state, double c, double s, double pivot_x,
                              double pivot_y, double vx, double vy, double yaw_rate, double load) {
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
  state.angle = caster_detail::WrapAngle(state.angle + rate * constants.dt);

  CasterForce force;
  force.slip = v_n - t * (yaw_rate + rate);
  const double lateral = -k * force.slip;
  const double rolling = grounded ? -params.rolling_resistance * load *
                                        std::clamp(v_e * (1.0 / caster_detail::kRollingSpeedScale), -1.0, 1.0)
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

/// δ after rolling a distance `distance` [m] forward from δ_0 under the kinematic law.
/// (A reference for tests and chair-checks, written from the closed form above.)
double KinematicCasterAngle(double angle0, double trail, double distance);

}  // namespace pwsim
