#include "engine/lumped_model.h"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "engine/check.h"

namespace pwsim {

AxisPropagator MakeAxisPropagator(const AxisParams& axis, double dt) {
  PWSIM_DEMAND(axis.inertia > 0.0 && dt > 0.0);
  // Augmented state s = [q, q̇, u, u̇, F]; u̇ and F are constant across the step.
  Eigen::Matrix<double, 5, 5> a = Eigen::Matrix<double, 5, 5>::Zero();
  const double inv_m = 1.0 / axis.inertia;
  a(0, 1) = 1.0;
  a(1, 0) = -axis.stiffness * inv_m;
  a(1, 1) = -axis.damping * inv_m;
  a(1, 2) = axis.stiffness * inv_m;
  a(1, 3) = axis.damping * inv_m;
  a(1, 4) = inv_m;
  a(2, 3) = 1.0;
  const Eigen::Matrix<double, 5, 5> phi = (a * dt).exp();
  AxisPropagator propagator;
  for (int row = 0; row < 2; ++row) {
    for (int col = 0; col < 5; ++col) propagator.phi[row * 5 + col] = phi(row, col);
  }
  return propagator;
}

LumpedModelParams MakeLumpedModelParams(const Chair& chair, double load_kg) {
  PWSIM_DEMAND(chair.lm.has_value());
  LumpedModelParams params;
  params.heave = {MovingMass(chair, load_kg), chair.lm->c_z, chair.lm->k_z};
  params.pitch = {PitchInertia(chair, load_kg), chair.lm->c_theta, chair.lm->k_theta};
  return params;
}

DiscreteLumpedModel Discretize(const LumpedModelParams& params, double dt) {
  DiscreteLumpedModel model;
  model.params = params;
  model.dt = dt;
  model.inv_dt = 1.0 / dt;
  model.heave = MakeAxisPropagator(params.heave, dt);
  model.pitch = MakeAxisPropagator(params.pitch, dt);
  return model;
}

}  // namespace pwsim
