// The noise model of the diagnosis (sysid/diagnose/noise_model.h) against noise processes of
// known spectrum (synth/measurement_noise.h): white noise, AR(1) with r(k) = φ^k, Butterworth-
// filtered white noise (autocorrelation from its impulse response), outliers; and the verdict
// judged against it (coloured noise is noise-like, structure in it is still seen).
#include "sysid/diagnose/noise_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "synth/measurement_noise.h"
#include "sysid/diagnose/verdict.h"

namespace pwsim::diagnose {
namespace {

/// `windows` rest windows of `n` samples of the process, each at its own level.
std::vector<std::vector<double>> RestWindows(const synth::NoiseProcess& p, std::size_t windows,
                                             std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::vector<double>> out;
  for (std::size_t w = 0; w < windows; ++w) {
    std::vector<double> y = synth::DrawNoise(p, n, 100.0, rng);
    for (double& v : y) v += 0.3 + 0.01 * static_cast<double>(w);
    out.push_back(std::move(y));
  }
  return out;
}

TEST(MeasurementNoiseTest, TheGeneratorHasTheSpectrumItStates) {
  std::mt19937_64 rng(1);
  synth::NoiseProcess ar;
  ar.sigma = 2.0;
  ar.ar1 = 0.7;
  const std::vector<double> y = synth::DrawNoise(ar, 200000, 100.0, rng);
  double s0 = 0, s1 = 0, s2 = 0;
  for (std::size_t k = 2; k < y.size(); ++k) {
    s0 += y[k] * y[k];
    s1 += y[k] * y[k - 1];
    s2 += y[k] * y[k - 2];
  }
  EXPECT_NEAR(std::sqrt(s0 / static_cast<double>(y.size() - 2)), 2.0, 0.03);
  EXPECT_NEAR(s1 / s0, 0.7, 0.01);
  EXPECT_NEAR(s2 / s0, 0.49, 0.01);
  // Butterworth: unit DC gain (the impulse response sums to 1) and the stated variance.
  double dc = 0.0;
  for (double h : synth::ButterworthImpulse(10.0, 100.0, 2000)) dc += h;
  EXPECT_NEAR(dc, 1.0, 1e-9);
  synth::NoiseProcess bw;
  bw.sigma = 1.0;
  bw.low_pass_hz = 10.0;
  const std::vector<double> f = synth::DrawNoise(bw, 200000, 100.0, rng);
  double v = 0.0;
  for (double x : f) v += x * x;
  EXPECT_NEAR(std::sqrt(v / static_cast<double>(f.size())), 1.0, 0.02);
}

TEST(NoiseModelTest, WhiteNoiseIsFoundWhite) {
  synth::NoiseProcess p;
  p.sigma = 3e-4;
  const ChannelNoise n = EstimateChannelNoise(RestWindows(p, 20, 25, 2), {}, 10);
  ASSERT_TRUE(n.from_rest);
  EXPECT_NEAR(n.sigma / 3e-4, 1.0, 0.1);
  for (std::size_t k = 1; k < std::min<std::size_t>(6, n.acf.size()); ++k) EXPECT_LT(std::abs(n.acf[k]), 0.15) << k;
  EXPECT_LT(std::abs(n.MeanAutocorrelation(5)), 0.1);
}

TEST(NoiseModelTest, Ar1NoiseGivesItsVarianceAndAutocorrelation) {
  // r(k) = φ^k; a rest window's own level hides a large part of such noise (a third for
  // φ = 0.8 in 25 samples), which the variogram's sill gives back.
  synth::NoiseProcess p;
  p.sigma = 1.0;
  p.ar1 = 0.8;
  const ChannelNoise n = EstimateChannelNoise(RestWindows(p, 60, 25, 3), {}, 10);
  ASSERT_TRUE(n.from_rest);
  EXPECT_NEAR(n.sigma, 1.0, 0.12);
  EXPECT_NEAR(n.acf[1], 0.8, 0.06);
  EXPECT_NEAR(n.acf[2], 0.64, 0.08);
  EXPECT_NEAR(n.acf[4], 0.41, 0.12);
  EXPECT_NEAR(n.MeanAutocorrelation(5), (0.8 + 0.64 + 0.512 + 0.4096 + 0.32768) / 5.0, 0.1);
}

TEST(NoiseModelTest, ButterworthFilteredNoiseGivesItsAutocorrelation) {
  synth::NoiseProcess p;
  p.sigma = 5e-4;
  p.low_pass_hz = 8.0;
  const std::vector<double> h = synth::ButterworthImpulse(8.0, 100.0, 2000);
  auto r = [&](std::size_t k) {
    double num = 0.0, den = 0.0;
    for (std::size_t j = 0; j < h.size(); ++j) {
      den += h[j] * h[j];
      if (j + k < h.size()) num += h[j] * h[j + k];
    }
    return num / den;
  };
  const ChannelNoise n = EstimateChannelNoise(RestWindows(p, 60, 25, 4), {});
  EXPECT_NEAR(n.sigma / 5e-4, 1.0, 0.15);
  // The model's colour is first order: its lag-1 correlation matches the filter's.
  EXPECT_NEAR(n.acf[1], r(1), 0.1);
}

TEST(NoiseModelTest, OutliersDoNotInflateTheScale) {
  synth::NoiseProcess p;
  p.sigma = 1.0;
  p.outlier_rate = 0.03;
  p.outlier_sigmas = 20.0;
  const ChannelNoise n = EstimateChannelNoise(RestWindows(p, 20, 25, 5), {}, 10);
  EXPECT_NEAR(n.sigma, 1.0, 0.12);
  EXPECT_LT(std::abs(n.MeanAutocorrelation(1)), 0.15);
}

TEST(NoiseModelTest, TooFewRestSamplesFallBackToWhiteNoiseAtTheFourthDifferenceLevel) {
  std::mt19937_64 rng(6);
  synth::NoiseProcess p;
  p.sigma = 1.0;
  const std::vector<double> whole = synth::DrawNoise(p, 3000, 100.0, rng);
  const ChannelNoise n = EstimateChannelNoise({{0.1, 0.2, 0.3}}, {whole}, 10);
  EXPECT_FALSE(n.from_rest);
  EXPECT_EQ(n.sigma, NoiseSigma(whole));
  EXPECT_EQ(n.acf, std::vector<double>{1.0});
}

TEST(NoiseModelTest, EffectiveSamplesOfAr1NoiseHaveTheirClosedForm) {
  // Σ_{i,j} φ^{2|i−j|} → n (1 + φ²)/(1 − φ²) for n ≫ correlation time.
  ChannelNoise n;
  for (std::size_t k = 1; k < 200; ++k) n.acf.push_back(std::pow(0.8, static_cast<double>(k)));
  const double phi2 = 0.64;
  EXPECT_NEAR(n.EffectiveSamples(100000) / (100000.0 * (1.0 - phi2) / (1.0 + phi2)), 1.0, 1e-3);
  EXPECT_EQ(WhiteNoise(1.0).EffectiveSamples(50), 50.0);
}

TEST(NoiseModelTest, TheUpperBoundOfTheLevelFollowsTheChiSquareOfItsEffectiveSamples) {
  // White noise in 10 windows of 25: ν = 250, σ_upper / σ̂ = sqrt(250 / χ²_250(0.05)).
  synth::NoiseProcess p;
  p.sigma = 1.0;
  const std::vector<std::vector<double>> rest = RestWindows(p, 10, 25, 12);
  ChannelNoise n = WhiteNoise(0.9);
  n.from_rest = true;
  SetUpperBound(rest, n);
  EXPECT_NEAR(n.sigma_upper / 0.9, std::sqrt(250.0 / 214.3916), 1e-4);  // R: qchisq(0.05, 250) = 214.3916
  // Coloured noise has fewer effective samples: a wider bound.
  ChannelNoise coloured = n;
  for (std::size_t k = 1; k < 40; ++k) coloured.acf.push_back(std::pow(0.8, static_cast<double>(k)));
  SetUpperBound(rest, coloured);
  EXPECT_GT(coloured.sigma_upper, n.sigma_upper);
}

ResidualRecord Record(std::vector<double> e) {
  ResidualRecord r;
  r.name = "trial";
  r.speed = 1.0;
  for (std::size_t k = 0; k < e.size(); ++k) {
    r.t.push_back(0.01 * static_cast<double>(k));
    r.x.push_back(0.01 * static_cast<double>(k));
    r.gm_z.push_back(std::sin(0.02 * static_cast<double>(k)));
  }
  r.gm_pitch = r.gm_z;
  r.e_z = e;
  r.e_pitch = std::move(e);
  return r;
}

TEST(NoiseModelTest, LowPassedNoiseIsNoiseLikeAgainstItsModelButNotAgainstWhiteNoise) {
  synth::NoiseProcess p;
  p.sigma = 1.0;
  p.low_pass_hz = 6.0;
  const ChannelNoise model = EstimateChannelNoise(RestWindows(p, 40, 25, 7), {}, 10);
  std::mt19937_64 rng(8);
  std::vector<ResidualRecord> records;
  for (int trial = 0; trial < 6; ++trial) records.push_back(Record(synth::DrawNoise(p, 800, 100.0, rng)));
  const NoiseCheck coloured = CheckResidual(records, NoiseModel{model, model});
  EXPECT_TRUE(coloured.NoiseLike()) << coloured.Evidence();
  // The same residual judged as white noise at the level its high frequencies show (4th
  // differences): its whiteness and magnitude fail, the false alarm the model avoids.
  std::vector<std::vector<double>> e;
  for (const auto& r : records) e.push_back(r.e_z);
  const double sigma_hf = PooledNoiseSigma(e);
  EXPECT_LT(sigma_hf, 0.5);
  EXPECT_FALSE(CheckResidual(records, sigma_hf, sigma_hf).NoiseLike());
  // A slow structure of 1.5 σ in the coloured noise is still seen.
  for (auto& r : records)
    for (std::size_t k = 0; k < r.e_z.size(); ++k) r.e_z[k] += 1.5 * std::sqrt(2.0) * std::sin(0.03 * static_cast<double>(k));
  const NoiseCheck structured = CheckResidual(records, NoiseModel{model, model});
  EXPECT_TRUE(structured.z.magnitude_fails);
  EXPECT_TRUE(structured.pitch.NoiseLike());
}

}  // namespace
}  // namespace pwsim::diagnose

namespace pwsim::diagnose {
namespace {

TEST(NoiseModelTest, RestLastsUntilTheChairDeparts) {
  // At rest for 0.6 s, then x = ½ a (t − 0.6)², a = 0.8 m/s²: it passes 1 mm after 0.05 s.
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0.0, 3e-4);
  std::vector<double> t, x;
  for (int k = 0; k < 300; ++k) {
    t.push_back(0.01 * k);
    const double moving = std::max(0.0, t.back() - 0.6);
    x.push_back(2.0 + 0.4 * moving * moving + noise(rng));
  }
  const std::size_t n = RestSamples(t, x, 0.25);
  EXPECT_GE(n, 55u);
  EXPECT_LE(n, 66u);
  // A chair moving from the first sample: the rest window is all the diagnosis assumes.
  for (std::size_t k = 0; k < x.size(); ++k) x[k] = 0.5 * t[k];
  EXPECT_EQ(RestSamples(t, x, 0.25), 25u);
}

}  // namespace
}  // namespace pwsim::diagnose
