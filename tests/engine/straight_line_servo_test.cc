#include "engine/straight_line_servo.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace pwsim {
namespace {

double MaxLateral(const ServoParams& params, double seconds, double* final_y) {
  ServoState state;
  double max_y = 0.0;
  const double dt = 1e-3;
  for (int tick = 0; tick < static_cast<int>(seconds / dt); ++tick) {
    state = StepServo(params, state, 1.2, dt);
    max_y = std::max(max_y, std::abs(state.y));
  }
  *final_y = state.y;
  return max_y;
}

// Tests Fig. 4: without the PI correction a yaw bias makes |y| grow without bound
// (quadratically), with it |y| stays bounded near ω_d/k_i.
TEST(StraightLineServoTest, CorrectionBoundsLateralDrift) {
  ServoParams open_loop;
  open_loop.enabled = false;
  double y_open_10 = 0.0, y_open_20 = 0.0;
  MaxLateral(open_loop, 10.0, &y_open_10);
  MaxLateral(open_loop, 20.0, &y_open_20);
  EXPECT_GT(std::abs(y_open_20), 3.0 * std::abs(y_open_10));  // grows ~t²
  EXPECT_GT(std::abs(y_open_20), 1.0);

  ServoParams closed_loop;
  double y_closed_20 = 0.0, y_closed_60 = 0.0;
  const double max_20 = MaxLateral(closed_loop, 20.0, &y_closed_20);
  const double max_60 = MaxLateral(closed_loop, 60.0, &y_closed_60);
  EXPECT_LT(max_60, 0.1);
  EXPECT_NEAR(max_60, max_20, 1e-3);  // bounded: no further growth
  EXPECT_NEAR(y_closed_60, closed_loop.drift_yaw_rate / closed_loop.ki, 1e-3);
}

// Tests that a lateral slip is also rejected (ẏ driven back to zero).
TEST(StraightLineServoTest, LateralSlipRejected) {
  ServoParams params;
  params.drift_yaw_rate = 0.0;
  params.drift_lateral = 0.05;
  ServoState state;
  for (int tick = 0; tick < 30000; ++tick) state = StepServo(params, state, 1.2, 1e-3);
  const double y_rate = 1.2 * std::sin(state.yaw) + params.drift_lateral;
  EXPECT_NEAR(y_rate, 0.0, 1e-4);
  EXPECT_LT(std::abs(state.y), 0.2);
}

}  // namespace
}  // namespace pwsim
