// The noise model of the diagnosis (sysid/diagnose/noise_model.h) against noise processes of
// known spectrum (synth/measurement_noise.h): white noise, AR(1) with r(k) = φ^k, Butterworth-
// filtered white noise (autocorrelation from its impulse response), outliers; and the verdict
// judged against it (coloured noise is noise-like, structure in it is still seen).
#include "sysid/diagnose/noise_model.h"

#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
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

namespace pwsim::diagnose {
namespace {

/// Variance of the samples k ∈ [begin, end) of every series in `y` about 0.
double MeanSquareOf(const std::vector<std::vector<double>>& y, std::size_t begin, std::size_t end) {
  double s = 0.0;
  std::size_t n = 0;
  for (const auto& v : y)
    for (std::size_t k = begin; k < std::min(end, v.size()); ++k, ++n) s += v[k] * v[k];
  return s / static_cast<double>(n);
}

TEST(NoiseModelTest, TheVariogramOfARandomWalkGrowsLinearlyAndOfAr1PlusWalkAsItsSum) {
  // Walk of std q_s per √s at 100 Hz: γ(k) = ½ q_s² k Δt. AR(1) + walk: σ² (1 − φ^k) + ½ q_s² k Δt.
  synth::NoiseProcess walk;
  walk.drift_per_sqrt_s = 1.0;
  walk.sigma = 1.0;  // the walk's unit; no stationary part: every filter off
  std::mt19937_64 rng(21);
  std::vector<std::vector<double>> windows;
  for (int w = 0; w < 400; ++w) {
    std::vector<double> y = synth::DrawNoise(walk, 60, 100.0, rng);
    windows.push_back(std::move(y));
  }
  // DrawNoise adds σ-white noise to the walk when no filter is set: γ(k) = σ² + ½ k Δt for k ≥ 1.
  const std::vector<double> gamma = RestVariogram(windows, 30);
  ASSERT_EQ(gamma.size(), 31u);
  for (std::size_t k : {1u, 10u, 30u}) EXPECT_NEAR(gamma[k] / (1.0 + 0.005 * static_cast<double>(k)), 1.0, 0.05) << k;
  synth::NoiseProcess ar = walk;
  ar.ar1 = 0.8;
  windows.clear();
  for (int w = 0; w < 3000; ++w) windows.push_back(synth::DrawNoise(ar, 60, 100.0, rng));
  const std::vector<double> g2 = RestVariogram(windows, 30);
  // (long lags: few independent pairs per window; 3000 windows give ≈ 2.5 % standard error)
  for (std::size_t k : {1u, 5u, 30u})
    EXPECT_NEAR(g2[k] / (1.0 - std::pow(0.8, static_cast<double>(k)) + 0.005 * static_cast<double>(k)), 1.0, 0.06) << k;
}

TEST(NoiseModelTest, OutliersInContaminatedGaussianDataAreReplacedAndTheScaleIsItsOwn) {
  // N(0, 1) with 1 % of the samples moved by ±(12..30) σ (beyond the limit of 6 robust scales
  // of d, 6 × 1.39 σ): the cleaned series has std 1 again.
  std::mt19937_64 rng(22);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> y(20000);
  std::size_t inserted = 0;
  for (double& v : y) {
    v = gauss(rng);
    if (unit(rng) < 0.01) {
      v += (unit(rng) < 0.5 ? -1.0 : 1.0) * (12.0 + 18.0 * unit(rng));
      ++inserted;
    }
  }
  auto rms = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x * x;
    return std::sqrt(s / static_cast<double>(v.size()));
  };
  EXPECT_GT(rms(y), 1.9);
  const std::size_t replaced = ReplaceOutliers(y, 1.0, 6.0);  // 6 × 1.39 σ: all of 12 σ and more
  EXPECT_NEAR(static_cast<double>(replaced), static_cast<double>(inserted), 0.01 * static_cast<double>(inserted));
  // Replaced samples carry the prediction's noise, Var = (34/36) σ²: the std stays ≈ 1.
  EXPECT_NEAR(rms(y), 1.0, 0.02);
}

TEST(NoiseModelTest, ASmoothMotionHasNoOutliers) {
  // A cubic and slow sines with little noise: nothing is replaced, and the kinks of a ramp
  // (slope changes of 10 mm per sample) neither.
  std::mt19937_64 rng(23);
  std::normal_distribution<double> gauss(0.0, 1e-4);
  std::vector<double> y, ramp;
  for (int k = 0; k < 2000; ++k) {
    const double t = 0.01 * k;
    y.push_back(0.02 * t * t * t - 0.1 * t + 0.01 * std::sin(3.0 * t) + gauss(rng));
    ramp.push_back(0.01 * std::clamp(k - 900.0, 0.0, 5.0) + gauss(rng));
  }
  std::vector<double> copy = y;
  EXPECT_EQ(ReplaceOutliers(y), 0u);
  EXPECT_EQ(y, copy);
  // A ramp is a kink at both ends: the cubic prediction misses it by a third of the slope
  // change (3.3 mm here), far above the noise (scale from d alone), so it IS replaced: the
  // change is bounded by the kink's own size.
  std::vector<double> before = ramp;
  ReplaceOutliers(ramp);
  for (std::size_t k = 0; k < ramp.size(); ++k) EXPECT_NEAR(ramp[k], before[k], 0.01) << k;
}

TEST(NoiseModelTest, ASpikeOnTheSecondSampleIsReplacedNotTheGoodFirstOne) {
  // A spike of M at sample 1 gives sample 0's extrapolation (2 y_1 − y_2) d = −2M, larger than
  // its own d = M even in limits: choosing by the largest |d| replaced the good first sample by
  // ≈ 2M and left the spike (development calibration set 928: a 6 mrad spike at the second
  // sample became a 0.8 mrad offset of the whole trial through the centring on the rest).
  std::mt19937_64 rng(29);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> clean(300);
  for (double& v : clean) v = gauss(rng);
  for (std::size_t spike : {std::size_t{1}, std::size_t{298}, std::size_t{0}, std::size_t{299}, std::size_t{150}}) {
    std::vector<double> y = clean;
    y[spike] += 25.0;
    EXPECT_EQ(ReplaceOutliers(y, 1.0), 1u) << spike;
    for (std::size_t k = 0; k < y.size(); ++k) {
      if (k == spike) EXPECT_NEAR(y[k], clean[k], 4.0 * std::sqrt(5.0)) << spike;  // ŷ: 4 of its σ
      else EXPECT_EQ(y[k], clean[k]) << spike << " " << k;        // every other sample untouched
    }
  }
}

TEST(NoiseModelTest, KinksInLowPassedNoiseAreNoOutliersAgainstTheNoiseLevel) {
  // 8 Hz Butterworth-filtered noise of σ = 1 makes d small: a kink of 1.5 σ per sample (d = 0.5 σ
  // at both ends of the ramp) stands out of d's own scale, not out of the noise's σ (RestSpread,
  // the floor).
  synth::NoiseProcess p;
  p.sigma = 1.0;
  p.low_pass_hz = 8.0;
  std::mt19937_64 rng(28);
  std::vector<double> y = synth::DrawNoise(p, 2000, 100.0, rng);
  for (std::size_t k = 1000; k < y.size(); ++k) y[k] += 1.5 * static_cast<double>(std::min<std::size_t>(k - 1000, 40));
  std::vector<double> unfloored = y;
  EXPECT_GT(ReplaceOutliers(unfloored), 0u);
  const double sigma = RestSpread(y, 100);
  EXPECT_NEAR(sigma, 1.0, 0.35);
  std::vector<double> floored = y;
  EXPECT_EQ(ReplaceOutliers(floored, sigma), 0u);
  // A spike of 8 σ in it is found against the floor.
  floored[1500] += 8.0;
  EXPECT_EQ(ReplaceOutliers(floored, sigma), 1u);
  EXPECT_NEAR(floored[1500], y[1500], 0.3);
}

TEST(NoiseModelTest, TheFinalRestMirrorsTheInitialRest) {
  std::vector<double> t, x;
  for (int k = 0; k < 400; ++k) {
    t.push_back(0.01 * k);
    x.push_back(std::clamp(0.01 * k - 1.0, 0.0, 2.0));  // rest 1 s, move 2 s, rest 1 s
  }
  EXPECT_EQ(RestSamples(t, x, 0.25), 99u);  // x = 0 for k ≤ 100, less the 2 before departure
  EXPECT_EQ(EndRestSamples(t, x, 0.25), 98u);  // x = 2 for k ≥ 300
}

/// Trials of `n` samples at 100 Hz, at rest for `rest` samples at each end, of the process.
std::vector<RestLevelChange> LevelChanges(const synth::NoiseProcess& p, int trials, std::size_t n,
                                          std::size_t rest, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<RestLevelChange> out;
  std::vector<double> t, x;
  for (std::size_t k = 0; k < n; ++k) {
    t.push_back(0.01 * static_cast<double>(k));
    x.push_back(0.5 * std::clamp(0.01 * static_cast<double>(static_cast<int>(k) - static_cast<int>(rest)), 0.0,
                                 0.01 * static_cast<double>(n - 2 * rest)));
  }
  for (int i = 0; i < trials; ++i) out.push_back(LevelChangeAtRest(t, x, synth::DrawNoise(p, n, 100.0, rng), 0.25));
  return out;
}

TEST(NoiseModelTest, TheDriftRateOfARandomWalkIsFoundFromTheRestLevels) {
  // White σ = 1 plus a walk of 0.5 σ/√s over 1000-sample trials (rests of 100 at each end):
  // E D² = q Δt + σ² (1/ν_s + 1/ν_e), q = 0.25 σ²/s.
  synth::NoiseProcess p;
  p.sigma = 1.0;
  p.drift_per_sqrt_s = 0.5;
  const std::vector<RestLevelChange> changes = LevelChanges(p, 400, 1000, 100, 24);
  ASSERT_GT(changes.front().n_start, 90u);
  ASSERT_EQ(changes.front().n_end, 49u);  // the later half of the final rest's 99 samples
  ChannelNoise noise = WhiteNoise(1.0);
  EstimateDrift(changes, 0.1, noise);
  EXPECT_GT(noise.drift_statistic, noise.drift_bound);
  EXPECT_NEAR(noise.drift_rate / 0.25, 1.0, 0.12);
  // s_d = budget σ² / (0.2337 q): 0.1 / (0.2337 × 0.25) = 1.71 s, leaving budget σ².
  EXPECT_NEAR(noise.slow_scale_s, 0.1 / (kDriftLeftPerScale * noise.drift_rate), 1e-12);
  EXPECT_NEAR(noise.drift_left, 0.1, 1e-12);
  EXPECT_FALSE(noise.final_rest_unsettled);  // a walk tilts both rests alike
  // Stationary noise: no drift (the χ² test at 1 %).
  p.drift_per_sqrt_s = 0.0;
  ChannelNoise still = WhiteNoise(1.0);
  EstimateDrift(LevelChanges(p, 40, 1000, 100, 25), 0.1, still);
  EXPECT_LT(still.drift_statistic, still.drift_bound);
  EXPECT_EQ(still.drift_rate, 0.0);
  EXPECT_EQ(still.slow_scale_s, 0.0);
  // The same change of 0.5 σ in every trial (a settling the model gets wrong) is no drift,
  // however significant: drift has no sign; the family is left out of the test.
  std::vector<RestLevelChange> shared = LevelChanges(p, 40, 1000, 100, 25);
  for (RestLevelChange& c : shared) c.change += 0.5;
  ChannelNoise model_error = WhiteNoise(1.0);
  EstimateDrift(shared, 0.1, model_error);
  EXPECT_TRUE(model_error.drift_systematic);
  EXPECT_EQ(model_error.slow_scale_s, 0.0);
}

TEST(NoiseModelTest, TheDriftLeftAboveTheSlowPartHasItsClosedForm) {
  // ∫₀^∞ (1 − e^{−u²/2})² / u² du = √π (√2 − 1), by the trapezoidal rule.
  double integral = 0.0;
  const double du = 1e-4;
  for (double u = du / 2; u < 200.0; u += du) {
    const double g = 1.0 - std::exp(-0.5 * u * u);
    integral += g * g / (u * u) * du;
  }
  integral += 1.0 / 200.0;  // the tail ∫_200^∞ du/u²
  EXPECT_NEAR(integral, std::sqrt(std::numbers::pi) * (std::sqrt(2.0) - 1.0), 1e-4);
  EXPECT_NEAR(kDriftLeftPerScale, (std::sqrt(2.0) - 1.0) / std::sqrt(std::numbers::pi), 1e-6);
  // A walk of q = 1 /s less its slow part of scale 0.5 s leaves 0.2337 × 0.5 in the interior.
  synth::NoiseProcess walk;
  walk.sigma = 1e-9;  // the walk alone
  walk.drift_per_sqrt_s = 1e9;
  std::mt19937_64 rng(26);
  std::vector<double> t;
  for (int k = 0; k < 3000; ++k) t.push_back(0.01 * k);
  std::vector<std::vector<double>> fast;
  for (int i = 0; i < 200; ++i) fast.push_back(WithoutSlowPart(t, synth::DrawNoise(walk, 3000, 100.0, rng), 0.5));
  EXPECT_NEAR(MeanSquareOf(fast, 500, 2500) / (kDriftLeftPerScale * 0.5), 1.0, 0.08);
}

TEST(NoiseModelTest, TheSlowPartIsALocalLinearGaussianSmooth) {
  // A line is all slow part (at the ends too); a sine of frequency f keeps 1 − e^{−(2π f s)²/2}
  // of its amplitude in the interior.
  std::vector<double> t, line, slow, fast;
  const double s = 0.5, f_slow = 0.2, f_fast = 3.0;
  for (int k = 0; k < 2000; ++k) {
    t.push_back(0.01 * k);
    line.push_back(0.3 - 0.7 * t.back());
    slow.push_back(std::sin(2.0 * std::numbers::pi * f_slow * t.back()));
    fast.push_back(std::sin(2.0 * std::numbers::pi * f_fast * t.back()));
  }
  for (double v : WithoutSlowPart(t, line, s)) EXPECT_NEAR(v, 0.0, 1e-9);
  auto amplitude = [&](const std::vector<double>& y) {
    double a = 0.0;
    for (std::size_t k = 500; k < 1500; ++k) a = std::max(a, std::abs(y[k]));
    return a;
  };
  auto keep = [&](double f) { return 1.0 - std::exp(-0.5 * std::pow(2.0 * std::numbers::pi * f * s, 2.0)); };
  EXPECT_NEAR(amplitude(WithoutSlowPart(t, slow, s)), keep(f_slow), 0.02);
  EXPECT_NEAR(amplitude(WithoutSlowPart(t, fast, s)), keep(f_fast), 0.01);
  EXPECT_EQ(WithoutSlowPart(t, slow, 0.0), slow);
}

TEST(NoiseModelTest, DriftingNoiseIsNoiseLikeOnceTheDriftIsModelledAndALocalErrorIsStillSeen) {
  // White σ = 1 plus a walk of 0.6 σ/√s: the level wanders by ≈ 2 σ over a 10 s trial.
  synth::NoiseProcess p;
  p.sigma = 1.0;
  p.drift_per_sqrt_s = 0.6;
  std::mt19937_64 rng(27);
  std::vector<ResidualRecord> records;
  for (int i = 0; i < 12; ++i) {
    std::vector<double> e = synth::DrawNoise(p, 1000, 100.0, rng);
    for (double& v : e) v -= e.front();
    ResidualRecord r = Record(e);
    for (std::size_t k = 0; k < r.x.size(); ++k)  // rest 1 s at each end
      r.x[k] = 0.5 * std::clamp(r.t[k] - 1.0, 0.0, 8.0);
    records.push_back(std::move(r));
  }
  NoiseModel model{WhiteNoise(1.0), WhiteNoise(1.0)};
  EXPECT_FALSE(CheckResidual(records, model).NoiseLike());
  AddDrift(records, 0.25, VerdictOptions{}.drift_budget, model);
  ASSERT_GT(model.z.slow_scale_s, 0.0);
  const NoiseCheck check = CheckResidual(records, model);
  EXPECT_TRUE(check.NoiseLike()) << check.Evidence();
  // An error of 4 σ for 0.3 s (at an obstacle, say) is still local structure.
  for (std::size_t k = 500; k < 530; ++k) records[3].e_z[k] += 4.0;
  EXPECT_TRUE(CheckResidual(records, model).z.local_fails);
}

TEST(NoiseModelTest, TheSlopeOfAWindowHasItsVarianceUnderWhiteNoiseAWalkAndAr1) {
  // White noise: Var b = σ² / Σ(t − t̄)² = 12 σ² / (h² n (n² − 1)).
  const ChannelNoise white = WhiteNoise(1.0);
  EXPECT_NEAR(white.SlopeVarianceFactor(50, 0.01) / (12.0 / (1e-4 * 50.0 * (2500.0 - 1.0))), 1.0, 1e-9);
  // A walk of rate q: two samples give (W_1 − W_0)/h, Var = q/h; long windows tend to 6/(5 L).
  EXPECT_NEAR(SlopeWalkFactor(2, 0.01), 100.0, 1e-9);
  EXPECT_NEAR(SlopeWalkFactor(1000, 0.01) * 5.0 * 9.99 / 6.0, 1.0, 2e-3);
  // Both against simulated slopes: AR(1) φ = 0.8 (r(k) = φ^k) and a walk of 1 unit/√s.
  std::mt19937_64 rng(31);
  auto slope_variance = [&](const synth::NoiseProcess& p, std::size_t n) {
    std::vector<double> t;
    for (std::size_t k = 0; k < n; ++k) t.push_back(0.01 * static_cast<double>(k));
    double sum = 0.0;
    const int draws = 4000;
    for (int i = 0; i < draws; ++i) {
      const std::vector<double> y = synth::DrawNoise(p, n, 100.0, rng);
      double tm = 0.0, ym = 0.0, sxy = 0.0, sxx = 0.0;
      for (std::size_t k = 0; k < n; ++k) tm += t[k] / static_cast<double>(n), ym += y[k] / static_cast<double>(n);
      for (std::size_t k = 0; k < n; ++k) sxy += (t[k] - tm) * (y[k] - ym), sxx += (t[k] - tm) * (t[k] - tm);
      sum += (sxy / sxx) * (sxy / sxx);
    }
    return sum / draws;
  };
  synth::NoiseProcess ar;
  ar.sigma = 1.0;
  ar.ar1 = 0.8;
  ChannelNoise coloured = WhiteNoise(1.0);
  coloured.acf.assign(1, 1.0);
  for (int k = 1; k < 80; ++k) coloured.acf.push_back(std::pow(0.8, k));
  EXPECT_NEAR(slope_variance(ar, 100) / coloured.SlopeVarianceFactor(100, 0.01), 1.0, 0.07);
  synth::NoiseProcess walk;
  walk.sigma = 1e-6;  // the walk alone
  walk.drift_per_sqrt_s = 1e6;
  EXPECT_NEAR(slope_variance(walk, 100) / SlopeWalkFactor(100, 0.01), 1.0, 0.07);
}

TEST(NoiseModelTest, ASlowSinusoidTheTrialsSpanIsFoundFromTheRestsSlopes) {
  // White σ = 1 plus a sinusoid of amplitude 2 σ whose period is the time between the rests'
  // centres (9.255 s: rests of 99 and the final 49 samples of 10 s trials), random phase: the
  // level changes D are ≈ 0, the rests tilt by up to 2 ω σ.
  const double f = 1.0 / 9.255, amplitude = 2.0;
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * std::numbers::pi);
  synth::NoiseProcess p;
  p.sigma = 1.0;
  std::vector<ResidualRecord> records;
  std::vector<RestLevelChange> changes;
  for (int i = 0; i < 12; ++i) {
    std::vector<double> e = synth::DrawNoise(p, 1000, 100.0, rng);
    const double phi = phase(rng);
    for (std::size_t k = 0; k < e.size(); ++k)
      e[k] += amplitude * std::sin(2.0 * std::numbers::pi * f * 0.01 * static_cast<double>(k) + phi);
    ResidualRecord r = Record(e);
    for (std::size_t k = 0; k < r.x.size(); ++k) r.x[k] = 0.5 * std::clamp(r.t[k] - 1.0, 0.0, 8.0);
    changes.push_back(LevelChangeAtRest(r.t, r.x, e, 0.25));
    records.push_back(std::move(r));
  }
  // The level changes alone do not show it ...
  std::vector<RestLevelChange> levels_only = changes;
  for (RestLevelChange& c : levels_only) c.step_s = 0.0;  // no slopes
  ChannelNoise blind = WhiteNoise(1.0);
  EstimateDrift(levels_only, 0.1, blind);
  EXPECT_EQ(blind.slow_scale_s, 0.0) << blind.drift_statistic << " vs " << blind.drift_bound;
  // ... the slopes do, at a walk-equivalent rate whose slow part leaves the sinusoid's
  // amplitude × (1 − e^{−(2π f s_d)²/2}) ≪ σ.
  ChannelNoise seen = WhiteNoise(1.0);
  EstimateDrift(changes, 0.1, seen);
  ASSERT_GT(seen.slow_scale_s, 0.0) << seen.drift_statistic << " vs " << seen.drift_bound;
  EXPECT_FALSE(seen.final_rest_unsettled);  // the sinusoid tilts both rests alike
  const double kept = 1.0 - std::exp(-0.5 * std::pow(2.0 * std::numbers::pi * f * seen.slow_scale_s, 2.0));
  EXPECT_LT(amplitude * kept, 0.2);
  // The verdict: structure against stationary noise, noise-like once the drift is modelled.
  NoiseModel model{WhiteNoise(1.0), WhiteNoise(1.0)};
  EXPECT_FALSE(CheckResidual(records, model).NoiseLike());
  AddDrift(records, 0.25, VerdictOptions{}.drift_budget, model);
  const NoiseCheck check = CheckResidual(records, model);
  EXPECT_TRUE(check.NoiseLike()) << check.Evidence();
}

