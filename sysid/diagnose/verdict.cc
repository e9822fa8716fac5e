#include "sysid/diagnose/verdict.h"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <cstdio>

#include "sysid/diagnose/residual_analysis.h"

namespace pwsim::diagnose {
namespace {


double MeanSquare(std::span<const double> e) {
  double s = 0.0;
  for (double v : e) s += v * v;
  return e.empty() ? 0.0 : s / static_cast<double>(e.size());
}

/// Structured RMS in units of σ: sqrt(max(0, ms - σ² q)) / σ.
double Rho(double ms, double sigma, double q = 1.0) {
  if (sigma <= 0.0) return ms > 0.0 ? 1e9 : 0.0;
  return std::sqrt(std::max(0.0, ms - sigma * sigma * q)) / sigma;
}

double SlopeOf(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() < 3) return 0.0;
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    mx += x[k];
    my += y[k];
  }
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(x.size());
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sxy += (x[k] - mx) * (y[k] - my);
    sxx += (x[k] - mx) * (x[k] - mx);
  }
  return sxx > 0.0 ? sxy / sxx : 0.0;
}

ChannelCheck CheckChannel(const std::vector<ResidualRecord>& records, bool pitch,
                          const ChannelNoise& noise, const VerdictOptions& o) {
  ChannelCheck c;
  const double sigma_noise = noise.sigma_upper > 0.0 ? noise.sigma_upper : noise.sigma;
  // With drift, the residual less its slow part against the noise plus the drift left above it.
  const double sigma = std::sqrt(sigma_noise * sigma_noise + noise.drift_left);
  c.sigma = sigma;
  c.slow_scale_s = noise.slow_scale_s;
  const double clip = o.clip_sigma * sigma;
  auto square = [&](double v) { return sigma > 0.0 ? std::min(v * v, clip * clip) : v * v; };
  // Residual and input in the band judged: both less their slow part (none without drift).
  std::vector<std::vector<double>> fast, fast_input;
  for (const auto& r : records) {
    fast.push_back(WithoutSlowPart(r.t, pitch ? r.e_pitch : r.e_z, noise.slow_scale_s));
    fast_input.push_back(WithoutSlowPart(r.t, pitch ? r.gm_pitch : r.gm_z, noise.slow_scale_s));
  }
  auto e_of = [&](const ResidualRecord& r) -> const std::vector<double>& {
    return fast[static_cast<std::size_t>(&r - records.data())];
  };
  auto u_of = [&](const ResidualRecord& r) -> const std::vector<double>& {
    return fast_input[static_cast<std::size_t>(&r - records.data())];
  };
  // (a) magnitude over every record.
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& r : records) {
    for (double v : e_of(r)) sum += square(v);
    n += e_of(r).size();
  }
  c.rho = Rho(n > 0 ? sum / static_cast<double>(n) : 0.0, sigma);
  c.magnitude_fails = c.rho > o.rho_max;
  // (b) windows.
  struct Window {
    std::size_t record, begin, end;
  };
  std::vector<Window> windows;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const auto& t = records[i].t;
    std::size_t b = 0;
    while (b < t.size()) {
      std::size_t e = b;
      while (e < t.size() && t[e] - t[b] < o.window_s) ++e;
      if (e - b >= 5) windows.push_back({i, b, e});
      b = e;
    }
  }
  const double m = std::max<double>(1.0, static_cast<double>(windows.size()));
  c.rho_local = 0.0;
  for (const Window& w : windows) {
    const auto& e = e_of(records[w.record]);
    const double nw = noise.EffectiveSamples(w.end - w.begin);
    const boost::math::chi_squared_distribution<double> chi(nw);
    const double q = boost::math::quantile(boost::math::complement(chi, o.alpha / m)) / nw;
    double ms = 0.0;
    for (std::size_t k = w.begin; k < w.end; ++k) ms += square(e[k]);
    const double rho = Rho(ms / static_cast<double>(w.end - w.begin), sigma, q);
    if (rho > c.rho_local) {
      c.rho_local = rho;
      const std::size_t mid = (w.begin + w.end) / 2;
      c.local_trial = records[w.record].name;
      c.local_t = records[w.record].t[mid];
      c.local_x = mid < records[w.record].x.size() ? records[w.record].x[mid] : 0.0;
    }
  }
  c.local_fails = c.rho_local > o.rho_local;
  // (c) whiteness: r̄ over lags 1..5, pooled over records (weighted by length).
  double rbar = 0.0, weight = 0.0;
  for (const auto& r : records) {
    const auto& e = e_of(r);
    if (e.size() < 20) continue;
    const CorrelationTest acf = AutoCorrelationTest(e, 5);
    double s = 0.0;
    for (std::size_t k = 1; k < acf.r.size(); ++k) s += acf.r[k];
    const double w = static_cast<double>(e.size());
    rbar += w * s / static_cast<double>(std::max<std::size_t>(1, acf.r.size() - 1));
    weight += w;
  }
  c.whiteness = weight > 0.0 ? rbar / weight : 0.0;
  // The drift left above the slow part is noise too, correlated over far more than 5 lags.
  const double stationary = sigma_noise * sigma_noise;
  c.whiteness_noise = stationary + noise.drift_left > 0.0
                          ? (stationary * noise.MeanAutocorrelation(5) + noise.drift_left) / (stationary + noise.drift_left)
                          : noise.MeanAutocorrelation(5);
  double bartlett = 1.0;
  for (std::size_t k = 1; k < noise.acf.size(); ++k) bartlett += 2.0 * noise.acf[k] * noise.acf[k];
  c.whiteness_bound = weight > 0.0 ? kZ99 * std::sqrt(bartlett) / std::sqrt(5.0 * weight) : 0.0;
  const double rmax2 = o.rho_max * o.rho_max;
  const double excess = c.whiteness - c.whiteness_noise;
  const double share = c.whiteness_noise < 1.0 ? excess / (1.0 - c.whiteness_noise) : 0.0;
  c.whiteness_fails = share > rmax2 / (1.0 + rmax2) && excess > c.whiteness_bound;
  // (d) input correlation: the worst record and lag, its bound widened from the pointwise 99 %
  // to a family-wise α over the m = 51 × records lags looked at (Bonferroni, as (b)).
  constexpr int kInputLags = 25;
  std::size_t tested = 0;
  for (const auto& r : records)
    if (e_of(r).size() >= 60 && u_of(r).size() == e_of(r).size()) ++tested;
  const double lags_looked_at = static_cast<double>((2 * kInputLags + 1) * std::max<std::size_t>(1, tested));
  const double widening =
      boost::math::quantile(boost::math::complement(boost::math::normal(), 0.5 * o.alpha / lags_looked_at)) / kZ99;
  for (const auto& r : records) {
    if (e_of(r).size() < 60 || u_of(r).size() != e_of(r).size()) continue;
    const CorrelationTest ccf = CrossCorrelationTest(e_of(r), u_of(r), kInputLags);
    if (ccf.worst > c.input_r) {
      c.input_r = ccf.worst;
      c.input_bound = widening * ccf.bound;
    }
  }
  c.input_fails = c.input_r > o.input_r_max && c.input_r > c.input_bound;
  // (e) speed and load.
  std::vector<double> speed, load, rho;
  for (const auto& r : records) {
    speed.push_back(r.speed);
    load.push_back(r.load_kg / 100.0);
    rho.push_back(Rho(MeanSquare(e_of(r)), sigma));
  }
  c.speed_slope = SlopeOf(speed, rho);
  c.load_slope = SlopeOf(load, rho);
  return c;
}

