#include "engine/controller_profile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/input_error.h"

namespace pwsim {
namespace {

// Tests the targets against the profile's closed form: s(d) = (|d| - d0)/(1 - d0) signed,
// v = s(f) v_fwd (v_rev backwards), ω = clamp(G s(t)) ω_max (1 - (1 - ρ) |v| / v_fwd).
TEST(ControllerProfileTest, TargetsFollowTheProfile) {
  ControllerProfile p;
  p.deadband = 0.1;
  p.turn_gain = 1.5;
  const double s = (0.55 - 0.1) / 0.9;
  ControllerState target = ControllerTarget(p, {0.55, -0.55});
  EXPECT_DOUBLE_EQ(target.speed, s * p.max_forward_speed);
  EXPECT_DOUBLE_EQ(target.yaw_rate, -1.5 * s * p.max_turn_rate * (1.0 - (1.0 - p.turn_rate_at_speed) * s));
  target = ControllerTarget(p, {-1.0, 1.0});
  EXPECT_DOUBLE_EQ(target.speed, -p.max_reverse_speed);
  EXPECT_DOUBLE_EQ(target.yaw_rate, p.max_turn_rate * (1.0 - (1.0 - p.turn_rate_at_speed) * p.max_reverse_speed / p.max_forward_speed));
  EXPECT_EQ(ControllerTarget(p, {0.08, -0.09}).speed, 0.0);  // deadband
  p.exponent = 2.0;
  EXPECT_DOUBLE_EQ(ControllerTarget(p, {0.55, 0.0}).speed, s * s * p.max_forward_speed);
}

// Tests the ramps: from rest at full forward the set-point grows by a_acc dt per tick until
// v_fwd; releasing shrinks it by a_dec dt; full reverse from forward first shrinks to 0 at the
// forward deceleration, then grows backwards at the reverse acceleration.
TEST(ControllerProfileTest, SetpointsRampAtTheProgrammedRates) {
  ControllerProfile p;
  const double dt = 1e-3;
  ControllerState s;
  for (int k = 1; k <= 1000; ++k) {
    s = StepController(p, s, {1.0, 0.0}, dt);
    ASSERT_NEAR(s.speed, std::min(p.forward_accel * k * dt, p.max_forward_speed), 1e-12);
  }
  EXPECT_NEAR(s.accel, p.forward_accel, 1e-9);
  for (int k = 0; k < 3000; ++k) s = StepController(p, s, {1.0, 0.0}, dt);
  EXPECT_EQ(s.speed, p.max_forward_speed);
  const ControllerState released = StepController(p, s, {0.0, 0.0}, dt);
  EXPECT_NEAR(released.accel, -p.forward_decel, 1e-9);
  int ticks_to_zero = 0;
  while (s.speed > 0.0) {
    s = StepController(p, s, {-1.0, 0.0}, dt);
    ++ticks_to_zero;
  }
  EXPECT_NEAR(ticks_to_zero * dt, p.max_forward_speed / p.forward_decel, 2e-3);
  s = StepController(p, s, {-1.0, 0.0}, dt);
  EXPECT_NEAR(s.speed, -p.reverse_accel * dt, 1e-12);
}

// Tests the safe reaction of the real-time path: NaN or out-of-range deflections read as 0.
TEST(ControllerProfileTest, BadDeflectionsReadAsCentred) {
  ControllerProfile p;
  EXPECT_EQ(ControllerTarget(p, {std::numeric_limits<double>::quiet_NaN(), 1.7}).speed, 0.0);
  EXPECT_EQ(ControllerTarget(p, {std::numeric_limits<double>::quiet_NaN(), 1.7}).yaw_rate, 0.0);
}

// Tests that a negative acceleration in a profile file names its field and what was expected.
TEST(ControllerProfileTest, NegativeAccelerationIsAnErrorNamingTheField) {
  const YamlDocument doc = LoadYamlString("controller:\n  max_forward_speed_mps: 1.5\n  forward_decel_mps2: -0.5\n", "profile.yaml");
  YamlMap root(doc.root, doc.file, "");
  YamlMap map = root.Map("controller");
  try {
    ParseControllerProfile(map);
    FAIL() << "accepted a negative deceleration";
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), "controller.forward_decel_mps2");
    EXPECT_EQ(error.line(), 3);
    EXPECT_NE(std::string(error.what()).find("positive"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace pwsim