TEST(NoiseModelTest, AChairStillRingingInTheFinalRestIsNoDrift) {
  // White σ = 1 and, from braking at 8.5 s, a decaying ring the model lacks (1.5 Hz, τ 1.3 s,
  // amplitude 5-10 σ of either sign, random phase): the final rest (9-10 s, its later half
  // used) sits on the ring's tail, so its level changes are far beyond the noise with no shared
  // sign, as drift's would be; but the final rests tilt far more than the initial ones.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * std::numbers::pi), size(5.0, 10.0);
  std::bernoulli_distribution sign(0.5);
  synth::NoiseProcess p;
  p.sigma = 1.0;
  std::vector<RestLevelChange> changes;
  for (int i = 0; i < 12; ++i) {
    std::vector<double> e = synth::DrawNoise(p, 1000, 100.0, rng);
    const double phi = phase(rng), amplitude = (sign(rng) ? 1.0 : -1.0) * size(rng);
    std::vector<double> t, x;
    for (std::size_t k = 0; k < e.size(); ++k) {
      t.push_back(0.01 * static_cast<double>(k));
      x.push_back(0.5 * std::clamp(t.back() - 1.0, 0.0, 8.0));
      const double s = t.back() - 8.5;
      if (s > 0.0) e[k] += amplitude * std::exp(-s / 1.3) * std::sin(2.0 * std::numbers::pi * 1.5 * s + phi);
    }
    changes.push_back(LevelChangeAtRest(t, x, e, 0.25));
  }
  const ChannelNoise white = WhiteNoise(1.0);
  double level_statistic = 0.0;  // Σ D²/v, by hand: the level changes alone would call it drift
  for (const RestLevelChange& c : changes)
    level_statistic += c.change * c.change / (1.0 / white.EffectiveSamples(c.n_start) + 1.0 / white.EffectiveSamples(c.n_end));
  const boost::math::chi_squared_distribution<double> chi(static_cast<double>(changes.size()));
  ASSERT_GT(level_statistic, boost::math::quantile(boost::math::complement(chi, 0.01)));
  ChannelNoise noise = white;
  EstimateDrift(changes, 0.1, noise);
  EXPECT_TRUE(noise.final_rest_unsettled);
  EXPECT_FALSE(noise.drift_systematic);
  EXPECT_EQ(noise.slow_scale_s, 0.0) << noise.drift_statistic << " vs " << noise.drift_bound;
  // One trial's final rest alone (a step, a burst there) does not make the model's settling.
  std::vector<RestLevelChange> one = LevelChanges(p, 12, 1000, 100, 42);
  one[3].slope_end = changes[3].slope_end + 100.0;
  ChannelNoise single = white;
  EstimateDrift(one, 0.1, single);
  EXPECT_FALSE(single.final_rest_unsettled);
  // A walk besides the ring is still found, from the initial rests' slopes.
  synth::NoiseProcess walk;
  walk.sigma = 1e-6;
  walk.drift_per_sqrt_s = 3e6;  // 3 σ √t of the test's σ = 1 (the process's own σ is 1e-6)
  std::vector<RestLevelChange> drifting = changes;
  std::vector<RestLevelChange> walks = LevelChanges(walk, 12, 1000, 100, 43);
  for (std::size_t i = 0; i < drifting.size(); ++i) drifting[i].slope_start += walks[i].slope_start;
  ChannelNoise seen = white;
  EstimateDrift(drifting, 0.1, seen);
  EXPECT_GT(seen.slow_scale_s, 0.0) << seen.drift_statistic << " vs " << seen.drift_bound;
}

}  // namespace
}  // namespace pwsim::diagnose