std::string ChannelLine(const char* name, const ChannelCheck& c, const VerdictOptions& o) {
  char drift[128] = "";
  if (c.slow_scale_s > 0.0)
    std::snprintf(drift, sizeof(drift), "; drift in the data: judged above %.2f Hz (slow part of scale %.2f s removed)",
                  1.0 / (2.0 * 3.14159265358979 * c.slow_scale_s), c.slow_scale_s);
  char buf[1200];
  std::snprintf(buf, sizeof(buf),
                "%s: structured RMS %.2f σ (limit %.2f)%s, worst %.2g s window %.2f σ (limit %.2f) at "
                "x = %.2f m in %s%s, whiteness r̄ %.2f (noise %.2f)%s, input |r| %.2f (limit %.2f)%s, "
                "ρ vs speed %+.2f per m/s, vs load %+.2f per 100 kg%s",
                name, c.rho, o.rho_max, c.magnitude_fails ? " FAILS" : "", o.window_s, c.rho_local,
                o.rho_local, c.local_x, c.local_trial.empty() ? "-" : c.local_trial.c_str(),
                c.local_fails ? " FAILS" : "", c.whiteness, c.whiteness_noise,
                c.whiteness_fails ? " FAILS" : "", c.input_r, o.input_r_max,
                c.input_fails ? " FAILS" : "", c.speed_slope, c.load_slope, drift);
  return buf;
}

}  // namespace

