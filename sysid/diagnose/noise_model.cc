#include "sysid/diagnose/noise_model.h"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <limits>
#include <numeric>

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

double HuberLocation(const std::vector<double>& y, double k_scales) {
  if (y.empty()) return 0.0;
  const double s = RestSpread(y, y.size());  // the MAD scale of all of y
  const double n = static_cast<double>(y.size());
  if (!(s > 0.0)) return std::accumulate(y.begin(), y.end(), 0.0) / n;
  double mu = Median(y);
  for (int step = 0; step < 50; ++step) {
    double sum = 0.0;
    for (double v : y) sum += std::clamp(v, mu - k_scales * s, mu + k_scales * s);
    const double next = sum / n;
    const bool converged = std::abs(next - mu) < 1e-12 * s;
    mu = next;
    if (converged) break;
  }
  return mu;
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

namespace {

/// c_i = (i − m)/(h Σ(j − m)²), m = (n − 1)/2: the least-squares slope's weights.
std::vector<double> SlopeWeights(std::size_t n, double h) {
  const double m = 0.5 * static_cast<double>(n - 1);
  double sxx = 0.0;
  for (std::size_t i = 0; i < n; ++i) sxx += (static_cast<double>(i) - m) * (static_cast<double>(i) - m);
  std::vector<double> c(n);
  for (std::size_t i = 0; i < n; ++i) c[i] = (static_cast<double>(i) - m) / (h * sxx);
  return c;
}

}  // namespace

double ChannelNoise::SlopeVarianceFactor(std::size_t n, double h) const {
  if (n < 2 || !(h > 0.0)) return 0.0;
  const std::vector<double> c = SlopeWeights(n, h);
  double u = 0.0;
  for (std::size_t i = 0; i < n; ++i) u += c[i] * c[i];
  for (std::size_t k = 1; k < std::min(n, acf.size()); ++k) {
    double s = 0.0;
    for (std::size_t i = 0; i + k < n; ++i) s += c[i] * c[i + k];
    u += 2.0 * acf[k] * s;
  }
  return u;
}

double SlopeWalkFactor(std::size_t n, double h) {
  if (n < 2 || !(h > 0.0)) return 0.0;
  const std::vector<double> c = SlopeWeights(n, h);
  // Σ_ij c_i c_j min(t_i, t_j) with t_i = i h: Σ_i c_i Σ_j c_j min(i, j) h, the inner sum by
  // prefix sums (Σ c_j = 0, so the walk's starting level drops out).
  double w = 0.0, below = 0.0, tail = 0.0;
  for (double v : c) tail += v;
  for (std::size_t i = 0; i < n; ++i) {  // below = Σ_{j<i} c_j j, tail = Σ_{j≥i} c_j
    w += c[i] * h * (below + static_cast<double>(i) * tail);
    below += c[i] * static_cast<double>(i);
    tail -= c[i];
  }
  return w;
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

namespace pwsim::diagnose {
namespace {

/// ŷ_k from the neighbours: the cubic through k−2, k−1, k+1, k+2 inside; at the two first and
/// last samples the line through the two nearest on the inner side (noise variance 5 σ², not
/// (1 + 34/36) σ²: kEndWidening widens the limit there alike).
double Predicted(const std::vector<double>& y, std::size_t k) {
  const std::size_t n = y.size();
  if (k >= 2 && k + 2 < n) return (-y[k - 2] + 4.0 * y[k - 1] + 4.0 * y[k + 1] - y[k + 2]) / 6.0;
  if (k < 2) return k == 0 ? 2.0 * y[1] - y[2] : 0.5 * (y[0] + y[2]);
  return k == n - 1 ? 2.0 * y[n - 2] - y[n - 3] : 0.5 * (y[n - 1] + y[n - 3]);
}

/// sqrt(5 / (1 + 34/36)) for k = 0, n − 1 (extrapolated); sqrt(1.5 / (1 + 34/36)) for k = 1,
/// n − 2 (the mean of the two neighbours).
double EndWidening(std::size_t k, std::size_t n) {
  if (k == 0 || k == n - 1) return std::sqrt(5.0 / (1.0 + 34.0 / 36.0));
  if (k == 1 || k == n - 2) return std::sqrt(1.5 / (1.0 + 34.0 / 36.0));
  return 1.0;
}

}  // namespace

std::size_t ReplaceOutliers(std::vector<double>& y, double noise_sigma, double limit) {
  const std::size_t n = y.size();
  if (n < 7) return 0;
  std::size_t replaced = 0;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<double> d(n), magnitude(n);
    for (std::size_t k = 0; k < n; ++k) {
      d[k] = y[k] - Predicted(y, k);
      magnitude[k] = std::abs(d[k]);
    }
    const double scale = std::max(kMadToSigma * Median(magnitude), noise_sigma);
    if (!(scale > 0.0)) break;
    // The samples beyond their limit. Among those within ±2 of each other the outlier is the one
    // whose replacement leaves no |d| beyond its limit within ±2 (the least left of such), or,
    // where no single replacement does (two spikes side by side), the largest |d| in limits, as
    // before. A spike at the second sample drives the first one's extrapolated |d| to twice its
    // own: the largest |d| alone would replace the good first sample.
    auto in_limits = [&](std::size_t k) { return magnitude[k] / (limit * scale * EndWidening(k, n)); };
    auto left_after = [&](std::size_t k) {  // max |d_j| in limits, j within ±2, with y_k replaced
      const double kept = y[k];
      y[k] = Predicted(y, k);
      double worst = 0.0;
      for (std::size_t j = (k >= 2 ? k - 2 : 0); j < std::min(n, k + 3); ++j)
        worst = std::max(worst, std::abs(y[j] - Predicted(y, j)) / (limit * scale * EndWidening(j, n)));
      y[k] = kept;
      return worst;
    };
    std::vector<double> left(n, 0.0);
    for (std::size_t k = 0; k < n; ++k)
      if (in_limits(k) > 1.0) left[k] = left_after(k);
    // k before j: k explains its neighbourhood and j does not or leaves more; or neither does
    // and k's |d| is the larger.
    auto before = [&](std::size_t k, std::size_t j) {
      const bool k_explains = left[k] <= 1.0, j_explains = left[j] <= 1.0;
      if (k_explains != j_explains) return k_explains;
      if (k_explains) return left[k] < left[j] || (left[k] == left[j] && k < j);
      return in_limits(k) > in_limits(j) || (in_limits(k) == in_limits(j) && k < j);
    };
    std::vector<std::size_t> outliers;
    for (std::size_t k = 0; k < n; ++k) {
      if (!(in_limits(k) > 1.0)) continue;
      bool first = true;
      for (std::size_t j = (k >= 2 ? k - 2 : 0); j < std::min(n, k + 3); ++j)
        if (j != k && in_limits(j) > 1.0 && before(j, k)) first = false;
      if (first) outliers.push_back(k);
    }
    if (outliers.empty()) break;
    for (std::size_t k : outliers) y[k] = Predicted(y, k);
    replaced += outliers.size();
  }
  return replaced;
}

double RestSpread(const std::vector<double>& y, std::size_t n) {
  n = std::min(n, y.size());
  const std::vector<double> head(y.begin(), y.begin() + static_cast<long>(n));
  const double level = Median(head);
  std::vector<double> deviation(n);
  for (std::size_t k = 0; k < n; ++k) deviation[k] = std::abs(head[k] - level);
  return kMadToSigma * Median(std::move(deviation));
}

effects::TrialRecord WithoutOutliers(effects::TrialRecord record, double rest_window) {
  const std::size_t rest = RestSamples(record.t, record.x, rest_window);
  for (std::vector<double>* y : {&record.x, &record.z, &record.pitch}) ReplaceOutliers(*y, RestSpread(*y, rest));
  return record;
}

std::size_t EndRestSamples(const std::vector<double>& t, const std::vector<double>& x, double rest_window) {
  if (t.empty() || x.size() != t.size()) return 0;
  std::vector<double> t_back(t.size()), x_back(x.rbegin(), x.rend());
  for (std::size_t k = 0; k < t.size(); ++k) t_back[k] = t.back() - t[t.size() - 1 - k];
  return RestSamples(t_back, x_back, rest_window);
}

RestLevelChange LevelChangeAtRest(const std::vector<double>& t, const std::vector<double>& x,
                                  const std::vector<double>& e, double rest_window) {
  RestLevelChange out;
  if (e.size() != t.size()) return out;
  const std::size_t ns = std::min(RestSamples(t, x, rest_window), e.size());
  // The final rest's later half: the chair settles after it stops (a model error then, not drift).
  const std::size_t ne = std::min(EndRestSamples(t, x, rest_window), e.size()) / 2;
  if (ns < kMinRestSamples || ne < kMinRestSamples || ns + ne > e.size()) return out;
  double start = 0.0, end = 0.0, t_start = 0.0, t_end = 0.0;
  for (std::size_t k = 0; k < ns; ++k) {
    start += e[k];
    t_start += t[k];
  }
  for (std::size_t k = e.size() - ne; k < e.size(); ++k) {
    end += e[k];
    t_end += t[k];
  }
  out.change = end / static_cast<double>(ne) - start / static_cast<double>(ns);
  out.dt_s = t_end / static_cast<double>(ne) - t_start / static_cast<double>(ns);
  out.n_start = ns;
  out.n_end = ne;
  out.step_s = (t[ns - 1] - t[0]) / static_cast<double>(ns - 1);
  auto slope = [&](std::size_t begin, std::size_t n) {  // least squares on the window's own times
    double tm = 0.0, ym = 0.0;
    for (std::size_t k = begin; k < begin + n; ++k) {
      tm += t[k] / static_cast<double>(n);
      ym += e[k] / static_cast<double>(n);
    }
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t k = begin; k < begin + n; ++k) {
      sxy += (t[k] - tm) * (e[k] - ym);
      sxx += (t[k] - tm) * (t[k] - tm);
    }
    return sxx > 0.0 ? sxy / sxx : 0.0;
  };
  out.slope_start = slope(0, ns);
  out.slope_end = slope(e.size() - ne, ne);
  return out;
}

namespace {

/// One family of drift evidence (level changes, or slopes at one end): values x_i with
/// variance under stationary noise v_i and under a walk of unit rate w_i.
struct DriftEvidence {
  std::vector<double> x, v, w;
  /// x_i²/v_i: each a χ²_1 under stationary noise.
  double Term(std::size_t i) const { return x[i] * x[i] / v[i]; }
  /// Σ x²/v.
  double Statistic() const {
    double s = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) s += Term(i);
    return s;
  }
  /// max(0, Σ (x² − v)) / Σ w: unbiased before the outer max (a max per term would count the
  /// noise's positive excursions and drop its negative ones).
  double Rate() const {
    double excess = 0.0, span = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      excess += x[i] * x[i] - v[i];
      span += w[i];
    }
    return span > 0.0 ? std::max(0.0, excess) / span : 0.0;
  }
  /// A mean a two-sided t test at 1 % tells from 0 (three values at least): the model's.
  bool Systematic() const {
    const std::size_t n = x.size();
    if (n < 3) return false;
    double mean = 0.0, spread = 0.0;
    for (double value : x) mean += value / static_cast<double>(n);
    for (double value : x) spread += (value - mean) * (value - mean);
    const double se = std::sqrt(spread / static_cast<double>(n - 1) / static_cast<double>(n));
    const boost::math::students_t t(static_cast<double>(n - 1));
    return std::abs(mean) > boost::math::quantile(boost::math::complement(t, 0.005)) * se;
  }
};

