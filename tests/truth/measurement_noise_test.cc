// The truth's measurement noise against closed forms: the Butterworth design against scipy's
// butter() coefficients (orders 2-4) and the defining properties (unit DC gain, |H| = 1/√2 at the
// cut-off, zero at Nyquist); the variance of filtered white noise against the noise-equivalent
// bandwidth (2 f_c / f_s) Γ(1/m) Γ(r - 1/m) / (m Γ(r)), m = 2n; a random walk's variance σ² t;
// the outliers' rate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>

#include "tests/truth/measurement_noise.h"

namespace pwsim::truth {
namespace {

std::complex<double> Response(const std::vector<Biquad>& filter, double f_hz, double rate_hz) {
  const std::complex<double> zi = std::polar(1.0, -2.0 * std::numbers::pi * f_hz / rate_hz);  // z^-1
  std::complex<double> h = 1.0;
  for (const Biquad& s : filter) h *= (s.b0 + s.b1 * zi + s.b2 * zi * zi) / (1.0 + s.a1 * zi + s.a2 * zi * zi);
  return h;
}

TEST(MeasurementNoise, ButterworthOrderTwoMatchesScipy) {
  // scipy.signal.butter(2, 10 / 50): b = [0.0674552738890719, 0.1349105477781438,
  // 0.0674552738890719], a = [1, -1.1429805025399009, 0.4128015980961885].
  const std::vector<Biquad> f = ButterworthLowPass(2, 10.0, 100.0);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_NEAR(f[0].b0, 0.0674552738890719, 1e-13);
  EXPECT_NEAR(f[0].b1, 0.1349105477781438, 1e-13);
  EXPECT_NEAR(f[0].b2, 0.0674552738890719, 1e-13);
  EXPECT_NEAR(f[0].a1, -1.1429805025399009, 1e-13);
  EXPECT_NEAR(f[0].a2, 0.4128015980961885, 1e-13);
}

TEST(MeasurementNoise, ButterworthOrdersThreeAndFourMatchScipysSections) {
  // scipy 1.10.1: butter(4, 12/50, output='sos') and butter(3, 7/50, output='sos'): the sections'
  // denominators (a1, a2) and the cascade's overall gain (product of the b0).
  struct Ref {
    int order;
    double fc;
    std::vector<std::pair<double, double>> a;  // sorted by a2
    double gain;
  };
  const std::vector<Ref> refs = {
      {4, 12.0, {{-0.8931036327062872, 0.22516058868743402}, {-1.1552915050582222, 0.5848302129885163}},
       0.00891445723946302},
      {3, 7.0, {{-0.6346192975441481, 0.0}, {-1.4920187596823615, 0.648954632397437}}, 0.00716766742664455}};
  for (const Ref& ref : refs) {
    std::vector<Biquad> f = ButterworthLowPass(ref.order, ref.fc, 100.0);
    std::sort(f.begin(), f.end(), [](const Biquad& x, const Biquad& y) { return x.a2 < y.a2; });
    ASSERT_EQ(f.size(), ref.a.size());
    double gain = 1.0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      EXPECT_NEAR(f[i].a1, ref.a[i].first, 1e-13) << ref.order;
      EXPECT_NEAR(f[i].a2, ref.a[i].second, 1e-13) << ref.order;
      gain *= f[i].b0;
    }
    EXPECT_NEAR(gain / ref.gain, 1.0, 1e-12) << ref.order;
  }
}

TEST(MeasurementNoise, ButterworthHasUnitDcGainAndHalfPowerAtTheCutoff) {
  for (int order = 1; order <= 6; ++order) {
    for (double fc : {6.0, 10.0, 15.0}) {
      const std::vector<Biquad> f = ButterworthLowPass(order, fc, 100.0);
      EXPECT_EQ(f.size(), static_cast<std::size_t>((order + 1) / 2));
      EXPECT_NEAR(std::abs(Response(f, 0.0, 100.0)), 1.0, 1e-12) << order;
      EXPECT_NEAR(std::abs(Response(f, fc, 100.0)), 1.0 / std::sqrt(2.0), 1e-12) << order << " " << fc;
      EXPECT_NEAR(std::abs(Response(f, 50.0, 100.0)), 0.0, 1e-12) << order;
      // Monotone pass band: below the cut-off the gain exceeds 1/√2.
      EXPECT_GT(std::abs(Response(f, 0.5 * fc, 100.0)), 1.0 / std::sqrt(2.0)) << order;
    }
  }
  EXPECT_THROW(ButterworthLowPass(2, 60.0, 100.0), std::invalid_argument);
  EXPECT_THROW(ButterworthLowPass(0, 10.0, 100.0), std::invalid_argument);
}

double BandwidthFactor(int order, int passes) {
  const double m = 2.0 * order;
  return std::tgamma(1.0 / m) * std::tgamma(passes - 1.0 / m) / (m * std::tgamma(static_cast<double>(passes)));
}

TEST(MeasurementNoise, FilteredWhiteNoiseVarianceIsTheNoiseEquivalentBandwidth) {
  // f_c ≪ f_s, where the bilinear transform's warping is O((π f_c / f_s)²) = 2.5e-4. Orders 2-4:
  // a first-order one-pass response falls as 1/f only, so the analog tail past Nyquist (≈ 1 %)
  // is part of its closed form but not of any sampled filter.
  const double fs = 1000.0, fc = 5.0;
  for (int order = 2; order <= 4; ++order) {
    const std::vector<Biquad> f = ButterworthLowPass(order, fc, fs);
    const double one_pass = 2.0 * fc / fs * BandwidthFactor(order, 1);
    const double two_pass = 2.0 * fc / fs * BandwidthFactor(order, 2);
    EXPECT_NEAR(NoiseVarianceGain(f, false) / one_pass, 1.0, 2e-3) << order;
    EXPECT_NEAR(NoiseVarianceGain(f, true) / two_pass, 1.0, 2e-3) << order;
  }
  // The closed forms of the Γ expression: (π/m)/sin(π/m) and (1 - 1/m) of that.
  EXPECT_NEAR(BandwidthFactor(2, 1), std::numbers::pi / 4.0 / std::sin(std::numbers::pi / 4.0), 1e-12);
  EXPECT_NEAR(BandwidthFactor(2, 2), 0.75 * std::numbers::pi / 4.0 / std::sin(std::numbers::pi / 4.0), 1e-12);
}

TEST(MeasurementNoise, SampledFilteredNoiseHasThePredictedVariance) {
  MeasurementNoise model;
  model.white_only = false;
  model.lowpass_order = 3;
  model.lowpass_cutoff_hz = 10.0;
  ChannelNoise ch;
  ch.white_sigma = 2e-3;
  std::mt19937_64 rng(7);
  const std::vector<double> e = ChannelNoiseSequence(model, ch, 400000, 100.0, rng);
  double sum = 0.0, sq = 0.0;
  for (double v : e) {
    sum += v;
    sq += v * v;
  }
  const double n = static_cast<double>(e.size());
  const double var = sq / n - (sum / n) * (sum / n);
  const double predicted = ch.white_sigma * ch.white_sigma * NoiseVarianceGain(ButterworthLowPass(3, 10.0, 100.0), true);
  EXPECT_NEAR(var / predicted, 1.0, 0.03);
  // Filtered noise is coloured: neighbours correlate strongly (white: 0).
  double lag1 = 0.0;
  for (std::size_t k = 1; k < e.size(); ++k) lag1 += e[k] * e[k - 1];
  EXPECT_GT(lag1 / sq, 0.5);
}

TEST(MeasurementNoise, RandomWalkVarianceGrowsAsSigmaSquaredTimesTime) {
  MeasurementNoise model;
  model.white_only = false;
  ChannelNoise ch;
  ch.drift_walk_sigma = 3e-4;  // m/√s
  std::mt19937_64 rng(11);
  const int runs = 3000;
  const std::size_t n = 1001;  // t = 10 s at 100 Hz
  double sq_end = 0.0, sq_mid = 0.0;
  for (int r = 0; r < runs; ++r) {
    const std::vector<double> e = ChannelNoiseSequence(model, ch, n, 100.0, rng);
    EXPECT_EQ(e.front(), 0.0);
    sq_end += e.back() * e.back();
    sq_mid += e[500] * e[500];
  }
  // Standard error of a variance from 3000 draws: √(2/3000) = 2.6 %.
  EXPECT_NEAR(sq_end / runs / (ch.drift_walk_sigma * ch.drift_walk_sigma * 10.0), 1.0, 0.1);
  EXPECT_NEAR(sq_mid / runs / (ch.drift_walk_sigma * ch.drift_walk_sigma * 5.0), 1.0, 0.1);
}

TEST(MeasurementNoise, SinusoidalDriftAndOutliers) {
  MeasurementNoise model;
  model.white_only = false;
  model.drift_sine = true;
  model.drift_sine_hz = 0.2;
  ChannelNoise ch;
  ch.drift_sine_amp = 1e-3;
  std::mt19937_64 rng(3);
  std::vector<double> e = ChannelNoiseSequence(model, ch, 5001, 100.0, rng);  // 10 periods
  double peak = 0.0, sq = 0.0;
  for (double v : e) {
    peak = std::max(peak, std::abs(v));
    sq += v * v;
  }
  EXPECT_NEAR(peak, 1e-3, 1e-6);
  EXPECT_NEAR(sq / static_cast<double>(e.size()), 0.5e-6, 0.01e-6);  // A²/2

  MeasurementNoise spikes;
  spikes.white_only = false;
  spikes.outlier_prob = 0.01;
  ChannelNoise o;
  o.outlier_size = 5e-3;
  e = ChannelNoiseSequence(spikes, o, 100000, 100.0, rng);
  int count = 0;
  for (double v : e) {
    if (v == 0.0) continue;
    ++count;
    EXPECT_GE(std::abs(v), 2.5e-3);
    EXPECT_LE(std::abs(v), 5e-3);
  }
  EXPECT_NEAR(count, 1000, 4 * std::sqrt(1000.0 * 0.99));  // binomial: 4 standard deviations
}

}  // namespace
}  // namespace pwsim::truth
