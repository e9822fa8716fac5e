#include "tests/sysid/platform/truth_rail_yaw.h"

#include <Eigen/Dense>
#include <cmath>

namespace pwsim::test {
namespace {

// Centre-of-mass Jacobians in the horizontal plane: p1 = R(q1) (x_g1, y_g1),
// p2 = R(q1) (x_g2 + q2, y_g2).
Eigen::Matrix2d MassMatrix(const RailYawTruth& t, const Eigen::Vector2d& q) {
  const double c = std::cos(q(0)), s = std::sin(q(0));
  Eigen::Matrix2d j1, j2;
  // d p1 / d q1 = R'(q1) r1, d p1 / d q2 = 0
  j1 << -s * t.x_g1 - c * t.y_g1, 0.0, c * t.x_g1 - s * t.y_g1, 0.0;
  const double x = t.x_g2 + q(1);
  j2 << -s * x - c * t.y_g2, c, c * x - s * t.y_g2, s;
  Eigen::Matrix2d m = t.m1 * j1.transpose() * j1 + t.m2 * j2.transpose() * j2;
  m(0, 0) += t.izz;
  return m;
}

// c_i = Σ_jk (∂M_ij/∂q_k − ½ ∂M_jk/∂q_i) q̇_j q̇_k, derivatives by central differences.
Eigen::Vector2d Coriolis(const RailYawTruth& t, const Eigen::Vector2d& q, const Eigen::Vector2d& qd) {
  const double h = 1e-6;
  Eigen::Matrix2d dm[2];
  for (int k = 0; k < 2; ++k) {
    Eigen::Vector2d a = q, b = q;
    a(k) += h;
    b(k) -= h;
    dm[k] = (MassMatrix(t, a) - MassMatrix(t, b)) / (2.0 * h);
  }
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) c(i) += (dm[k](i, j) - 0.5 * dm[i](j, k)) * qd(j) * qd(k);
  return c;
}

}  // namespace

sysid::platform::AxisRecording SimulateRailYaw(const RailYawTruth& t) {
  auto ref = [](double time, int joint, int derivative) {
    // q1 = 0.4 sin 1.3t + 0.2 sin(3.1t + 1), q2 = 0.3 sin 0.9t + 0.15 sin(2.3t + 0.5)
    const double a1 = joint == 0 ? 0.4 : 0.3, w1 = joint == 0 ? 1.3 : 0.9;
    const double a2 = joint == 0 ? 0.2 : 0.15, w2 = joint == 0 ? 3.1 : 2.3, p2 = joint == 0 ? 1.0 : 0.5;
    if (derivative == 0) return a1 * std::sin(w1 * time) + a2 * std::sin(w2 * time + p2);
    return a1 * w1 * std::cos(w1 * time) + a2 * w2 * std::cos(w2 * time + p2);
  };
  const double T = 0.001, h = 2e-5;
  const int sub = 50;
  const int n = static_cast<int>(std::lround(t.duration / T)) + 1;
  Eigen::Vector2d q(ref(0, 0, 0), ref(0, 1, 0)), qd(ref(0, 0, 1), ref(0, 1, 1));
  const double kp[2] = {4.0e4, 3.0e5}, kd[2] = {1.5e3, 8.0e3};
  sysid::platform::AxisRecording rec;
  rec.file = "rail-yaw-truth.yaml";
  rec.dt = T;
  sysid::platform::JointRecording yaw, rail;
  yaw.name = "yaw";
  yaw.kind = sysid::platform::JointKind::kRevolute;
  rail.name = "rail";
  rail.kind = sysid::platform::JointKind::kPrismatic;
  auto torque = [&](double time) {
    Eigen::Vector2d tau;
    for (int i = 0; i < 2; ++i)
      tau(i) = kp[i] * (ref(time, i, 0) - q(i)) + kd[i] * (ref(time, i, 1) - qd(i));
    return tau;
  };
  for (int k = 0; k < n; ++k) {
    const double tk = k * T;
    const Eigen::Vector2d tau = torque(tk);
    rec.t.push_back(tk);
    yaw.position.push_back(q(0));
    rail.position.push_back(q(1));
    yaw.command.push_back(tau(0));
    rail.command.push_back(tau(1));
    for (int s = 0; s < sub; ++s) {
      const Eigen::Vector2d u = torque(tk + s * h);
      Eigen::Vector2d f;
      f(0) = t.fv1 * qd(0) + t.fc1 * std::tanh(qd(0) / 1e-3);
      f(1) = t.fv2 * qd(1) + t.fc2 * std::tanh(qd(1) / 1e-3);
      const Eigen::Vector2d acc = MassMatrix(t, q).ldlt().solve(u - f - Coriolis(t, q, qd));
      qd += acc * h;
      q += qd * h;
    }
  }
  yaw.effort = yaw.command;
  rail.effort = rail.command;
  rec.joints.push_back(std::move(yaw));
  rec.joints.push_back(std::move(rail));
  return rec;
}

}  // namespace pwsim::test
