#pragma once
// Lumped model (LM), seed 000 eq. (3)-(5): two independent base-excited spring-mass-dampers,
//   M Z̈ + C_Z (Ż - Ż_GM) + K_Z (Z - Z_GM) = 0
//   J θ̈ + C_θ (θ̇ - θ̇_GM) + K_θ (θ - θ_GM) = Γ_θ
// with M = M_0 + M_u and J = J_0 + d_CM² M.
//
// Discretisation is exact for inputs that are linear in time across a step (first-order hold
// on X_GM, so Ẋ_GM is the step's slope) and a torque held constant over the step: the
// augmented system [q, q̇, u, u̇, F] is propagated by its matrix exponential, computed once
// per (parameters, dt). A step is then two 2×5 matrix-vector products: no allocation.

#include <array>

#include "engine/chair.h"

namespace pwsim {

/// One axis of eq. (3): inertia m, damping c, stiffness k (SI, axis units).
struct AxisParams {
  double inertia{1.0};    ///< M [kg] or J [kg m^2]
  double damping{0.0};    ///< C [N s/m] or [N m s/rad]
  double stiffness{1.0};  ///< K [N/m] or [N m/rad]
};

struct LumpedModelParams {
  AxisParams heave;
  AxisParams pitch;
};

/// Builds the LM parameters of `chair` (which must have `lm`) carrying `load_kg`.
LumpedModelParams MakeLumpedModelParams(const Chair& chair, double load_kg);

struct LumpedState {
  double z{0.0};           ///< Z_M [m]
  double z_rate{0.0};      ///< Ż_M [m/s]
  double pitch{0.0};       ///< θ_M [rad]
  double pitch_rate{0.0};  ///< θ̇_M [rad/s]
  bool operator==(const LumpedState&) const = default;
};

/// The GM output at the start and end of one step, and the torque held over it.
struct LumpedInput {
  double z_gm_begin{0.0};      ///< [m]
  double z_gm_end{0.0};        ///< [m]
  double pitch_gm_begin{0.0};  ///< [rad]
  double pitch_gm_end{0.0};    ///< [rad]
  double pitch_torque{0.0};    ///< Γ_θ [N m]
};

/// Exact one-step propagator of one axis: [q, q̇]⁺ = Φ · [q, q̇, u0, u̇, F].
struct AxisPropagator {
  std::array<double, 10> phi{};  ///< rows q and q̇ of expm(A_aug dt), row-major 2×5
};

/// The exact propagator of one axis over dt. @pre axis.inertia > 0, dt > 0.
AxisPropagator MakeAxisPropagator(const AxisParams& axis, double dt);

/// One exact step of one axis: base input u0 at the step's start with rate u̇ (first-order
/// hold) and a force (or torque) held over the step. No allocation.
inline void AdvanceAxis(const AxisPropagator& p, double& q, double& q_rate, double u0,
                        double u_rate, double force) {
  const double* f = p.phi.data();
  const double next_q = f[0] * q + f[1] * q_rate + f[2] * u0 + f[3] * u_rate + f[4] * force;
  const double next_rate = f[5] * q + f[6] * q_rate + f[7] * u0 + f[8] * u_rate + f[9] * force;
  q = next_q;
  q_rate = next_rate;
}

struct DiscreteLumpedModel {
  LumpedModelParams params;
  double dt{1e-3};      ///< [s]
  double inv_dt{1e3};   ///< 1/dt, computed once by Discretize [1/s]
  AxisPropagator heave;
  AxisPropagator pitch;
};

/// Precomputes the exact propagators. @pre dt > 0, every inertia > 0.
DiscreteLumpedModel Discretize(const LumpedModelParams& params, double dt);

/// Advances one step of length model.dt. Same inputs, same bits; no allocation. Inline: it is
/// the inner step of every chair tick.
inline LumpedState Step(const DiscreteLumpedModel& model, const LumpedState& state,
                        const LumpedInput& input) {
  LumpedState next = state;
  AdvanceAxis(model.heave, next.z, next.z_rate, input.z_gm_begin,
              (input.z_gm_end - input.z_gm_begin) * model.inv_dt, 0.0);
  AdvanceAxis(model.pitch, next.pitch, next.pitch_rate, input.pitch_gm_begin,
              (input.pitch_gm_end - input.pitch_gm_begin) * model.inv_dt, input.pitch_torque);
  return next;
}

/// Accelerations (Z̈, θ̈) from eq. (3) at a state, given GM output, its rate and the torque.
struct LumpedAcceleration {
  double z{0.0};      ///< [m/s^2]
  double pitch{0.0};  ///< [rad/s^2]
};
inline LumpedAcceleration Accelerations(const LumpedModelParams& params, const LumpedState& state,
                                        double z_gm, double z_gm_rate, double pitch_gm,
                                        double pitch_gm_rate, double pitch_torque) {
  LumpedAcceleration acc;
  acc.z = (-params.heave.damping * (state.z_rate - z_gm_rate) -
           params.heave.stiffness * (state.z - z_gm)) /
          params.heave.inertia;
  acc.pitch = (pitch_torque - params.pitch.damping * (state.pitch_rate - pitch_gm_rate) -
               params.pitch.stiffness * (state.pitch - pitch_gm)) /
              params.pitch.inertia;
  return acc;
}

}  // namespace pwsim
