#include "engine/caster.h"

#include <cmath>

namespace pwsim {

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

double KinematicCasterAngle(double angle0, double trail, double distance) {
  return 2.0 * std::atan(std::tan(0.5 * angle0) * std::exp(-distance / trail));
}

}  // namespace pwsim
