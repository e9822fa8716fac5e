#pragma once
// Powertrain pieces: the engine torque map blended by throttle, the idle controller, the stall
// rule, and the clutch capacity from the pedal. The coupling of engine, clutch, gearbox and
// driven wheels (stick/slip switching) is in vehicle.cc, which owns all the speeds.
//
// Engine torque:  T_e(ω, θ) = T_closed(ω) + θ (T_full(ω) - T_closed(ω)),  θ ∈ [0, 1]
//   with T_full, T_closed linearly interpolated in rpm (held beyond the last point).
// Idle control (PI on the engine speed, anti-windup by clamping):
//   θ_idle = clamp(k_p (n_idle - n) + I, 0, θ_max),  İ = k_i (n_idle - n) (I kept in [0, θ_max])
//   θ_eff = max(θ_driver, θ_idle), and θ_eff = 0 above max_rpm (fuel cut).
// Stall: a running engine whose speed falls below stall_rpm stops; a stopped engine gives only
//   its friction |T_closed(ω)| as Coulomb friction, until restarted.
// Clutch capacity from the pedal travel c ∈ [0, 1] (0 released, 1 pressed):
//   T_cap = T_max · e(c),  e = 1 for c ≤ c_engaged, 0 for c ≥ c_free, smoothstep between.

#include <algorithm>

#include "engine/vehicle/vehicle_params.h"

namespace pwsim::vehicle {

struct EngineCurves {
  double full_load{0.0};        ///< [N m]
  double closed_throttle{0.0};  ///< [N m] ≤ 0
};

/// The two curves at `rpm` (≥ 0; negative speeds use |rpm|).
EngineCurves EngineCurvesAt(const EngineParams& engine, double rpm);

/// T_e(rpm, θ) of a running engine [N m].
inline double EngineTorque(const EngineParams& engine, double rpm, double throttle) {
  const EngineCurves c = EngineCurvesAt(engine, rpm);
  return c.closed_throttle + throttle * (c.full_load - c.closed_throttle);
}

struct IdleControllerState {
  double integral{0.0};  ///< I [-]
  bool operator==(const IdleControllerState&) const = default;
};

/// Effective throttle θ_eff and the next controller state for engine speed `rpm`.
struct IdleOutput {
  double throttle{0.0};
  IdleControllerState next;
};
IdleOutput IdleControl(const EngineParams& engine, const IdleControllerState& state, double rpm,
                       double driver_throttle, double dt);

/// T_cap [N m] for pedal travel `pedal` ∈ [0, 1].
double ClutchCapacity(const ClutchParams& clutch, double pedal);

}  // namespace pwsim::vehicle