namespace pwsim::diagnose {
namespace {

TEST(NoiseModelTest, HuberLocationSolvesItsEstimatingEquationAndIgnoresABurst) {
  // Reference: the estimating equation itself, Σ ψ((y − μ)/s) = 0 with s the MAD scale (the
  // definition R's MASS::huber solves), and the mean where no sample is beyond k s of it.
  std::mt19937_64 rng(31);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> y(25);
  for (double& v : y) v = 2.0 + 0.1 * gauss(rng);
  std::vector<double> burst = y;
  for (std::size_t k = 3; k < 6; ++k) burst[k] += 4.0;  // 3 of 25 samples 40 σ off
  for (const std::vector<double>* data : {&y, &burst}) {
    const double mu = HuberLocation(*data);
    std::vector<double> dev;
    for (double v : *data) dev.push_back(std::abs(v - Median(*data)));
    const double s = 1.4826 * Median(dev);
    double psi = 0.0;
    for (double v : *data) psi += std::clamp((v - mu) / s, -1.5, 1.5);
    EXPECT_NEAR(psi, 0.0, 1e-9);
  }
  // Samples all within k s of their mean: every ψ is linear, so μ is the mean exactly.
  // (median 1.05, s = 1.4826 × 0.03, k s = 0.067 > 0.05.)
  const std::vector<double> close{1.1, 1.0, 1.02, 1.08, 1.05};
  EXPECT_NEAR(HuberLocation(close), 1.05, 1e-12);
  // The burst moves a mean by 3 × 4 / 25 = 0.48 (4.8 σ); Huber's location by < 3 × 1.5 s / 25 + its noise.
  EXPECT_LT(std::abs(HuberLocation(burst) - HuberLocation(y)), 0.25 * 0.1 * 1.5 + 0.05);
  EXPECT_EQ(HuberLocation({}), 0.0);
  EXPECT_EQ(HuberLocation({1.0, 1.0, 1.0, 5.0}), 2.0);  // MAD 0 (s = 0): the mean
}

}  // namespace
}  // namespace pwsim::diagnose
