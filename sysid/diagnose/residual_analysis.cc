#include "sysid/diagnose/residual_analysis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "engine/check.h"

namespace pwsim::diagnose {
namespace {

std::vector<double> Centred(std::span<const double> v) {
  double mean = 0.0;
  for (double x : v) mean += x;
  mean /= std::max<double>(1.0, static_cast<double>(v.size()));
  std::vector<double> out(v.begin(), v.end());
  for (double& x : out) x -= mean;
  return out;
}

/// Biased covariance R(τ) = 1/N Σ a(k+τ) b(k), τ may be negative.
double Cov(const std::vector<double>& a, const std::vector<double>& b, int tau) {
  const int n = static_cast<int>(a.size());
  double sum = 0.0;
  for (int k = std::max(0, -tau); k < n && k + tau < n; ++k) sum += a[k + tau] * b[k];
  return sum / n;
}

}  // namespace

CorrelationTest AutoCorrelationTest(std::span<const double> e, int max_lag) {
  CorrelationTest test;
  const std::vector<double> c = Centred(e);
  const int n = static_cast<int>(c.size());
  max_lag = std::min(max_lag, std::max(0, n - 1));
  const double r0 = Cov(c, c, 0);
  test.bound = kZ99 / std::sqrt(std::max(1, n));
  for (int tau = 0; tau <= max_lag; ++tau) {
    const double r = r0 > 0.0 ? Cov(c, c, tau) / r0 : 0.0;
    test.lags.push_back(tau);
    test.r.push_back(r);
    if (tau == 0) continue;
    if (std::abs(r) > test.bound) ++test.outside;
    if (std::abs(r) > test.worst) {
      test.worst = std::abs(r);
      test.worst_lag = tau;
    }
  }
  return test;
}

CorrelationTest CrossCorrelationTest(std::span<const double> e, std::span<const double> u,
                                     int max_lag) {
  PWSIM_DEMAND(e.size() == u.size());
  CorrelationTest test;
  const std::vector<double> ce = Centred(e), cu = Centred(u);
  const int n = static_cast<int>(ce.size());
  max_lag = std::min(max_lag, std::max(0, n - 1));
  const double re0 = Cov(ce, ce, 0), ru0 = Cov(cu, cu, 0);
  const double norm = std::sqrt(re0 * ru0);
  // Coloured-input variance: P = Σ_k R_e(k) R_u(k), Bartlett-windowed over |k| ≤ M.
  const int m = std::min(n - 1, std::max(25, n / 10));
  double p = re0 * ru0;
  for (int k = 1; k <= m; ++k) {
    const double w = 1.0 - static_cast<double>(k) / (m + 1);
    p += 2.0 * w * Cov(ce, ce, k) * Cov(cu, cu, k);
  }
  test.bound = norm > 0.0 ? kZ99 * std::sqrt(std::max(0.0, p) / n) / norm : 0.0;
  for (int tau = -max_lag; tau <= max_lag; ++tau) {
    const double r = norm > 0.0 ? Cov(ce, cu, tau) / norm : 0.0;
    test.lags.push_back(tau);
    test.r.push_back(r);
    if (std::abs(r) > test.bound) ++test.outside;
    if (std::abs(r) > test.worst) {
      test.worst = std::abs(r);
      test.worst_lag = tau;
    }
  }
  return test;
}

Spectrum WelchSpectrum(std::span<const double> e, double rate_hz, int segment) {
  Spectrum s;
  const int n = static_cast<int>(e.size());
  if (n < 4) return s;
  const int len = std::min(segment, n);
  const int nfft = segment;
  const int step = std::max(1, len / 2);
  std::vector<double> window(len);
  double wsum2 = 0.0;
  for (int k = 0; k < len; ++k) {
    window[k] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * k / std::max(1, len - 1));
    wsum2 += window[k] * window[k];
  }
  const int bins = nfft / 2 + 1;
  s.hz.resize(bins);
  s.psd.assign(bins, 0.0);
  for (int b = 0; b < bins; ++b) s.hz[b] = rate_hz * b / nfft;
  int segments = 0;
  std::vector<double> buf(len);
  for (int start = 0; start + len <= n; start += step) {
    double mean = 0.0;
    for (int k = 0; k < len; ++k) mean += e[start + k];
    mean /= len;
    for (int k = 0; k < len; ++k) buf[k] = (e[start + k] - mean) * window[k];
    for (int b = 0; b < bins; ++b) {
      double re = 0.0, im = 0.0;
      const double w = 2.0 * std::numbers::pi * b / nfft;
      for (int k = 0; k < len; ++k) {
        re += buf[k] * std::cos(w * k);
        im -= buf[k] * std::sin(w * k);
      }
      const double one_sided = (b == 0 || 2 * b == nfft) ? 1.0 : 2.0;
      s.psd[b] += one_sided * (re * re + im * im) / (rate_hz * wsum2);
    }
    ++segments;
  }
  if (segments > 0)
    for (double& v : s.psd) v /= segments;
  return s;
}

