#include "sysid/diagnose/residual_analysis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace pwsim::diagnose {
namespace {

std::vector<double> WhiteNoise(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v) x = unit(rng);
  return v;
}

TEST(ResidualAnalysisTest, WhitenessBoundsLikeMatlabResid) {
  // White noise: about 1 % of lags outside the 99 % bound; over 20 records, rarely more than 1.
  int outside = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const CorrelationTest test = AutoCorrelationTest(WhiteNoise(2000, seed), 25);
    EXPECT_NEAR(test.bound, 2.5758 / std::sqrt(2000.0), 1e-4);
    EXPECT_EQ(test.r[0], 1.0);
    outside += test.outside;
  }
  EXPECT_LE(outside, 20);  // expectation 0.01 × 25 × 20 = 5
  // An AR(1) residual (unmodelled dynamics) fails clearly.
  std::vector<double> ar = WhiteNoise(2000, 99);
  for (std::size_t k = 1; k < ar.size(); ++k) ar[k] += 0.8 * ar[k - 1];
  const CorrelationTest coloured = AutoCorrelationTest(ar, 25);
  EXPECT_GT(coloured.outside, 5);
  EXPECT_EQ(coloured.worst_lag, 1);
  EXPECT_NEAR(coloured.r[1], 0.8, 0.05);
}

TEST(ResidualAnalysisTest, CrossCorrelationFindsTheDelayAndUsesTheColouredBound) {
  std::vector<double> u = WhiteNoise(3000, 7);
  for (std::size_t k = 1; k < u.size(); ++k) u[k] += 0.9 * u[k - 1];  // coloured input
  const std::vector<double> noise = WhiteNoise(3000, 8);
  std::vector<double> e(u.size(), 0.0);
  for (std::size_t k = 5; k < e.size(); ++k) e[k] = 0.3 * u[k - 5] + noise[k];
  const CorrelationTest test = CrossCorrelationTest(e, u, 25);
  EXPECT_EQ(test.worst_lag, 5);  // e after u: unmodelled input dynamics
  EXPECT_FALSE(test.Passes());
  // The coloured-input bound is wider than the white one.
  EXPECT_GT(test.bound, 2.5758 / std::sqrt(3000.0));
  // Independent residual: (almost) no lag outside.
  const CorrelationTest independent = CrossCorrelationTest(noise, u, 25);
  EXPECT_LE(independent.outside, 2);
}

TEST(ResidualAnalysisTest, WelchSpectrumPeaksAtTheRingingFrequency) {
  const double rate = 100.0;
  std::vector<double> e = WhiteNoise(4000, 3);
  for (std::size_t k = 0; k < e.size(); ++k) e[k] = 0.1 * e[k] + std::sin(2 * std::numbers::pi * 12.5 * static_cast<double>(k) / rate);
  const Spectrum s = WelchSpectrum(e, rate, 128);
  EXPECT_NEAR(PeakFrequency(s, 1.0), 12.5, rate / 128);
  EXPECT_GT(BandFraction(s, 6.0, 1e9), 0.9);
  // Parseval: the PSD integrates to the variance (0.5 + 0.01).
  double power = 0.0;
  for (std::size_t b = 0; b < s.psd.size(); ++b) power += s.psd[b] * rate / 128;
  EXPECT_NEAR(power, 0.51, 0.05);
}

TEST(ResidualAnalysisTest, ScaleAndLagRegressionReadsTheScaledDownModel) {
  // A model that has the right shape at 0.58 of the amplitude and 30 ms early: fit ≈ 58 % at
  // zero lag once the lag is removed (anchors §0: fit = 100 (1 - |1 - g|)).
  const double rate = 100.0;
  std::vector<double> y(600), m(600);
  for (int k = 0; k < 600; ++k) {
    y[k] = std::exp(-std::pow((k - 300) / 40.0, 2));
    m[k] = 0.58 * std::exp(-std::pow((k + 3 - 300) / 40.0, 2));
  }
  const ScaleLag r = RegressScaleLag(y, m, rate, 0.1);
  EXPECT_NEAR(r.scale, 1.0 / 0.58, 1e-6);
  EXPECT_NEAR(r.lag_s, 0.03, 1e-9);
  EXPECT_NEAR(r.fit_after, 100.0, 1e-6);
  EXPECT_LT(r.fit_before, 60.0);
}

TEST(ResidualAnalysisTest, CorrelationAndSlope) {
  const std::vector<double> x{1, 2, 3, 4, 5}, y{3, 5, 7, 9, 11};
  EXPECT_NEAR(Correlation(x, y), 1.0, 1e-12);
  EXPECT_NEAR(Slope(x, y), 2.0, 1e-12);
  const std::vector<double> flat{1, 1, 1, 1, 1};
  EXPECT_EQ(Correlation(x, flat), 0.0);
}

}  // namespace
}  // namespace pwsim::diagnose
