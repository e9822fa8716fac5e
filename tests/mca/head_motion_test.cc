#include "mca/head_motion.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pwsim::mca {
namespace {

ChairSample Sample(double a, double pitch, double pitch_rate, double pitch_acc, double z_acc = 0.0) {
  ChairSample s;
  s.drive.a = a;
  s.lm.pitch = pitch;
  s.lm.pitch_rate = pitch_rate;
  s.lm_acc.pitch = pitch_acc;
  s.lm_acc.z = z_acc;
  return s;
}

// Tests the rest, pure-acceleration and static-tilt cases of the specific force at the head.
TEST(HeadMotionTest, SpecificForceClosedForms) {
  const std::array<double, 3> head{0.05, 0.0, 1.25};
  const HeadMotion rest = HeadMotionFromChair(Sample(0, 0, 0, 0), head);
  EXPECT_EQ(rest, HeadMotion{});
  const HeadMotion accel = HeadMotionFromChair(Sample(0.8, 0, 0, 0, 0.3), head);
  EXPECT_DOUBLE_EQ(accel.fs[0], 0.8);
  EXPECT_DOUBLE_EQ(accel.fs[2], kGravity + 0.3);
  const double theta = 0.1;
  const HeadMotion tilt = HeadMotionFromChair(Sample(0, theta, 0, 0), head);
  EXPECT_NEAR(tilt.fs[0], kGravity * std::sin(theta), 1e-12);  // nose-up: pressed back
  EXPECT_NEAR(tilt.fs[2], kGravity * std::cos(theta), 1e-12);
}

// Tests the rotational terms: centripetal -θ̇² p and tangential θ̈ × p, and w_y = -θ̇.
TEST(HeadMotionTest, RotationTermsAtTheHead) {
  const std::array<double, 3> head{0.0, 0.0, 1.25};
  const HeadMotion spin = HeadMotionFromChair(Sample(0, 0, 1.0, 0), head);
  EXPECT_NEAR(spin.fs[2], kGravity - 1.25, 1e-12);
  EXPECT_DOUBLE_EQ(spin.w[1], -1.0);
  const HeadMotion angular = HeadMotionFromChair(Sample(0, 0, 0, 2.0), head);
  EXPECT_NEAR(angular.fs[0], -2.5, 1e-12);  // nose-up angular acceleration throws the head back
}

// Tests that differentiating a smooth pose track recovers the analytic head motion.
TEST(HeadMotionTest, TrackDifferentiation) {
  const std::array<double, 3> head{0.05, 0.0, 1.25};
  SagittalTrack track;
  track.dt = 1e-3;
  for (int k = 0; k < 4000; ++k) {
    const double t = k * track.dt;
    track.x.push_back(0.4 * t * t);
    track.z.push_back(0.02 * std::sin(3.0 * t));
    track.pitch.push_back(0.05 * std::sin(2.0 * t));
  }
  const std::vector<HeadMotion> dut = HeadMotionFromTrack(track, head);
  for (int k = 10; k < 3990; k += 97) {
    const double t = k * track.dt;
    const ChairSample s = [&] {
      ChairSample c = Sample(0.8, 0.05 * std::sin(2.0 * t), 0.1 * std::cos(2.0 * t),
                             -0.2 * std::sin(2.0 * t), -0.18 * std::sin(3.0 * t));
      return c;
    }();
    const HeadMotion expected = HeadMotionFromChair(s, head);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(dut[static_cast<std::size_t>(k)].fs[i], expected.fs[i], 1e-4) << k;
      EXPECT_NEAR(dut[static_cast<std::size_t>(k)].w[i], expected.w[i], 1e-5) << k;
    }
  }
}

}  // namespace
}  // namespace pwsim::mca
