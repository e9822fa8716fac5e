#include "engine/drive_profile.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pwsim {
namespace {

// Tests that x(t) is continuous, v = dx/dt, and the drive stops exactly at stop_x.
TEST(DriveProfileTest, ContinuousAndConsistent) {
  const DriveProfile dut{0.0, 0.5, 2.4, 1.0, 0.8, 8.0};
  ASSERT_EQ(dut.Validate(), "");
  double previous_x = EvaluateDrive(dut, 0.0).x;
  for (double t = 1e-3; t < dut.StopTime() + 1.0; t += 1e-3) {
    const Longitudinal now = EvaluateDrive(dut, t);
    EXPECT_LT(std::abs(now.x - previous_x), 2.4e-3 + 1e-9);
    const Longitudinal later = EvaluateDrive(dut, t + 1e-6);
    EXPECT_NEAR((later.x - now.x) / 1e-6, now.v, 2e-5);
    previous_x = now.x;
  }
  EXPECT_DOUBLE_EQ(EvaluateDrive(dut, dut.StopTime() + 0.1).x, 8.0);
  EXPECT_NEAR(EvaluateDrive(dut, dut.StopTime() - 1e-9).x, 8.0, 1e-6);
  EXPECT_EQ(PhaseAt(dut, 1.0), DrivePhase::kAccelerate);
  EXPECT_EQ(PhaseAt(dut, dut.AccelEndTime() + 0.1), DrivePhase::kCruise);
  EXPECT_EQ(PhaseAt(dut, dut.StopTime() - 0.1), DrivePhase::kDecelerate);
}

// Tests that a path too short to reach the speed and stop is reported.
TEST(DriveProfileTest, RejectsTooShortPath) {
  const DriveProfile dut{0.0, 0.5, 2.4, 0.5, 0.5, 3.0};
  EXPECT_NE(dut.Validate().find("stop_x_m"), std::string::npos);
}

}  // namespace
}  // namespace pwsim
