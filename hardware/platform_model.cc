#include "hardware/platform_model.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"

namespace pwsim::hw {

void PlatformMassMatrix(const PlatformParams& p, const std::array<double, 2>& q, double m[2][2]) {
  const double arm = p.x_g2 + q[1];
  m[0][0] = p.m1 * p.r_g1_sq + p.inertia_zz + p.m2 * p.y_g2 * p.y_g2 + p.m2 * arm * arm;
  m[0][1] = -p.m2 * p.y_g2;
  m[1][0] = m[0][1];
  m[1][1] = p.m2;
}

std::array<double, 2> PlatformCoriolis(const PlatformParams& p, const std::array<double, 2>& q,
                                       const std::array<double, 2>& qd) {
  const double arm = p.x_g2 + q[1];
  return {2.0 * p.m2 * arm * qd[0] * qd[1], -p.m2 * arm * qd[0] * qd[0]};
}

std::array<double, 2> PlatformFriction(const PlatformParams& p, const std::array<double, 2>& qd) {
  auto sgn = [&](double v) { return std::tanh(v / p.dry_velocity_eps); };
  return {p.ks1 * sgn(qd[0]) + p.kv1 * qd[0], p.ks2 * sgn(qd[1]) + p.kv2 * qd[1]};
}

std::array<double, 2> PlatformAcceleration(const PlatformParams& p, const PlatformState& s,
                                           const std::array<double, 2>& tau) {
  double m[2][2];
  PlatformMassMatrix(p, s.q, m);
  const auto c = PlatformCoriolis(p, s.q, s.qd);
  const auto f = PlatformFriction(p, s.qd);
  const double r0 = tau[0] - f[0] - c[0];
  const double r1 = tau[1] - f[1] - c[1];
  const double det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  PWSIM_DEMAND(det > 0.0);
  return {(m[1][1] * r0 - m[0][1] * r1) / det, (m[0][0] * r1 - m[1][0] * r0) / det};
}

PlatformPlant::PlatformPlant(PlatformParams params, double substep)
    : params_(params), substep_(substep) {
  PWSIM_DEMAND(substep > 0.0);
  // Critically damped joints at ~8 Hz on the nominal inertias (yaw with the cabin centred).
  const double w = 2.0 * M_PI * 8.0;
  double m[2][2];
  PlatformMassMatrix(params_, {0.0, 0.0}, m);
  for (int i = 0; i < 2; ++i) {
    const double inertia = m[i][i];
    gains_[static_cast<std::size_t>(i)] = {inertia * w * w, inertia * w * w * w / 10.0,
                                           2.0 * inertia * w};
  }
}

void PlatformPlant::ResetTarget(const std::array<double, 2>& target) {
  previous_target_ = target;
  state_.integral = {0.0, 0.0};
}

void PlatformPlant::Advance(double duration, const std::array<double, 2>& target, bool enabled,
                            std::array<AxisEnvelope, 2>* envelope) {
  const int steps = std::max(1, static_cast<int>(std::lround(duration / substep_)));
  const double h = duration / steps;
  const std::array<double, 2> limit{params_.tau1_max, params_.tau2_max};
  std::array<double, 2> v_ref{};
  for (std::size_t i = 0; i < 2; ++i) v_ref[i] = (target[i] - previous_target_[i]) / duration;
  for (int k = 1; k <= steps; ++k) {
    const double alpha = static_cast<double>(k) / steps;
    std::array<double, 2> tau{};
    if (enabled) {
      for (std::size_t i = 0; i < 2; ++i) {
        const double ref = previous_target_[i] + alpha * (target[i] - previous_target_[i]);
        const double e = ref - state_.q[i];
        const JointPid& g = gains_[i];
        // Anti-windup: the integral term may supply at most 20 % of the actuator's effort.
        const double i_max = g.ki > 0.0 ? 0.2 * limit[i] / g.ki : 0.0;
        state_.integral[i] = std::clamp(state_.integral[i] + e * h, -i_max, i_max);
        tau[i] = std::clamp(g.kp * e + g.ki * state_.integral[i] + g.kd * (v_ref[i] - state_.qd[i]),
                            -limit[i], limit[i]);
      }
    }
    const auto acc = PlatformAcceleration(params_, state_, tau);
    for (std::size_t i = 0; i < 2; ++i) {  // semi-implicit Euler
      state_.qd[i] += acc[i] * h;
      state_.q[i] += state_.qd[i] * h;
    }
    state_.qdd = acc;
    state_.tau = tau;
    if (envelope) {
      for (std::size_t i = 0; i < 2; ++i) (*envelope)[i].Add(state_.q[i], state_.qd[i], acc[i], tau[i]);
    }
  }
  previous_target_ = target;
}

}  // namespace pwsim::hw
