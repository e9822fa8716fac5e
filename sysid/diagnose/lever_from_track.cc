#include "sysid/diagnose/lever_from_track.h"

#include <algorithm>
#include <cmath>

namespace pwsim::diagnose {

std::vector<double> MinusMovingAverage(const std::vector<double>& y, std::size_t samples) {
  const std::size_t n = y.size(), half = samples / 2;
  std::vector<double> sum(n + 1, 0.0);
  for (std::size_t k = 0; k < n; ++k) sum[k + 1] = sum[k] + y[k];
  std::vector<double> out(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t lo = k >= half ? k - half : 0, hi = std::min(n, k + half + 1);
    out[k] = y[k] - (sum[hi] - sum[lo]) / static_cast<double>(hi - lo);
  }
  return out;
}

double RestPitch(const effects::TrialRecord& r, double rest_window_s) {
  const std::size_t n = std::min(r.t.size(), r.pitch.size());
  double theta0 = 0.0;
  std::size_t rest = 0;
  for (; rest < n && r.t[rest] - r.t.front() <= rest_window_s; ++rest) theta0 += r.pitch[rest];
  return theta0 / static_cast<double>(std::max<std::size_t>(rest, 1));
}

namespace {

/// a_i and b_i of every trial for the window `window_s`.
struct Sums {
  std::vector<double> a, b;
};

Sums TrialSums(const std::vector<effects::TrialRecord>& records, double window_s, double rest_window_s) {
  Sums out;
  for (const effects::TrialRecord& r : records) {
    const std::size_t n = std::min({r.t.size(), r.x.size(), r.pitch.size()});
    if (n < 3) continue;
    const double dt = (r.t[n - 1] - r.t[0]) / static_cast<double>(n - 1);
    if (!(dt > 0.0)) continue;
    const double theta0 = RestPitch(r, rest_window_s);
    std::vector<double> x(r.x.begin(), r.x.begin() + static_cast<std::ptrdiff_t>(n)), s(n);
    for (std::size_t k = 0; k < n; ++k) s[k] = -std::sin(r.pitch[k] - theta0);
    const std::size_t samples = 2 * static_cast<std::size_t>(std::lround(0.5 * window_s / dt)) + 1;
    const std::vector<double> hx = MinusMovingAverage(x, samples), hs = MinusMovingAverage(s, samples);
    double a = 0.0, b = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      a += hx[k] * hs[k];
      b += hs[k] * hs[k];
    }
    if (!std::isfinite(a) || !std::isfinite(b)) continue;
    out.a.push_back(a);
    out.b.push_back(b);
  }
  return out;
}

}  // namespace

std::optional<LeverHeight> LeverHeightFromTrack(const std::vector<effects::TrialRecord>& records,
                                                const LeverHeightOptions& options) {
  auto estimate = [&](double window_s, double* se) -> std::optional<double> {
    const Sums s = TrialSums(records, window_s, options.rest_window_s);
    double a = 0.0, b = 0.0;
    std::size_t moving = 0;
    for (std::size_t i = 0; i < s.a.size(); ++i) {
      a += s.a[i];
      b += s.b[i];
      moving += s.b[i] > 0.0;
    }
    if (!(b > 0.0) || moving < 2) return std::nullopt;
    const double r = a / b;
    if (se) {
      double v = 0.0;
      for (std::size_t i = 0; i < s.a.size(); ++i) v += (s.a[i] - r * s.b[i]) * (s.a[i] - r * s.b[i]);
      *se = std::sqrt(v) / b;
    }
    return r;
  };
  LeverHeight out;
  const std::optional<double> r = estimate(options.window_s, &out.se_m);
  const std::optional<double> r2 = estimate(2.0 * options.window_s, nullptr);
  if (!r || !r2) return std::nullopt;
  out.estimate_m = *r;
  out.bias_m = std::abs(*r2 - *r);
  const double half = 3.0 * out.se_m + out.bias_m + options.margin_m;
  out.lower_m = *r - half;
  out.upper_m = *r + half;
  return out;
}

}  // namespace pwsim::diagnose