/// The final rests' slopes stand out of the initial rests' by a one-sided F test at 1 %:
/// (Σ b_e²/v_e) / (Σ b_s²/v_s) beyond F_{N−1,N−1}(0.99), over the N trials but the one whose
/// final rest tilts most (a step or a burst in one trial's final rest is the data's, and one
/// trial alone does not make the model's settling). Under stationary noise and drift the two have
/// about the same law (a longer initial window tilts less under a walk, so the test errs
/// towards keeping the level changes).
bool FinalRestsTiltMore(const DriftEvidence& start, const DriftEvidence& end) {
  const std::size_t n = start.x.size();
  if (n < 4 || end.x.size() != n) return false;
  std::size_t steepest = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (end.Term(i) > end.Term(steepest)) steepest = i;
  double s_start = 0.0, s_end = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i == steepest) continue;
    s_start += start.Term(i);
    s_end += end.Term(i);
  }
  if (!(s_start > 0.0)) return false;
  const double df = static_cast<double>(n - 1);
  const boost::math::fisher_f f(df, df);
  return s_end / s_start > boost::math::quantile(boost::math::complement(f, 0.01));
}

}  // namespace

void EstimateDrift(const std::vector<RestLevelChange>& changes, double budget, ChannelNoise& noise) {
  noise.drift_rate = noise.slow_scale_s = noise.drift_left = noise.drift_statistic = noise.drift_bound = 0.0;
  noise.drift_systematic = noise.final_rest_unsettled = false;
  const double var = noise.sigma * noise.sigma;
  if (!(var > 0.0)) return;
  // Slopes of the initial rests only: the final rest's tilt carries the chair's settling
  // (inertial pitch after braking; development sets 13 and 108 lost their cause with it).
  DriftEvidence level, tilt_start, tilt_end;
  for (const RestLevelChange& c : changes) {
    if (c.n_start == 0 || c.n_end == 0 || !(c.dt_s > 0.0)) continue;
    level.x.push_back(c.change);
    level.v.push_back(var * (1.0 / noise.EffectiveSamples(c.n_start) + 1.0 / noise.EffectiveSamples(c.n_end)));
    level.w.push_back(c.dt_s);
    if (!(c.step_s > 0.0)) continue;
    tilt_start.x.push_back(c.slope_start);
    tilt_start.v.push_back(var * noise.SlopeVarianceFactor(c.n_start, c.step_s));
    tilt_start.w.push_back(SlopeWalkFactor(c.n_start, c.step_s));
    tilt_end.x.push_back(c.slope_end);
    tilt_end.v.push_back(var * noise.SlopeVarianceFactor(c.n_end, c.step_s));
  }
  // A final rest the model has not settled in: where the chair still rings after braking from
  // a cause the model lacks, the final rests tilt far more than the initial ones, which drift
  // and noise tilt alike (both stationary). Then the level changes are the model's, not drift:
  // left out.
  noise.final_rest_unsettled = FinalRestsTiltMore(tilt_start, tilt_end);
  // Drift has no sign: a family whose mean a t test tells from 0 is the model's, left out. The
  // others together: Σ x²/v ~ χ²_M under stationary noise; drift beyond its 99 % quantile, at
  // the largest of their rates.
  noise.drift_systematic = level.Systematic();
  double statistic = 0.0, rate = 0.0;
  std::size_t count = 0;
  for (const DriftEvidence* f : {&level, &tilt_start}) {
    if (f == &level && noise.final_rest_unsettled) continue;
    if (f->x.empty() || f->Systematic()) continue;
    statistic += f->Statistic();
    count += f->x.size();
    rate = std::max(rate, f->Rate());
  }
  if (count == 0) return;
  const boost::math::chi_squared_distribution<double> chi(static_cast<double>(count));
  noise.drift_statistic = statistic;
  noise.drift_bound = boost::math::quantile(boost::math::complement(chi, 0.01));
  if (statistic <= noise.drift_bound || !(rate > 0.0)) return;
  noise.drift_rate = rate;
  noise.slow_scale_s = std::clamp(budget * var / (kDriftLeftPerScale * noise.drift_rate), kMinSlowScale_s,
                                  kMaxSlowScale_s);
  noise.drift_left = kDriftLeftPerScale * noise.drift_rate * noise.slow_scale_s;
}

