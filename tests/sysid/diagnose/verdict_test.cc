// The verdict's pieces against closed forms and constructed residuals: the 4th-difference noise
// estimate on a known σ, the noise floor by hand, each residual test failing on exactly the
// structure it is there to see, and the decision table.
#include "sysid/diagnose/verdict.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace pwsim::diagnose {
namespace {

std::vector<double> Noise(std::size_t n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, sigma);
  std::vector<double> v(n);
  for (double& x : v) x = g(rng);
  return v;
}

TEST(NoiseSigmaTest, RecoversTheNoiseUnderASmoothSignalWithKinks) {
  for (double sigma : {3e-4, 1e-3}) {
    std::vector<double> y = Noise(2000, sigma, 7);
    for (std::size_t k = 0; k < y.size(); ++k) {
      const double t = 0.01 * static_cast<double>(k);
      y[k] += 0.03 * std::sin(2.0 * std::numbers::pi * 1.5 * t) + (t > 8.0 ? 0.02 * (t - 8.0) : 0.0);
    }
    EXPECT_NEAR(NoiseSigma(y) / sigma, 1.0, 0.06) << sigma;
  }
  EXPECT_EQ(NoiseSigma(std::vector<double>{1.0, 2.0}), 0.0);
}

TEST(NoiseFloorTest, HandComputed) {
  // y = ±1 alternating (mean 0, ||y - ȳ||² = N), σ = 0.1: floor = 100 (1 - 0.1).
  std::vector<double> y(100);
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = k % 2 ? 1.0 : -1.0;
  EXPECT_NEAR(NoiseFloorFitPct({y, y}, 0.1), 90.0, 1e-9);
}

ResidualRecord Record(std::vector<double> ez, std::vector<double> ep, std::vector<double> u) {
  ResidualRecord r;
  r.name = "trial";
  r.speed = 1.0;
  for (std::size_t k = 0; k < ez.size(); ++k) {
    r.t.push_back(0.01 * static_cast<double>(k));
    r.x.push_back(0.01 * static_cast<double>(k));
  }
  r.e_z = std::move(ez);
  r.e_pitch = std::move(ep);
  r.gm_z = u;
  r.gm_pitch = std::move(u);
  return r;
}

std::vector<double> Input(std::size_t n) {
  std::vector<double> u(n);
  for (std::size_t k = 0; k < n; ++k) u[k] = std::sin(0.02 * static_cast<double>(k)) + 0.3 * std::sin(0.11 * static_cast<double>(k));
  return u;
}

TEST(CheckResidualTest, WhiteNoiseIsNoiseLike) {
  const std::size_t n = 3000;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const NoiseCheck c = CheckResidual({Record(Noise(n, 1.0, seed), Noise(n, 2.0, seed + 9), Input(n))}, 1.0, 2.0);
    EXPECT_TRUE(c.NoiseLike()) << c.Evidence();
  }
}

TEST(CheckResidualTest, EachTestSeesItsStructure) {
  const std::size_t n = 3000;
  const std::vector<double> u = Input(n);
  // (a) + (c): a slow structure of 1 σ everywhere.
  {
    std::vector<double> e = Noise(n, 1.0, 4);
    for (std::size_t k = 0; k < n; ++k) e[k] += std::sqrt(2.0) * std::sin(0.05 * static_cast<double>(k));
    const NoiseCheck c = CheckResidual({Record(e, Noise(n, 1.0, 5), u)}, 1.0, 1.0);
    EXPECT_TRUE(c.z.magnitude_fails);
    EXPECT_TRUE(c.z.whiteness_fails);
    EXPECT_TRUE(c.pitch.NoiseLike());
    EXPECT_FALSE(c.NoiseLike());
  }
  // (b): a 3 σ bump over 0.4 s in one place only (overall RMS stays small).
  {
    std::vector<double> e = Noise(n, 1.0, 6);
    for (std::size_t k = 1500; k < 1540; ++k) e[k] += 4.0 * std::sin(std::numbers::pi * static_cast<double>(k - 1500) / 40.0);
    const NoiseCheck c = CheckResidual({Record(e, Noise(n, 1.0, 7), u)}, 1.0, 1.0);
    EXPECT_FALSE(c.z.magnitude_fails);
    EXPECT_TRUE(c.z.local_fails) << c.Evidence();
    EXPECT_NEAR(c.z.local_t, 15.2, 0.6);
  }
  // (d): the residual follows the input.
  {
    std::vector<double> e = Noise(n, 1.0, 8);
    for (std::size_t k = 0; k < n; ++k) e[k] += 0.8 * u[k];
    const NoiseCheck c = CheckResidual({Record(Noise(n, 1.0, 9), e, u)}, 1.0, 1.0);
    EXPECT_TRUE(c.pitch.input_fails) << c.Evidence();
    EXPECT_TRUE(c.z.NoiseLike());
  }
  // A wrong (too small) σ̂ makes pure noise look structured: the tests use σ̂, not a guess.
  {
    const NoiseCheck c = CheckResidual({Record(Noise(n, 1.0, 10), Noise(n, 1.0, 11), u)}, 0.5, 1.0);
    EXPECT_TRUE(c.z.magnitude_fails);
  }
}

TEST(DecideTest, TheFourVerdicts) {
  NoiseCheck clean, dirty;
  dirty.z.magnitude_fails = true;
  EXPECT_EQ(Decide(clean, 0, clean), Verdict::kAdequate);
  EXPECT_EQ(Decide(dirty, 0, dirty), Verdict::kUnexplained);
  EXPECT_EQ(Decide(dirty, 1, clean), Verdict::kExplained);
  EXPECT_EQ(Decide(dirty, 2, dirty), Verdict::kPartlyExplained);
  EXPECT_STREQ(VerdictName(Verdict::kPartlyExplained), "partly_explained");
}

}  // namespace
}  // namespace pwsim::diagnose