double NoiseSigma(std::span<const double> y) {
  if (y.size() < 5) return 0.0;
  std::vector<double> d;
  d.reserve(y.size() - 4);
  for (std::size_t k = 0; k + 4 < y.size(); ++k)
    d.push_back(std::abs(y[k] - 4.0 * y[k + 1] + 6.0 * y[k + 2] - 4.0 * y[k + 3] + y[k + 4]));
  return 1.4826 * Median(std::move(d)) / std::sqrt(70.0);
}

double PooledNoiseSigma(const std::vector<std::vector<double>>& records) {
  std::vector<double> s;
  for (const auto& r : records)
    if (r.size() >= 5) s.push_back(NoiseSigma(r));
  return Median(std::move(s));
}

double NoiseFloorFitPct(const std::vector<std::vector<double>>& records, double sigma) {
  double dev = 0.0, n = 0.0;
  for (const auto& r : records) {
    double mean = 0.0;
    for (double v : r) mean += v;
    mean /= std::max<double>(1.0, static_cast<double>(r.size()));
    for (double v : r) dev += (v - mean) * (v - mean);
    n += static_cast<double>(r.size());
  }
  if (dev <= 0.0) return 0.0;
  return 100.0 * (1.0 - std::sqrt(n * sigma * sigma) / std::sqrt(dev));
}

void AddDrift(const std::vector<ResidualRecord>& records, double rest_window, double budget, NoiseModel& noise) {
  for (const bool pitch : {false, true}) {
    std::vector<RestLevelChange> changes;
    for (const auto& r : records) changes.push_back(LevelChangeAtRest(r.t, r.x, pitch ? r.e_pitch : r.e_z, rest_window));
    EstimateDrift(changes, budget, pitch ? noise.pitch : noise.z);
  }
}

NoiseCheck CheckResidual(const std::vector<ResidualRecord>& records, const NoiseModel& noise,
                         const VerdictOptions& options) {
  NoiseCheck check;
  check.z = CheckChannel(records, false, noise.z, options);
  check.pitch = CheckChannel(records, true, noise.pitch, options);
  check.options = options;
  return check;
}

NoiseCheck CheckResidual(const std::vector<ResidualRecord>& records, double sigma_z,
                         double sigma_pitch, const VerdictOptions& options) {
  return CheckResidual(records, NoiseModel{WhiteNoise(sigma_z), WhiteNoise(sigma_pitch)}, options);
}

std::string NoiseCheck::Evidence() const {
  const VerdictOptions& o = options;
  return std::string(NoiseLike() ? "residual cannot be told from noise; " : "residual is structured; ") +
         ChannelLine("Z", z, o) + "; " + ChannelLine("pitch", pitch, o);
}

Verdict Decide(const NoiseCheck& base, std::size_t causes, const NoiseCheck& extended) {
  return DecideVerdict(base.NoiseLike(), causes, extended.NoiseLike());
}

}  // namespace pwsim::diagnose
