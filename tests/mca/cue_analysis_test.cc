#include "mca/cue_analysis.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pwsim::mca {
namespace {

// Tests delivered head motion: a neutral platform delivers rest, a heave sinusoid delivers its
// second derivative, a static pitch delivers g sin θ in surge and a pitch rate w_y = -θ̇.
TEST(CueAnalysisTest, DeliveredHeadMotionClosedForms) {
  const PlatformSpec platform = MakePw4DofPlatform();
  const double dt = 1e-3;
  std::vector<DofArray> poses(2000);
  EXPECT_EQ(DeliveredHeadMotion(platform, poses, dt)[1000], HeadMotion{});
  for (std::size_t k = 0; k < poses.size(); ++k) {
    poses[k] = {};
    poses[k][Index(Dof::kHeave)] = 0.02 * std::sin(3.0 * static_cast<double>(k) * dt);
  }
  const std::vector<HeadMotion> heave = DeliveredHeadMotion(platform, poses, dt);
  for (std::size_t k = 1; k + 1 < poses.size(); k += 111) {
    EXPECT_NEAR(heave[k].fs[2] - kGravity, -0.18 * std::sin(3.0 * static_cast<double>(k) * dt), 1e-5);
  }
  const double theta = 0.05, rate = 0.02;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    poses[k] = {};
    poses[k][Index(Dof::kPitch)] = theta + rate * static_cast<double>(k) * dt;
  }
  const std::vector<HeadMotion> pitch = DeliveredHeadMotion(platform, poses, dt);
  const double th = theta + rate * 1.0;
  // head at (hx, hz) above the pivot: centripetal -θ̇² r adds a little at the head
  const auto& h = platform.head_from_pivot;
  const double expected_x = kGravity * std::sin(th) - rate * rate * h[0];
  EXPECT_NEAR(pitch[1000].fs[0], expected_x, 1e-6);
  EXPECT_NEAR(pitch[1000].w[1], -rate, 1e-9);
  EXPECT_NEAR(pitch[1000].w[0], 0.0, 1e-12);
}

// Tests the metrics on synthetic signals with known correlation, gain, lag and wrong signs.
TEST(CueAnalysisTest, MetricsOnKnownSignals) {
  const double dt = 1e-2;
  std::vector<double> truth(3000), platform(3000);
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const double t = static_cast<double>(k) * dt;
    truth[k] = std::sin(0.9 * t);
    platform[k] = 0.5 * std::sin(0.9 * (t - 0.2));  // half the gain, 0.2 s late
  }
  const AxisConsistency c = CompareAxis(truth, platform, 0.05, dt, 1.0);
  EXPECT_NEAR(c.lag, 0.2, 1e-9);
  EXPECT_NEAR(c.gain, 0.5, 5e-3);
  EXPECT_NEAR(c.correlation, std::cos(0.9 * 0.2), 5e-3);
  EXPECT_GT(c.wrong_sign_count, 0);  // the late half-wave opposes the truth near zero crossings

  std::vector<double> inverted(truth.size());
  for (std::size_t k = 0; k < truth.size(); ++k) inverted[k] = -truth[k];
  const AxisConsistency w = CompareAxis(truth, inverted, 0.5, dt, 0.0);
  EXPECT_NEAR(w.correlation, -1.0, 1e-12);
  EXPECT_NEAR(w.rms_error, 2.0 * std::sqrt(0.5), 1e-2);
  EXPECT_GT(w.wrong_sign_duration, 0.5 * 3000 * dt);

  const std::array<double, 2> xc = MaxCrossCorrelation(truth, platform, dt, 1.0);
  EXPECT_NEAR(xc[0], 1.0, 1e-3);
  EXPECT_NEAR(xc[1], 0.2, 1e-9);
}

// Tests tilt-rate episode counting.
TEST(CueAnalysisTest, RateAboveThreshold) {
  const double dt = 1e-3, thr = 3.0 * kDegToRad;
  std::vector<double> angle(3000, 0.0);
  for (std::size_t k = 1; k < angle.size(); ++k) {
    const bool fast = (k >= 500 && k < 700) || (k >= 2000 && k < 2100);
    angle[k] = angle[k - 1] + (fast ? 2.0 * thr : thr) * dt;
  }
  const RateCues r = RateAbove(angle, thr, dt);
  EXPECT_EQ(r.count, 2);
  EXPECT_NEAR(r.duration, 0.3, 1e-9);
  EXPECT_NEAR(r.max_rate, 2.0 * thr, 1e-9);
}

}  // namespace
}  // namespace pwsim::mca
