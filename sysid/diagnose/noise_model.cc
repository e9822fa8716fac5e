#include "sysid/diagnose/noise_model.h"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <limits>

#include "sysid/diagnose/verdict.h"

namespace pwsim::diagnose {
namespace {

constexpr double kMadToSigma = 1.4826;


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

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<long>(mid)));
  return m;
}

double ColourAutocorrelation(NoiseColour form, double tau, std::size_t k) {
  if (k == 0) return 1.0;
  if (tau <= 0.0) return 0.0;
  const double u = static_cast<double>(k) / tau;
  return form == NoiseColour::kFirstOrder ? std::exp(-u) : (1.0 + u) * std::exp(-u);
}

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
  n.sigma = n.sigma_hf = n.sigma_upper = sigma;
  return n;
}

std::vector<double> RestVariogram(const std::vector<std::vector<double>>& rest, std::size_t max_lag) {
  std::vector<double> gamma(1, 0.0);
  for (std::size_t k = 1; k <= max_lag; ++k) {
    std::vector<double> d;
    for (const auto& w : rest)
      for (std::size_t t = 0; t + k < w.size(); ++t) d.push_back(w[t + k] - w[t]);
    if (d.size() < kMinRestSamples) break;
    std::vector<double> magnitude(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) magnitude[i] = std::abs(d[i]);
    const double limit = 4.0 * kMadToSigma * Median(std::move(magnitude));
    double sum = 0.0;
    std::size_t n = 0;
    for (double v : d) {
      if (std::abs(v) > limit) continue;
      sum += v * v;
      ++n;
    }
    gamma.push_back(n > 0 ? 0.5 * sum / static_cast<double>(n) : 0.0);
  }
  return gamma;
}

std::vector<ChannelNoise> FitNoiseColour(const std::vector<std::vector<double>>& variograms) {
  // Each channel's variogram in units of its mean; one shape (form, τ) for all, a sill each.
  std::size_t lags = std::numeric_limits<std::size_t>::max();
  for (const auto& g : variograms) lags = std::min(lags, g.size() - 1);
  std::vector<double> unit(variograms.size(), 0.0);
  for (std::size_t c = 0; c < variograms.size(); ++c) {
    for (std::size_t k = 1; k <= lags; ++k) unit[c] += variograms[c][k] / static_cast<double>(lags);
  }
  double best_cost = std::numeric_limits<double>::infinity(), best_tau = 0.0;
  NoiseColour best_form = NoiseColour::kFirstOrder;
  std::vector<double> best_sill(variograms.size(), 0.0);
  for (NoiseColour form : {NoiseColour::kFirstOrder, NoiseColour::kSecondOrder}) {
    for (int i = -1; i <= 120; ++i) {
      const double tau = i < 0 ? 0.0 : 0.05 * std::pow(10.0, 3.0 * static_cast<double>(i) / 120.0);
      double cost = 0.0;
      std::vector<double> sill(variograms.size(), 0.0);
      for (std::size_t c = 0; c < variograms.size(); ++c) {
        if (!(unit[c] > 0.0)) continue;
        double ga = 0.0, aa = 0.0;
        for (std::size_t k = 1; k <= lags; ++k) {
          const double a = 1.0 - ColourAutocorrelation(form, tau, k);
          ga += variograms[c][k] / unit[c] * a;
          aa += a * a;
        }
        sill[c] = ga / aa;
        for (std::size_t k = 1; k <= lags; ++k) {
          const double r = variograms[c][k] / unit[c] - sill[c] * (1.0 - ColourAutocorrelation(form, tau, k));
          cost += r * r;
        }
      }
      if (cost < best_cost) {
        best_cost = cost;
        best_form = form;
        best_tau = tau;
        best_sill = sill;
      }
    }
  }
  std::vector<ChannelNoise> out(variograms.size());
  for (std::size_t c = 0; c < variograms.size(); ++c) {
    ChannelNoise& n = out[c];
    n.sigma = std::sqrt(best_sill[c] * unit[c]);
    n.colour = best_form;
    n.tau_samples = best_tau;
    n.acf.assign(1, 1.0);
    for (std::size_t k = 1; k <= 200; ++k) {
      const double r = ColourAutocorrelation(best_form, best_tau, k);
      if (std::abs(r) < 1e-3) break;
      n.acf.push_back(r);
    }
    n.from_rest = true;
  }
  return out;
}

