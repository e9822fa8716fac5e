#include "mca/head_motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

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

// Tests the 3-D pose-track kinematics against a steady left turn of radius R at yaw rate ω: the
// head, 5 cm ahead of O_V and 1.25 m up, circles the turn centre (R to the left of O_V), so
// fs_H = (−0.05 ω², R ω², g) (centripetal towards the centre, x component from the lever) and
// w_H = (0, 0, ω). The track passes yaw ±π, which the matrix differencing must not notice.
TEST(HeadMotionTest, SteadyTurnFromBodyTrackClosedForm) {
  const double radius = 1.5, omega = 0.8, dt = 1e-3;
  const std::array<double, 3> head{0.05, 0.0, 1.25};
  std::vector<DofArray> track;
  for (int k = 0; k <= 10000; ++k) {
    const double t = k * dt;
    const double yaw = std::remainder(omega * t, 2.0 * kPi);  // wrapped to (−π, π]
    track.push_back({radius * std::sin(omega * t), radius * (1.0 - std::cos(omega * t)), 0.0, 0.0,
                     0.0, yaw});
  }
  const std::vector<HeadMotion> m = HeadMotionFromBodyTrack(track, head, dt);
  ASSERT_EQ(m.size(), track.size());
  for (std::size_t k = 0; k < m.size(); k += 7) {
    ASSERT_NEAR(m[k].fs[0], -0.05 * omega * omega, 1e-6) << k;
    ASSERT_NEAR(m[k].fs[1], radius * omega * omega, 1e-6) << k;
    ASSERT_NEAR(m[k].fs[2], kGravity, 1e-6) << k;
    ASSERT_NEAR(m[k].w[0], 0.0, 1e-9) << k;
    ASSERT_NEAR(m[k].w[1], 0.0, 1e-9) << k;
    ASSERT_NEAR(m[k].w[2], omega, 1e-6) << k;
  }
}

// Tests static roll and pitch (gravity seen in tilted axes: left side up φ gives fs_y = g sin φ)
// and a pure roll rate about the body's x axis.
TEST(HeadMotionTest, TiltedAndRollingBodyClosedForms) {
  const double dt = 1e-3, phi = 0.07, theta = -0.04, rate = 0.3;
  std::vector<DofArray> still(5, DofArray{1.0, 2.0, 0.1, phi, theta, 0.4});
  const HeadMotion s = HeadMotionFromBodyTrack(still, {0.0, 0.0, 0.0}, dt)[2];
  EXPECT_NEAR(s.fs[0], kGravity * std::sin(theta), 1e-12);
  EXPECT_NEAR(s.fs[1], kGravity * std::cos(theta) * std::sin(phi), 1e-12);
  EXPECT_NEAR(s.fs[2], kGravity * std::cos(theta) * std::cos(phi), 1e-12);
  std::vector<DofArray> rolling;
  for (int k = 0; k < 5; ++k) rolling.push_back({0.0, 0.0, 0.0, rate * k * dt, 0.0, 0.0});
  const HeadMotion r = HeadMotionFromBodyTrack(rolling, {0.0, 0.0, 1.0}, dt)[2];
  EXPECT_NEAR(r.w[0], rate, 1e-7);  // central difference: sin δ / δ, δ = rate·dt
  EXPECT_NEAR(r.fs[1], kGravity * std::sin(2 * rate * dt), 1e-6);
  EXPECT_NEAR(r.fs[2], kGravity * std::cos(2 * rate * dt) - rate * rate * 1.0, 1e-6);  // centripetal
}

}  // namespace
}  // namespace pwsim::mca
