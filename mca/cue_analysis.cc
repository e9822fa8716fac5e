#include "mca/cue_analysis.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

/// Σ a[i] b[i + lag] over the overlap.
double LaggedDot(const std::vector<double>& a, const std::vector<double>& b, long lag) {
  const long n = static_cast<long>(a.size());
  double s = 0.0;
  for (long i = std::max(0L, -lag); i < n && i + lag < n; ++i) {
    s += a[static_cast<std::size_t>(i)] * b[static_cast<std::size_t>(i + lag)];
  }
  return s;
}

double LaggedSquares(const std::vector<double>& v, long from, long to) {
  double s = 0.0;
  for (long i = std::max(0L, from); i < std::min(static_cast<long>(v.size()), to); ++i) {
    s += v[static_cast<std::size_t>(i)] * v[static_cast<std::size_t>(i)];
  }
  return s;
}

/// The lag scan both correlations share: for each lag within ±max_lag (at most half the
/// length), the dot product `dot_at(lag)` normalised over that lag's own overlap by the prefix
/// sums of squares qa, qb; the largest value, its lag, and the value at lag 0 when defined.
struct LagScanResult {
  double best{-2.0};
  long best_lag{0};
  std::optional<double> zero_lag;
};
template <class DotAt>
LagScanResult ScanLags(const std::vector<double>& qa, const std::vector<double>& qb, std::size_t n,
                       double max_lag, double dt, DotAt dot_at) {
  const long max_ticks = std::min(static_cast<long>(std::llround(max_lag / dt)), static_cast<long>(n) / 2);
  LagScanResult result;
  for (long lag = -max_ticks; lag <= max_ticks; ++lag) {
    const auto a_from = static_cast<std::size_t>(std::max(0L, -lag));
    const auto a_to = static_cast<std::size_t>(std::min(static_cast<long>(n), static_cast<long>(n) - lag));
    if (a_to <= a_from) continue;
    const auto b_from = static_cast<std::size_t>(static_cast<long>(a_from) + lag);
    const auto b_to = static_cast<std::size_t>(static_cast<long>(a_to) + lag);
    const double norm = std::sqrt((qa[a_to] - qa[a_from]) * (qb[b_to] - qb[b_from]));
    if (!(norm > 0.0)) continue;
    const double value = dot_at(lag) / norm;
    if (lag == 0) result.zero_lag = value;
    if (value > result.best) {
      result.best = value;
      result.best_lag = lag;
    }
  }
  return result;
}

}  // namespace

PlatformHeadPose HeadPoseOnPlatform(const PlatformSpec& platform, const DofArray& pose) {
  return PointOnBody(pose, platform.head_from_pivot);
}

std::vector<HeadMotion> DeliveredHeadMotion(const PlatformSpec& platform,
                                            const std::vector<DofArray>& poses, double dt) {
  return HeadMotionFromBodyTrack(poses, platform.head_from_pivot, dt);
}

std::array<double, 2> MaxCrossCorrelation(const std::vector<double>& a,
                                          const std::vector<double>& b, double dt, double max_lag) {
  PWSIM_DEMAND(a.size() == b.size() && dt > 0.0);
  const double ma = Mean(a);
  const double mb = Mean(b);
  const std::size_t n = a.size();
  std::vector<double> ca(n), cb(n);
  // prefix sums of squares: each lag is normalised over its own overlap
  std::vector<double> qa(n + 1, 0.0), qb(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    ca[i] = a[i] - ma;
    cb[i] = b[i] - mb;
    qa[i + 1] = qa[i] + ca[i] * ca[i];
    qb[i + 1] = qb[i] + cb[i] * cb[i];
  }
  const LagScanResult scan = ScanLags(qa, qb, n, max_lag, dt, [&](long lag) { return LaggedDot(ca, cb, lag); });
  if (scan.best < -1.0) return {0.0, 0.0};
  return {scan.best, static_cast<double>(scan.best_lag) * dt};
}