ChannelNoise EstimateChannelNoise(const std::vector<std::vector<double>>& rest,
                                  const std::vector<std::vector<double>>& whole, std::size_t max_lag) {
  ChannelNoise out = WhiteNoise(PooledNoiseSigma(whole));
  for (const auto& w : rest) out.rest_samples += w.size();
  if (out.rest_samples < kMinRestSamples) return out;
  const std::vector<double> gamma = RestVariogram(rest, max_lag);
  if (gamma.size() < 2 || !(gamma[1] > 0.0)) return out;
  ChannelNoise fitted = FitNoiseColour({gamma}).front();
  fitted.sigma_hf = out.sigma_hf;
  fitted.rest_samples = out.rest_samples;
  return fitted;
}

std::size_t RestSamples(const std::vector<double>& t, const std::vector<double>& x, double rest_window) {
  std::size_t n0 = 0;
  while (n0 < t.size() && t[n0] - t.front() < rest_window) ++n0;
  if (n0 < 5 || x.size() != t.size()) return n0;
  const std::vector<double> head(x.begin(), x.begin() + static_cast<long>(n0));
  const double ref = Median(head);
  std::vector<double> deviation(n0);
  for (std::size_t k = 0; k < n0; ++k) deviation[k] = std::abs(head[k] - ref);
  const double spread = 6.0 * kMadToSigma * Median(std::move(deviation));
  if (spread > 5.0 * kRestMotion_m) return n0;  // moving (or too noisy to tell) already
  const double threshold = std::max(spread, kRestMotion_m);
  std::size_t n = 0;
  while (n < t.size() && std::abs(x[n] - ref) <= threshold) ++n;
  n = n > 2 ? n - 2 : 0;  // the last samples before the departure may already move
  return std::max(n0, n);
}

void SetUpperBound(const std::vector<std::vector<double>>& rest, ChannelNoise& noise) {
  noise.sigma_upper = noise.sigma;
  if (!noise.from_rest) return;
  double n_eff = 0.0;
  for (const auto& w : rest) n_eff += noise.EffectiveSamples(w.size());
  if (!(n_eff > 1.0)) return;
  const boost::math::chi_squared_distribution<double> chi(n_eff);
  noise.sigma_upper = noise.sigma * std::sqrt(n_eff / boost::math::quantile(chi, 0.05));
}

NoiseModel EstimateNoiseModel(const std::vector<effects::TrialRecord>& records, double rest_window) {
  std::vector<std::vector<double>> x_rest, z_rest, p_rest, z_all, p_all;
  for (const auto& r : records) {
    const std::size_t n = std::min({RestSamples(r.t, r.x, rest_window), r.z.size(), r.pitch.size()});
    x_rest.emplace_back(r.x.begin(), r.x.begin() + static_cast<long>(n));
    z_rest.emplace_back(r.z.begin(), r.z.begin() + static_cast<long>(n));
    p_rest.emplace_back(r.pitch.begin(), r.pitch.begin() + static_cast<long>(n));
    z_all.push_back(r.z);
    p_all.push_back(r.pitch);
  }
  NoiseModel model{EstimateChannelNoise(z_rest, z_all), EstimateChannelNoise(p_rest, p_all)};
  if (!model.z.from_rest || !model.pitch.from_rest) {
    SetUpperBound(z_rest, model.z);
    SetUpperBound(p_rest, model.pitch);
    return model;
  }
  // One colour for the export's channels (x, Z, θ), a level each.
  const std::vector<std::vector<double>> variograms{RestVariogram(x_rest), RestVariogram(z_rest),
                                                    RestVariogram(p_rest)};
  for (const auto& g : variograms)
    if (g.size() < 2 || !(g[1] > 0.0)) return model;
  const std::vector<ChannelNoise> fitted = FitNoiseColour(variograms);
  for (ChannelNoise* c : {&model.z, &model.pitch}) {
    const ChannelNoise& f = fitted[c == &model.z ? 1 : 2];
    c->sigma = f.sigma;
    c->colour = f.colour;
    c->tau_samples = f.tau_samples;
    c->acf = f.acf;
  }
  SetUpperBound(z_rest, model.z);
  SetUpperBound(p_rest, model.pitch);
  return model;
}

}  // namespace pwsim::diagnose
