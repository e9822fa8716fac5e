#include "engine/vehicle/powertrain.h"

#include <cmath>

namespace pwsim::vehicle {

EngineCurves EngineCurvesAt(const EngineParams& engine, double rpm) {
  const std::vector<TorquePoint>& map = engine.map;
  const double n = std::abs(rpm);
  if (n >= map.back().rpm) return {map.back().full_load, map.back().closed_throttle};
  // few points: a linear scan is faster than a binary search
  std::size_t i = 1;
  while (map[i].rpm < n) ++i;
  const TorquePoint& a = map[i - 1];
  const TorquePoint& b = map[i];
  const double w = (n - a.rpm) / (b.rpm - a.rpm);
  return {a.full_load + w * (b.full_load - a.full_load),
          a.closed_throttle + w * (b.closed_throttle - a.closed_throttle)};
}

IdleOutput IdleControl(const EngineParams& engine, const IdleControllerState& state, double rpm,
                       double driver_throttle, double dt) {
  const double error = engine.idle_rpm - rpm;
  IdleOutput out;
  out.next.integral =
      std::clamp(state.integral + engine.idle_integral_gain * error * dt, 0.0, engine.idle_max_throttle);
  const double idle =
      std::clamp(engine.idle_gain * error + out.next.integral, 0.0, engine.idle_max_throttle);
  out.throttle = rpm > engine.max_rpm ? 0.0 : std::max(std::clamp(driver_throttle, 0.0, 1.0), idle);
  return out;
}

double ClutchCapacity(const ClutchParams& clutch, double pedal) {
  const double u = std::clamp((clutch.free_pedal - pedal) / (clutch.free_pedal - clutch.engaged_pedal), 0.0, 1.0);
  return clutch.max_torque * u * u * (3.0 - 2.0 * u);
}

}  // namespace pwsim::vehicle