double BandFraction(const Spectrum& spectrum, double lo_hz, double hi_hz) {
  double total = 0.0, band = 0.0;
  for (std::size_t b = 1; b < spectrum.psd.size(); ++b) {
    total += spectrum.psd[b];
    if (spectrum.hz[b] >= lo_hz && spectrum.hz[b] < hi_hz) band += spectrum.psd[b];
  }
  return total > 0.0 ? band / total : 0.0;
}

double PeakFrequency(const Spectrum& spectrum, double min_hz) {
  double best = -1.0, hz = 0.0;
  for (std::size_t b = 0; b < spectrum.psd.size(); ++b) {
    if (spectrum.hz[b] < min_hz) continue;
    if (spectrum.psd[b] > best) {
      best = spectrum.psd[b];
      hz = spectrum.hz[b];
    }
  }
  return hz;
}

ScaleLag RegressScaleLag(std::span<const double> y, std::span<const double> m, double rate_hz,
                         double max_lag_s) {
  PWSIM_DEMAND(y.size() == m.size());
  ScaleLag out;
  const int n = static_cast<int>(y.size());
  if (n < 3) return out;
  double mean = 0.0;
  for (double v : y) mean += v;
  mean /= n;
  double dev = 0.0, err = 0.0;
  for (int k = 0; k < n; ++k) {
    dev += (y[k] - mean) * (y[k] - mean);
    err += (y[k] - m[k]) * (y[k] - m[k]);
  }
  dev = std::sqrt(dev);
  out.fit_before = dev > 0 ? 100.0 * (1.0 - std::sqrt(err) / dev) : 0.0;
  const int max_lag = static_cast<int>(std::round(max_lag_s * rate_hz));
  double best = std::numeric_limits<double>::infinity();
  for (int lag = -max_lag; lag <= max_lag; ++lag) {
    // y(k) ≈ g m(k - lag), samples where both exist; edges use the nearest model sample.
    double ym = 0.0, mm = 0.0;
    for (int k = 0; k < n; ++k) {
      const double mk = m[std::clamp(k - lag, 0, n - 1)];
      ym += y[k] * mk;
      mm += mk * mk;
    }
    if (mm <= 0.0) continue;
    const double g = ym / mm;
    double sse = 0.0;
    for (int k = 0; k < n; ++k) {
      const double r = y[k] - g * m[std::clamp(k - lag, 0, n - 1)];
      sse += r * r;
    }
    if (sse < best) {
      best = sse;
      out.scale = g;
      out.lag_s = lag / rate_hz;
    }
  }
  out.fit_after = dev > 0 ? 100.0 * (1.0 - std::sqrt(best) / dev) : 0.0;
  return out;
}

double Correlation(std::span<const double> a, std::span<const double> b) {
  PWSIM_DEMAND(a.size() == b.size());
  const std::vector<double> ca = Centred(a), cb = Centred(b);
  double ab = 0.0, aa = 0.0, bb = 0.0;
  for (std::size_t k = 0; k < ca.size(); ++k) {
    ab += ca[k] * cb[k];
    aa += ca[k] * ca[k];
    bb += cb[k] * cb[k];
  }
  return aa > 0.0 && bb > 0.0 ? ab / std::sqrt(aa * bb) : 0.0;
}

double Slope(std::span<const double> x, std::span<const double> y) {
  PWSIM_DEMAND(x.size() == y.size());
  const std::vector<double> cx = Centred(x), cy = Centred(y);
  double xy = 0.0, xx = 0.0;
  for (std::size_t k = 0; k < cx.size(); ++k) {
    xy += cx[k] * cy[k];
    xx += cx[k] * cx[k];
  }
  return xx > 0.0 ? xy / xx : 0.0;
}

}  // namespace pwsim::diagnose
