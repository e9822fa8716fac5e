// Frequency response against known models: a continuous 2nd-order system simulated here (RK4 on
// the analytic chirp), and the whole loop platform-sim chirp → recording files → estimate →
// fitted model against the analytic closed-loop bandwidth of the seed-001 rail joint.
#include "sysid/platform/frequency_response.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>

#include "hardware/platform_chirp.h"

namespace pwsim::sysid::platform {
namespace {

// First ω where |T(jω)| falls to |T(0)|/√2 for T = num/den (descending powers), by scanning.
double AnalyticBandwidth(const std::vector<double>& num, const std::vector<double>& den) {
  auto gain = [&](double w) {
    std::complex<double> s(0, w), n(0, 0), d(0, 0);
    for (double c : num) n = n * s + c;
    for (double c : den) d = d * s + c;
    return std::abs(n / d);
  };
  const double target = gain(0.0) / std::sqrt(2.0);
  for (double w = 0.01; w < 1e5; w *= 1.00001)
    if (gain(w) < target) return w;
  return 0.0;
}

AxisRecording SecondOrderChirp(double wn, double zeta, double noise_std, std::uint64_t seed) {
  const double w0 = 1.0, w1 = 400.0, ts = 20.0, T = 0.001;
  const int sweeps = 3;
  const double ratio = std::log(w1 / w0);
  auto u = [&](double t) {
    const double tt = std::fmod(t, ts);
    const double g = std::exp(tt / ts * ratio);
    return std::sin(w0 * ts / ratio * (g - 1.0));
  };
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  AxisRecording r;
  r.file = "second-order.yaml";
  r.dt = T;
  JointRecording j;
  j.name = "axis";
  double x = 0.0, v = 0.0;  // ẍ = wn²(u − x) − 2ζwn ẋ
  const int sub = 20;
  const double h = T / sub;
  auto f = [&](double t, double xx, double vv) { return wn * wn * (u(t) - xx) - 2.0 * zeta * wn * vv; };
  const int n = static_cast<int>(sweeps * ts / T);
  for (int k = 0; k < n; ++k) {
    const double t = k * T;
    r.t.push_back(t);
    j.reference.push_back(u(t));
    // Measurement noise that grows with frequency content: white on the position.
    j.position.push_back(x + noise_std * n01(rng));
    j.command.push_back(0.0);
    j.effort.push_back(0.0);
    for (int s = 0; s < sub; ++s) {
      const double tt = t + s * h;
      const double k1x = v, k1v = f(tt, x, v);
      const double k2x = v + 0.5 * h * k1v, k2v = f(tt + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v);
      const double k3x = v + 0.5 * h * k2v, k3v = f(tt + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v);
      const double k4x = v + h * k3v, k4v = f(tt + h, x + h * k3x, v + h * k3v);
      x += h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
      v += h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
  }
  r.joints.push_back(std::move(j));
  return r;
}

TEST(FrequencyResponse, RecoversAKnownSecondOrderSystem) {
  const double wn = 60.0, zeta = 0.4;
  FrequencyResponseOptions o;
  o.sweeps = 3;
  const auto fr = EstimateFrequencyResponse({SecondOrderChirp(wn, zeta, 0.0, 1)}, o);
  ASSERT_EQ(fr.size(), 1u);
  ASSERT_FALSE(fr[0].fits.empty());
  const FrequencyFit& f2 = fr[0].fits[0];
  ASSERT_EQ(f2.order, 2);
  EXPECT_GT(f2.fit_pct, 99.0);
  EXPECT_NEAR(std::sqrt(f2.den[2]), wn, 0.01 * wn);
  EXPECT_NEAR(f2.den[1] / (2.0 * std::sqrt(f2.den[2])), zeta, 0.02);
  const double truth = AnalyticBandwidth({wn * wn}, {1.0, 2.0 * zeta * wn, wn * wn});
  EXPECT_NEAR(fr[0].bandwidth_rad_s, truth, 0.03 * truth);
  EXPECT_NEAR(fr[0].bandwidth_nonparametric_rad_s, truth, 0.03 * truth);
}

TEST(FrequencyResponse, CoherenceFallsWhereNoiseDominates) {
  FrequencyResponseOptions o;
  o.sweeps = 3;
  const auto fr = EstimateFrequencyResponse({SecondOrderChirp(60.0, 0.4, 2e-3, 2)}, o);
  ASSERT_EQ(fr.size(), 1u);
  double low = 1.0, high = 1.0;
  for (const auto& p : fr[0].points) {
    if (p.w_rad_s < 20.0) low = std::min(low, p.coherence);
    if (p.w_rad_s > 300.0) high = std::min(high, p.coherence);
  }
  EXPECT_GT(low, 0.95);
  EXPECT_LT(high, 0.8);  // the output falls as 1/ω² beyond ωn while the noise stays white
  bool some_not_fitted = false;
  for (const auto& p : fr[0].points) some_not_fitted = some_not_fitted || !p.fitted;
  EXPECT_TRUE(some_not_fitted);
}

class PlatformChirp : public ::testing::TestWithParam<int> {};

TEST_P(PlatformChirp, LoopRecoversTheJointBandwidth) {
  // platform-sim's chirp → recording files → estimate, against the analytic closed loop of the
  // joint: I s² q = kp e + ki e/s + kd (s r − s q) − kv s q (hardware/platform_model.cc gains,
  // I the nominal inertia with the cabin at the rail's centre).
  const int joint = GetParam();
  hw::ChirpParams c;
  c.joint = joint;
  c.sweep_s = 20.0;
  c.sweeps = 3;
  const hw::PlatformParams platform;
  const hw::ChirpRecord rec = hw::RunChirp(c, platform);
  AxisRecording r;
  EXPECT_EQ(rec.saturated_samples, 0);
  r.file = std::filesystem::path(PWSIM_BINARY_DIR) / "test-frequency-response" /
           ("chirp" + std::to_string(joint) + ".yaml");
  r.experiment = "chirp";
  r.t = rec.t;
  r.dt = c.sample_s;
  for (std::size_t j = 0; j < 2; ++j) {
    JointRecording jr;
    jr.name = j == 0 ? "yaw" : "rail";
    jr.kind = j == 0 ? JointKind::kRevolute : JointKind::kPrismatic;
    jr.position = rec.q[j];
    jr.reference = rec.q_ref[j];
    jr.command = rec.tau[j];
    jr.effort = rec.tau[j];
    r.joints.push_back(jr);
  }
  WriteAxisRecordingCsv(r, r.file);
  FrequencyResponseOptions o;
  o.sweeps = 3;
  const auto fr = EstimateFrequencyResponse({ReadAxisRecording(r.file)}, o);
  ASSERT_EQ(fr.size(), 1u);  // the other joint's reference does not move
  EXPECT_EQ(fr[0].joint, joint == 0 ? "yaw" : "rail");
  const double m = joint == 0 ? platform.m1 * platform.r_g1_sq + platform.inertia_zz +
                                    platform.m2 * (platform.x_g2 * platform.x_g2 + platform.y_g2 * platform.y_g2)
                              : platform.m2;
  const double kv = joint == 0 ? platform.kv1 : platform.kv2;
  const double w = 2.0 * M_PI * 8.0;
  const double kp = m * w * w, ki = m * w * w * w / 10.0, kd = 2.0 * m * w;
  const double truth = AnalyticBandwidth({kd, kp, ki}, {m, kd + kv, kp, ki});
  EXPECT_NEAR(fr[0].bandwidth_rad_s, truth, 0.03 * truth);
}

INSTANTIATE_TEST_SUITE_P(YawAndRail, PlatformChirp, ::testing::Values(0, 1));

}  // namespace
}  // namespace pwsim::sysid::platform