std::vector<double> WithoutSlowPart(const std::vector<double>& t, const std::vector<double>& y, double scale_s) {
  if (!(scale_s > 0.0) || y.size() != t.size() || y.size() < 3) return y;
  const std::size_t n = y.size();
  // Uniform sampling (the usual case): the weights by index offset, computed once.
  const double step = (t.back() - t.front()) / static_cast<double>(n - 1);
  bool uniform = step > 0.0;
  for (std::size_t k = 0; k < n && uniform; ++k)
    uniform = std::abs(t[k] - t.front() - static_cast<double>(k) * step) < 1e-6 * step;
  std::vector<double> table;
  if (uniform) {
    for (std::size_t j = 0; static_cast<double>(j) * step <= 4.0 * scale_s && j < n; ++j) {
      const double u = static_cast<double>(j) * step / scale_s;
      table.push_back(std::exp(-0.5 * u * u));
    }
  }
  std::vector<double> out(n);
  std::size_t lo = 0, hi = 0;
  for (std::size_t k = 0; k < n; ++k) {
    while (t[k] - t[lo] > 4.0 * scale_s) ++lo;
    while (hi < n && t[hi] - t[k] <= 4.0 * scale_s) ++hi;
    // Weighted least squares of a + b (t − t_k) on [lo, hi), weights e^{−½ ((t − t_k)/s)²}.
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, m0 = 0.0, m1 = 0.0;
    for (std::size_t j = lo; j < hi; ++j) {
      const double u = t[j] - t[k];
      const std::size_t offset = j > k ? j - k : k - j;
      const double w = uniform && offset < table.size() ? table[offset]
                                                         : std::exp(-0.5 * (u / scale_s) * (u / scale_s));
      s0 += w;
      s1 += w * u;
      s2 += w * u * u;
      m0 += w * y[j];
      m1 += w * u * y[j];
    }
    const double det = s0 * s2 - s1 * s1;
    const double level = det > 1e-12 * s0 * s2 ? (s2 * m0 - s1 * m1) / det : m0 / s0;
    out[k] = y[k] - level;
  }
  return out;
}

}  // namespace pwsim::diagnose
