#pragma once
// Tyre: combined-slip magic formula with first-order slip relaxation.
//
// Pure slip (Pacejka's magic formula):   F = D sin(C atan(B s - E (B s - atan(B s))))
//   longitudinal: s = κ,      D = μ_x F_z, B C D = C_κ = (C_κ/F_z) F_z
//   lateral:      s = tan α,  D = μ_y F_z, B C D = C_α = c1 sin(2 atan(F_z / c2))
// Combined slip (similarity method on normalised "theoretical" slips): with
//   σ_x = C_κ κ / (μ_x F_z),  σ_y = C_α tan α / (μ_y F_z),  σ = √(σ_x² + σ_y²)
//   F_x = μ_x F_z g_x(σ) σ_x/σ,  F_y = μ_y F_z g_y(σ) σ_y/σ,
//   g(σ) = sin(C atan(σ/C - E (σ/C - atan(σ/C))))   (unit slope at 0, peak 1),
// which is the pure-slip formula above when the other slip is 0, and bounds the resultant
// force by the friction ellipse (F_x/μ_x F_z)² + (F_y/μ_y F_z)² ≤ 1.
//
// Relaxation (lagged slip; no division by the speed, so no blow-up at standstill):
//   σ_κ dκ'/dt = (R_e ω - V_cx) - V κ',   σ_α dα'/dt = -V_cy - V α',   V = max(|V_cx|, v_low)
// with V_cx, V_cy the contact-point velocity in the wheel frame (x along the wheel heading).
// In steady state κ' = (R_e ω - V_cx)/V and α' = tan α = -V_cy/V (α > 0 pushes the tyre left).
// The longitudinal force is evaluated at κ' + τ_x dκ'/dt: a carcass damper beside the tread
// spring, which damps the wheel-spin / tyre-deflection mode (≈ 30 Hz) that the lag alone leaves
// almost undamped at low speed (ζ = V/(2 σ_κ ω_n)).
// Integrated with the decay term implicit (stable for any step). Below v_low a contact damping
// -c_low (1 - |V_cx|/v_low) V_s is added so that a car braked to a halt settles instead of
// rocking on its tyre springs.

#include <cmath>

#include "engine/vehicle/vehicle_params.h"

namespace pwsim::vehicle {

/// Unit magic-formula curve g(σ) (slope 1 at 0, peak 1 when E ≤ 1).
inline double UnitMagic(double sigma, double shape, double curvature) {
  const double bs = sigma / shape;
  return std::sin(shape * std::atan(bs - curvature * (bs - std::atan(bs))));
}

/// C_α(F_z) = c1 sin(2 atan(F_z/c2)) [N/rad], evaluated as c1 · 2z/(1 + z²), z = F_z/c2.
inline double CorneringStiffness(const TyreParams& tyre, double fz) {
  const double z = fz / tyre.cornering_c2;
  return tyre.cornering_c1 * 2.0 * z / (1.0 + z * z);
}

struct TyreForce {
  double fx{0.0};  ///< [N] along the wheel heading
  double fy{0.0};  ///< [N] lateral, wheel frame (positive left)
};

/// Steady combined-slip force for slip ratio κ and tan α at load F_z ≥ 0.
TyreForce CombinedSlipForce(const TyreParams& tyre, double kappa, double tan_alpha, double fz);

/// Lagged slip state of one tyre.
struct TyreSlipState {
  double kappa{0.0};      ///< κ' [-]
  double tan_alpha{0.0};  ///< tan α' [-]
  bool operator==(const TyreSlipState&) const = default;
};

/// One relaxation step: contact velocities vcx, vcy [m/s] (wheel frame), wheel rim speed
/// R_e ω [m/s], step dt [s].
inline TyreSlipState RelaxSlip(const TyreParams& tyre, const TyreSlipState& s, double vcx,
                               double vcy, double rim_speed, double dt) {
  const double v = std::max(std::abs(vcx), tyre.low_speed);
  TyreSlipState next;
  next.kappa = (s.kappa + dt * (rim_speed - vcx) / tyre.relax_x) / (1.0 + dt * v / tyre.relax_x);
  next.tan_alpha = (s.tan_alpha - dt * vcy / tyre.relax_y) / (1.0 + dt * v / tyre.relax_y);
  return next;
}

/// Force of a tyre from its lagged slips plus the low-speed contact damping.
inline TyreForce TyreForceFromState(const TyreParams& tyre, const TyreSlipState& s, double fz,
                                    double vcx, double vcy, double rim_speed) {
  // carcass damping: the force follows κ' + τ_x dκ'/dt (a damper beside the tread spring)
  const double v = std::max(std::abs(vcx), tyre.low_speed);
  const double kappa_rate = (rim_speed - vcx - v * s.kappa) / tyre.relax_x;
  TyreForce f = CombinedSlipForce(tyre, s.kappa + tyre.carcass_damping_time * kappa_rate, s.tan_alpha, fz);
  const double fade = 1.0 - std::abs(vcx) / tyre.low_speed;
  if (fade > 0.0 && fz > 0.0) {
    const double c = tyre.low_speed_damping * fade;
    f.fx += c * (rim_speed - vcx);
    f.fy -= c * vcy;
  }
  return f;
}

}  // namespace pwsim::vehicle
