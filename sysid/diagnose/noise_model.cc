#include "sysid/diagnose/noise_model.h"

#include <algorithm>
#include <cmath>

#include "sysid/diagnose/verdict.h"

namespace pwsim::diagnose {
namespace {

constexpr double kMadToSigma = 1.4826;

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<long>(mid)));
  return m;
}

/// r at lag k (0 beyond the model's lags).
double R(const std::vector<double>& acf, std::size_t k) { return k < acf.size() ? acf[k] : 0.0; }

/// (1/n²) Σ_{i,j<n} f(r(|i − j|)).
template <class F>
double DoubleSum(const std::vector<double>& acf, std::size_t n, F f) {
  double s = static_cast<double>(n) * f(1.0);
  for (std::size_t k = 1; k < std::min(n, acf.size()); ++k)
    s += 2.0 * static_cast<double>(n - k) * f(acf[k]);
  return s;
}

}  // namespace

double ChannelNoise::EffectiveSamples(std::size_t n) const {
  if (n == 0) return 0.0;
  const double s = DoubleSum(acf, n, [](double r) { return r * r; });
  return static_cast<double>(n) * static_cast<double>(n) / s;
}

double ChannelNoise::MeanAutocorrelation(std::size_t lags) const {
  double s = 0.0;
  for (std::size_t k = 1; k <= lags; ++k) s += R(acf, k);
  return lags > 0 ? s / static_cast<double>(lags) : 0.0;
}

ChannelNoise WhiteNoise(double sigma) {
  ChannelNoise n;
  n.sigma = n.sigma_hf = sigma;
  return n;
}

ChannelNoise EstimateChannelNoise(const std::vector<std::vector<double>>& rest,
                                  const std::vector<std::vector<double>>& whole, std::size_t max_lag) {
  ChannelNoise out = WhiteNoise(PooledNoiseSigma(whole));
  std::vector<double> deviations;
  for (const auto& w : rest) {
    const double level = Median(w);
    for (double v : w) deviations.push_back(std::abs(v - level));
  }
  out.rest_samples = deviations.size();
  if (out.rest_samples < kMinRestSamples) return out;
  const double s = kMadToSigma * Median(deviations);
  std::vector<double> gamma(max_lag + 1, 0.0);  // variogram γ̂(k)
  std::size_t lags = 0;
  for (std::size_t k = 1; k <= max_lag; ++k) {
    std::vector<double> d;
    for (const auto& w : rest)
      for (std::size_t t = 0; t + k < w.size(); ++t) d.push_back(std::abs(w[t + k] - w[t]));
    if (d.size() < kMinRestSamples) break;
    const double sd = kMadToSigma * Median(std::move(d));
    gamma[k] = 0.5 * sd * sd;
    lags = k;
  }
  if (s <= 0.0) return out;
  std::vector<double> acf(lags + 1, 0.0);
  acf[0] = 1.0;
  double sigma2 = s * s;
  for (int iteration = 0; iteration < 100; ++iteration) {
    for (std::size_t k = 1; k <= lags; ++k) acf[k] = std::clamp(1.0 - gamma[k] / sigma2, -1.0, 1.0);
    double c = 0.0, n_total = 0.0;  // share of the noise power each window's level absorbs
    for (const auto& w : rest) {
      const std::size_t n = w.size();
      if (n == 0) continue;
      const double share = DoubleSum(acf, n, [](double r) { return r; }) /
                           (static_cast<double>(n) * static_cast<double>(n));
      c += static_cast<double>(n) * share;
      n_total += static_cast<double>(n);
    }
    c = std::min(0.9, c / n_total);
    const double next = s * s / (1.0 - c);
    const bool done = std::abs(next - sigma2) <= 1e-12 * sigma2;
    sigma2 = next;
    if (done) break;
  }
  for (std::size_t k = 1; k <= lags; ++k) acf[k] = std::clamp(1.0 - gamma[k] / sigma2, -1.0, 1.0);
  out.sigma = std::sqrt(sigma2);
  out.acf = std::move(acf);
  out.from_rest = true;
  return out;
}

NoiseModel EstimateNoiseModel(const std::vector<effects::TrialRecord>& records, double rest_window) {
  std::vector<std::vector<double>> z_rest, p_rest, z_all, p_all;
  for (const auto& r : records) {
    std::size_t n = 0;
    while (n < r.t.size() && r.t[n] - r.t.front() < rest_window) ++n;
    z_rest.emplace_back(r.z.begin(), r.z.begin() + static_cast<long>(std::min(n, r.z.size())));
    p_rest.emplace_back(r.pitch.begin(), r.pitch.begin() + static_cast<long>(std::min(n, r.pitch.size())));
    z_all.push_back(r.z);
    p_all.push_back(r.pitch);
  }
  return {EstimateChannelNoise(z_rest, z_all), EstimateChannelNoise(p_rest, p_all)};
}

}  // namespace pwsim::diagnose
