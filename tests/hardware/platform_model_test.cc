#include "hardware/platform_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pwsim::hw {
namespace {

TEST(PlatformModel, MassMatrixAndCoriolisFollowSeedEquations) {
  const PlatformParams p;
  double m[2][2];
  PlatformMassMatrix(p, {0.3, 0.1}, m);
  const double arm = p.x_g2 + 0.1;
  EXPECT_DOUBLE_EQ(m[0][0], p.m1 * p.r_g1_sq + p.inertia_zz + p.m2 * p.y_g2 * p.y_g2 + p.m2 * arm * arm);
  EXPECT_DOUBLE_EQ(m[0][1], -p.m2 * p.y_g2);
  EXPECT_DOUBLE_EQ(m[1][0], m[0][1]);
  EXPECT_DOUBLE_EQ(m[1][1], p.m2);
  EXPECT_GT(m[0][0] * m[1][1] - m[0][1] * m[1][0], 0.0);
  const auto c = PlatformCoriolis(p, {0.0, 0.1}, {0.5, 0.2});
  EXPECT_DOUBLE_EQ(c[0], 2.0 * p.m2 * arm * 0.5 * 0.2);
  EXPECT_DOUBLE_EQ(c[1], -p.m2 * arm * 0.25);
  const auto f = PlatformFriction(p, {1.0, -2.0});
  EXPECT_NEAR(f[0], p.ks1 + p.kv1, 1e-9);
  EXPECT_NEAR(f[1], -p.ks2 - 2.0 * p.kv2, 1e-9);
}

TEST(PlatformModel, CoastingLosesEnergyToFriction) {
  PlatformPlant plant;
  PlatformState s;
  s.qd = {0.2, 0.5};
  plant.set_state(s);
  double m[2][2];
  auto energy = [&](const PlatformState& x) {
    PlatformMassMatrix(plant.params(), x.q, m);
    return 0.5 * (m[0][0] * x.qd[0] * x.qd[0] + 2 * m[0][1] * x.qd[0] * x.qd[1] + m[1][1] * x.qd[1] * x.qd[1]);
  };
  const double e0 = energy(plant.state());
  plant.Advance(1.0, plant.state().q, /*enabled=*/false);
  const double e1 = energy(plant.state());
  EXPECT_LT(e1, e0);
  EXPECT_GT(e1, 0.9 * e0);  // the identified friction is small
}

TEST(PlatformModel, PidTracksAStepWithinTheSeedBandwidth) {
  PlatformPlant plant;
  plant.ResetTarget({0.0, 0.0});
  for (int k = 0; k < 250; ++k) plant.Advance(0.004, {0.05, 0.1}, true);  // 1 s
  EXPECT_NEAR(plant.state().q[0], 0.05, 1e-3);
  EXPECT_NEAR(plant.state().q[1], 0.1, 1e-3);
  EXPECT_LT(std::abs(plant.state().qd[1]), 0.01);
}

}  // namespace
}  // namespace pwsim::hw