StackedCorrelation CompareStacked(const std::vector<std::vector<double>>& truth,
                                  const std::vector<std::vector<double>>& platform, double dt, double max_lag) {
  PWSIM_DEMAND(truth.size() == platform.size() && dt > 0.0 && max_lag >= 0.0);
  StackedCorrelation out;
  if (truth.empty() || truth[0].empty()) return out;
  const std::size_t n = truth[0].size();
  std::vector<std::vector<double>> a(truth.size()), b(truth.size());
  std::vector<double> qa(n + 1, 0.0), qb(n + 1, 0.0);  // prefix sums of squares over the channels
  for (std::size_t c = 0; c < truth.size(); ++c) {
    PWSIM_DEMAND(truth[c].size() == n && platform[c].size() == n);
    const double ma = Mean(truth[c]), mb = Mean(platform[c]);
    a[c].resize(n);
    b[c].resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      a[c][i] = truth[c][i] - ma;
      b[c][i] = platform[c][i] - mb;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    double sa = 0.0, sb = 0.0;
    for (std::size_t c = 0; c < a.size(); ++c) {
      sa += a[c][i] * a[c][i];
      sb += b[c][i] * b[c][i];
    }
    qa[i + 1] = qa[i] + sa;
    qb[i + 1] = qb[i] + sb;
  }
  const LagScanResult scan = ScanLags(qa, qb, n, max_lag, dt, [&](long lag) {
    double dot = 0.0;
    for (std::size_t c = 0; c < a.size(); ++c) dot += LaggedDot(a[c], b[c], lag);
    return dot;
  });
  if (scan.zero_lag) out.zero_lag = *scan.zero_lag;
  if (scan.best >= -1.0) {
    out.peak = scan.best;
    out.lag = static_cast<double>(scan.best_lag) * dt;
  }
  return out;
}

AxisConsistency CompareAxis(const std::vector<double>& truth, const std::vector<double>& platform,
                            double threshold, double dt, double max_lag) {
  PWSIM_DEMAND(truth.size() == platform.size() && dt > 0.0 && max_lag >= 0.0);
  AxisConsistency out;
  const std::size_t n = truth.size();
  if (n == 0) return out;
  // correlation and RMS error at zero lag
  const double mt = Mean(truth);
  const double mp = Mean(platform);
  double stt = 0.0, spp = 0.0, stp = 0.0, see = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = truth[i] - mt;
    const double p = platform[i] - mp;
    stt += t * t;
    spp += p * p;
    stp += t * p;
    const double e = platform[i] - truth[i];
    see += e * e;
    out.peak_true = std::max(out.peak_true, std::abs(truth[i]));
    out.peak_platform = std::max(out.peak_platform, std::abs(platform[i]));
  }
  out.correlation = (stt > 0.0 && spp > 0.0) ? stp / std::sqrt(stt * spp) : 0.0;
  out.rms_error = std::sqrt(see / static_cast<double>(n));
  // lag and gain at the best cross-correlation
  const auto [xc, lag] = MaxCrossCorrelation(truth, platform, dt, max_lag);
  out.xcorr = xc;
  out.lag = lag;
  const long lag_ticks = static_cast<long>(std::llround(lag / dt));
  const double tt = LaggedSquares(truth, -lag_ticks, static_cast<long>(n) - lag_ticks);
  out.gain = tt > 0.0 ? LaggedDot(truth, platform, lag_ticks) / tt : 0.0;
  // wrong-sign episodes
  bool in_episode = false;
  for (std::size_t i = 0; i < n; ++i) {
    const bool wrong = std::abs(platform[i]) > threshold && platform[i] * truth[i] < 0.0;
    if (wrong) {
      out.wrong_sign_duration += dt;
      if (!in_episode) ++out.wrong_sign_count;
    }
    in_episode = wrong;
  }
  return out;
}

RateCues RateAbove(const std::vector<double>& angle, double threshold, double dt) {
  PWSIM_DEMAND(dt > 0.0);
  std::vector<double> rate(angle.empty() ? 0 : angle.size() - 1);
  for (std::size_t i = 1; i < angle.size(); ++i) rate[i - 1] = (angle[i] - angle[i - 1]) / dt;
  return RatesAbove(rate, threshold, dt);
}

RateCues RatesAbove(const std::vector<double>& rate, double threshold, double dt) {
  PWSIM_DEMAND(dt > 0.0);
  RateCues out;
  bool in_episode = false;
  // a relative margin keeps a rate limited exactly at the threshold from counting
  const double limit = threshold * (1.0 + 1e-9);
  for (const double r : rate) {
    out.max_rate = std::max(out.max_rate, std::abs(r));
    const bool above = std::abs(r) > limit;
    if (above) {
      out.duration += dt;
      if (!in_episode) ++out.count;
    }
    in_episode = above;
  }
  return out;
}

}  // namespace pwsim::mca
