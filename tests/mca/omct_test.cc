#include "mca/omct.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

namespace pwsim::mca {
namespace {

// Tests the 12 OMCT frequencies 10^(k/5), 0.1 .. 15.85 rad/s.
TEST(OmctTest, Frequencies) {
  const std::array<double, 12> f = OmctFrequencies();
  EXPECT_DOUBLE_EQ(f.front(), 0.1);
  EXPECT_NEAR(f[5], 1.0, 1e-15);
  EXPECT_NEAR(f.back(), 15.848931924611133, 1e-12);
  for (std::size_t i = 1; i < f.size(); ++i) EXPECT_NEAR(f[i] / f[i - 1], std::pow(10.0, 0.2), 1e-12);
}

// Tests that a direct heave test equals the continuous design (s² · channel) within 1e-3 at
// chosen frequencies, through the limiter (inside its limits) and the head kinematics.
TEST(OmctTest, HeaveMatchesContinuousDesign) {
  const WashoutParams params = DefaultWashoutParams();
  const PlatformSpec platform = MakePw4DofPlatform();
  const ContinuousSystem channel = ChannelSystem(params, Dof::kHeave);
  OmctOptions options;
  options.settle_min = 10.0;
  for (double w : {0.631, 2.512, 10.0}) {
    const OmctPoint p = RunOmctPoint(OmctTests()[5], w, params, platform, options);
    ASSERT_EQ(p.test, "fz_to_fz");
    const std::complex<double> s(0.0, w);
    const std::complex<double> expected = s * s * channel.Response(w);
    EXPECT_NEAR(p.gain, std::abs(expected), 1e-3) << w;
    EXPECT_NEAR(p.phase * kDegToRad, std::arg(expected), 1e-3) << w;
  }
}

// Tests the roll and yaw direct tests (p→p, r→r) against the continuous design: rate out over
// rate in is s · channel(s) (the channel maps a rate to an angle).
TEST(OmctTest, RollAndYawMatchContinuousDesign) {
  const WashoutParams params = DefaultWashoutParams();
  const PlatformSpec platform = MakePw4DofPlatform();
  OmctOptions options;
  options.settle_min = 10.0;
  for (auto [index, dof] : {std::pair{0, Dof::kRoll}, std::pair{2, Dof::kYaw}}) {
    const ContinuousSystem channel = ChannelSystem(params, dof);
    for (double w : {0.251, 1.0, 6.31}) {
      const OmctPoint p = RunOmctPoint(OmctTests()[static_cast<std::size_t>(index)], w, params, platform, options);
      ASSERT_EQ(p.test, index == 0 ? "p_to_p" : "r_to_r");
      const std::complex<double> expected = std::complex<double>(0.0, w) * channel.Response(w);
      EXPECT_NEAR(p.gain, std::abs(expected), 1e-3) << p.test << " " << w;
      EXPECT_NEAR(p.phase * kDegToRad, std::arg(expected), 1e-3) << p.test << " " << w;
    }
  }
}

// Tests roll tilt coordination in the OMCT (fy→p): at low frequency, inside the tilt-rate
// limit, the roll rate is d/dt asin(LP(s) fy / g) ≈ s · LP(s) / g per unit fy (small angles:
// 0.1 m/s² is 0.58°), with LP = ω²/(s² + 2ζωs + ω²) the tilt low-pass.
TEST(OmctTest, LateralForceToRollRateIsTiltCoordination) {
  const WashoutParams params = DefaultWashoutParams();
  OmctOptions options;
  options.settle_min = 10.0;
  for (double w : {0.1, 0.251}) {
    const OmctPoint p = RunOmctPoint(OmctTests()[7], w, params, MakePw4DofPlatform(), options);
    ASSERT_EQ(p.test, "fy_to_p");
    const std::complex<double> s(0.0, w);
    const double wn = params.tilt_roll.lp_omega, z = params.tilt_roll.lp_zeta;
    const std::complex<double> expected = s * (wn * wn / (s * s + 2.0 * z * wn * s + wn * wn)) / kGravity;
    EXPECT_NEAR(p.gain, std::abs(expected), 2e-3 * std::abs(expected)) << w;
    EXPECT_NEAR(p.phase * kDegToRad, std::arg(expected), 2e-3) << w;
  }
}

// Tests which tests apply to the two platforms of the seeds.
TEST(OmctTest, ApplicableTests) {
  const WashoutParams params = DefaultWashoutParams();
  int pw = 0, car = 0;
  for (const OmctTest& t : OmctTests()) {
    pw += OmctApplies(t, params, MakePw4DofPlatform()) ? 1 : 0;
    car += OmctApplies(t, params, MakeCar2DofPlatform()) ? 1 : 0;
  }
  EXPECT_EQ(pw, 10);  // fx and fy are produced by tilt coordination
  EXPECT_EQ(car, 2);  // fx_to_fx on the rail, r_to_r on the turntable
}


// Tests the OMCT through the MPC (held input) at a mid frequency, 1 rad/s, on both platforms of
// the seeds. Every test: every command inside the travel, gain above 0; a direct test's gain at
// most 1.2 (the MPC may not amplify a cue much beyond one). The direct tests of axes that do not tilt gravity (r, fx, fy,
// fz) give a real cue (gain > 0.05) in the washout's sense (phase within 90° of it, where the
// washout passes the cue with gain above 0.3). Pitch and roll rotations are different: in the
// OMCT they come without a change of specific force, and on the platform every degree of tilt
// is g·θ of false specific force, which the MPC weighs against the rotation cue; so its p→p and
// q→q gains are small and its false-force cross-coupling (p→fy, q→fx) must be below the
// washout's, which passes the rotation and with it the false force.
TEST(OmctTest, MpcAtMidFrequencyIsSane) {
  OmctOptions options;
  options.settle_min = 10.0;
  int compared = 0;
  for (const PlatformSpec& platform : {MakePw4DofPlatform(), MakeCar2DofPlatform()}) {
    McaConfig washout;
    washout.platform = platform;
    McaConfig mpc = washout;
    mpc.algorithm = McaAlgorithm::kMpc;
    ASSERT_TRUE(CheckMpcStart(mpc).empty()) << platform.name;
    for (const OmctTest& test : OmctTests()) {
      if (!OmctApplies(test, mpc)) continue;
      const OmctPoint w = RunOmctPoint(test, 1.0, washout, options);
      const OmctPoint m = RunOmctPoint(test, 1.0, mpc, options);
      const std::string name = test.name;
      const bool direct = test.input == test.output;
      EXPECT_TRUE(m.within_limits) << platform.name << " " << name;
      EXPECT_GT(m.gain, 0.0) << name;
      if (direct) {
        EXPECT_LE(m.gain, 1.2) << name;
      }
      if (name == "q_to_fx" || name == "p_to_fy") {
        EXPECT_LT(m.gain, w.gain) << platform.name << " " << name;
        ++compared;
      }
      const bool tilts = test.input == OmctSignal::kP || test.input == OmctSignal::kQ;
      if (!direct || tilts || w.gain < 0.3) continue;
      ++compared;
      EXPECT_GT(m.gain, 0.05) << platform.name << " " << name;
      double difference = std::fmod(std::abs(m.phase - w.phase), 360.0);
      if (difference > 180.0) difference = 360.0 - difference;
      EXPECT_LT(difference, 90.0) << platform.name << " " << name << ": mpc " << m.phase << " washout " << w.phase;
    }
  }
  EXPECT_EQ(compared, 6);  // pw4dof: r, fx, fy direct, q→fx, p→fy; car2dof: r direct
}

}  // namespace
}  // namespace pwsim::mca
