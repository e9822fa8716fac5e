#include "sysid/platform/frequency_response.h"

#include <Eigen/Dense>
#include <unsupported/Eigen/FFT>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

namespace pwsim::sysid::platform {
namespace {

using Complex = std::complex<double>;

struct Spectra {
  std::vector<double> suu, syy;
  std::vector<Complex> syu;
};

void AddSegment(const std::vector<double>& u, const std::vector<double>& y, std::size_t begin,
                std::size_t len, Spectra& s, Eigen::FFT<double>& fft) {
  std::vector<double> uw(len), yw(len);
  double mu = 0, my = 0;
  for (std::size_t i = 0; i < len; ++i) {
    mu += u[begin + i];
    my += y[begin + i];
  }
  mu /= static_cast<double>(len);
  my /= static_cast<double>(len);
  for (std::size_t i = 0; i < len; ++i) {
    const double w = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) /
                                          static_cast<double>(len));
    uw[i] = w * (u[begin + i] - mu);
    yw[i] = w * (y[begin + i] - my);
  }
  std::vector<Complex> U, Y;
  fft.fwd(U, uw);
  fft.fwd(Y, yw);
  const std::size_t bins = len / 2 + 1;
  if (s.suu.empty()) {
    s.suu.assign(bins, 0.0);
    s.syy.assign(bins, 0.0);
    s.syu.assign(bins, Complex(0, 0));
  }
  for (std::size_t k = 0; k < bins; ++k) {
    s.suu[k] += std::norm(U[k]);
    s.syy[k] += std::norm(Y[k]);
    s.syu[k] += Y[k] * std::conj(U[k]);
  }
}

Complex Poly(const std::vector<double>& c, Complex s) {  // descending powers
  Complex v(0, 0);
  for (double x : c) v = v * s + x;
  return v;
}

// SK fit at fixed delay; returns fit error (complex residual norm) and the model.
double FitRational(const std::vector<double>& w, const std::vector<Complex>& g,
                   const std::vector<double>& weight, int n, double delay, int iterations,
                   std::vector<double>* num, std::vector<double>* den) {
  const int m = n - 1;  // numerator degree
  const std::size_t K = w.size();
  double w0 = 0;  // frequency scaling
  for (double x : w) w0 = std::max(w0, x);
  w0 = std::sqrt(w0 * w.front());
  std::vector<Complex> gd(K);
  for (std::size_t k = 0; k < K; ++k) gd[k] = g[k] * std::exp(Complex(0, w[k] * delay));
  std::vector<double> a(static_cast<std::size_t>(n) + 1, 0.0);  // scaled, descending, a[0] = 1
  a[0] = 1.0;
  std::vector<double> b(static_cast<std::size_t>(m) + 1, 0.0);
  std::vector<double> prev_weight(K, 1.0);
  for (int it = 0; it <= iterations; ++it) {
    const int unknowns = n + m + 1;
    Eigen::MatrixXd x(2 * static_cast<Eigen::Index>(K), unknowns);
    Eigen::VectorXd rhs(2 * static_cast<Eigen::Index>(K));
    for (std::size_t k = 0; k < K; ++k) {
      const Complex s(0, w[k] / w0);
      const double wt = std::sqrt(weight[k]) * prev_weight[k];
      // G·(s^n + Σ a_i s^i) − Σ b_j s^j = 0, unknowns a_{n−1..0}, b_{m..0}
      int col = 0;
      for (int i = n - 1; i >= 0; --i, ++col) {
        const Complex v = gd[k] * std::pow(s, i) * wt;
        x(2 * static_cast<Eigen::Index>(k), col) = v.real();
        x(2 * static_cast<Eigen::Index>(k) + 1, col) = v.imag();
      }
      for (int j = m; j >= 0; --j, ++col) {
        const Complex v = -std::pow(s, j) * wt;
        x(2 * static_cast<Eigen::Index>(k), col) = v.real();
        x(2 * static_cast<Eigen::Index>(k) + 1, col) = v.imag();
      }
      const Complex r = -gd[k] * std::pow(s, n) * wt;
      rhs(2 * static_cast<Eigen::Index>(k)) = r.real();
      rhs(2 * static_cast<Eigen::Index>(k) + 1) = r.imag();
    }
    const Eigen::VectorXd theta = x.colPivHouseholderQr().solve(rhs);
    for (int i = 0; i < n; ++i) a[static_cast<std::size_t>(i) + 1] = theta(i);
    for (int j = 0; j <= m; ++j) b[static_cast<std::size_t>(j)] = theta(n + j);
    for (std::size_t k = 0; k < K; ++k) {
      const double mag = std::abs(Poly(a, Complex(0, w[k] / w0)));
      prev_weight[k] = mag > 0 ? 1.0 / mag : 1.0;
    }
  }
  // Unscale: s' = s/w0 → coefficient of s^p divided by w0^p; make A monic.
  den->assign(static_cast<std::size_t>(n) + 1, 0.0);
  num->assign(static_cast<std::size_t>(m) + 1, 0.0);
  for (int i = 0; i <= n; ++i)
    (*den)[static_cast<std::size_t>(i)] = a[static_cast<std::size_t>(i)] / std::pow(w0, n - i);
  for (int j = 0; j <= m; ++j)
    (*num)[static_cast<std::size_t>(j)] = b[static_cast<std::size_t>(j)] / std::pow(w0, m - j);
  const double lead = (*den)[0];
  for (double& v : *den) v /= lead;
  for (double& v : *num) v /= lead;
  double err = 0;
  for (std::size_t k = 0; k < K; ++k) {
    const Complex s(0, w[k]);
    const Complex model = Poly(*num, s) / Poly(*den, s) * std::exp(-s * delay);
    err += weight[k] * std::norm(g[k] - model);
  }
  return err;
}

double Bandwidth(const FrequencyFit& f, double w_max) {
  const double dc = std::abs(f.num.back() / f.den.back());
  const double target = dc / std::sqrt(2.0);
  double lo = 1e-3, prev_w = lo;
  for (double w = lo; w <= 100.0 * w_max; w *= 1.02) {
    if (FitGain(f, w) < target) {
      double a = prev_w, b = w;
      for (int i = 0; i < 60; ++i) {
        const double mid = std::sqrt(a * b);
        (FitGain(f, mid) < target ? b : a) = mid;
      }
      return std::sqrt(a * b);
    }
    prev_w = w;
  }
  return 0.0;
}

}  // namespace

double FitGain(const FrequencyFit& fit, double w) {
  const Complex s(0, w);
  return std::abs(Poly(fit.num, s) / Poly(fit.den, s));
}

std::vector<JointFrequencyResponse> EstimateFrequencyResponse(
    const std::vector<AxisRecording>& recordings, const FrequencyResponseOptions& o) {
  if (recordings.empty()) throw std::invalid_argument("frequency-response: no recording given");
  const AxisRecording& first = recordings.front();
  std::vector<JointFrequencyResponse> out;
  Eigen::FFT<double> fft;
  for (std::size_t j = 0; j < first.joints.size(); ++j) {
    Spectra s;
    int segments = 0;
    std::size_t len = 0;
    bool has_reference = true;
    for (const AxisRecording& r : recordings) {
      if (r.joints.size() != first.joints.size() || r.joints[j].name != first.joints[j].name ||
          std::abs(r.dt - first.dt) > 1e-3 * first.dt)
        throw std::invalid_argument(r.file.string() +
                                    ": expected the joints and sampling of the first recording");
      const JointRecording& jr = r.joints[j];
      if (jr.reference.empty()) {
        has_reference = false;
        break;
      }
      double lo = 1e300, hi = -1e300;
      for (double v : jr.reference) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
      if (!(hi - lo > 0.0)) {
        has_reference = false;
        break;
      }
      const std::size_t n = jr.reference.size();
      if (o.sweeps > 0 || recordings.size() > 1) {
        const std::size_t parts = static_cast<std::size_t>(std::max(1, o.sweeps));
        const std::size_t seg = n / parts;
        if (len == 0) len = seg;
        for (std::size_t p = 0; p < parts; ++p) {
          AddSegment(jr.reference, jr.position, p * seg, std::min(seg, len), s, fft);
          ++segments;
        }
      } else {
        // 8 segments with 50 % overlap span 4.5 segment lengths (MATLAB tfestimate default).
        const auto seg = static_cast<std::size_t>(static_cast<double>(n) / 4.5);
        len = seg;
        for (std::size_t b = 0; b + seg <= n; b += seg / 2) {
          AddSegment(jr.reference, jr.position, b, seg, s, fft);
          ++segments;
        }
      }
    }
    if (!has_reference) continue;
    JointFrequencyResponse jf;
    jf.joint = first.joints[j].name;
    jf.segments = segments;
    // Bands.
    const double df = 1.0 / (static_cast<double>(len) * first.dt);
    const std::size_t bins = s.suu.size();
    const double f_lo = df, f_hi = df * static_cast<double>(bins - 1);
    const int nb = static_cast<int>(std::ceil(std::log10(f_hi / f_lo) * o.bands_per_decade));
    double max_power = 0.0;
    struct Band {
      double w, suu, syy;
      Complex syu;
    };
    std::vector<Band> bands;
    std::size_t k = 1;
    for (int b = 0; b < nb && k < bins; ++b) {
      const double edge = f_lo * std::pow(10.0, static_cast<double>(b + 1) / o.bands_per_decade);
      Band band{0, 0, 0, Complex(0, 0)};
      double wsum = 0;
      int count = 0;
      while (k < bins && (df * static_cast<double>(k) <= edge || count < 2)) {
        band.suu += s.suu[k];
        band.syy += s.syy[k];
        band.syu += s.syu[k];
        wsum += s.suu[k] * 2.0 * std::numbers::pi * df * static_cast<double>(k);
        ++count;
        ++k;
      }
      if (count == 0 || band.suu <= 0) continue;
      band.w = wsum / band.suu;
      bands.push_back(band);
      max_power = std::max(max_power, band.suu / count);
    }
    std::vector<double> fw, weight;
    std::vector<Complex> fg;
    double phase_prev = 0.0, unwrap = 0.0;
    bool first_point = true;
    for (const Band& b : bands) {
      if (b.suu < o.min_input_fraction * max_power) continue;
      FrequencyPoint p;
      const Complex h = b.syu / b.suu;
      p.w_rad_s = b.w;
      p.gain_db = 20.0 * std::log10(std::abs(h));
      double ph = std::arg(h);
      if (!first_point) {
        while (ph + unwrap - phase_prev > std::numbers::pi) unwrap -= 2.0 * std::numbers::pi;
        while (ph + unwrap - phase_prev < -std::numbers::pi) unwrap += 2.0 * std::numbers::pi;
      }
      first_point = false;
      phase_prev = ph + unwrap;
      p.phase_deg = phase_prev * 180.0 / std::numbers::pi;
      p.coherence = std::norm(b.syu) / (b.suu * b.syy);
      p.fitted = p.coherence >= o.min_coherence;
      p.re = h.real();
      p.im = h.imag();
      if (p.fitted) {
        fw.push_back(p.w_rad_s);
        fg.push_back(h);
        const double c = std::min(p.coherence, 0.999);
        weight.push_back(c / (1.0 - c));
      }
      jf.points.push_back(p);
    }
    // Nonparametric −3 dB crossing relative to the lowest band's gain.
    if (!jf.points.empty()) {
      const double ref = jf.points.front().gain_db;
      for (std::size_t i = 1; i < jf.points.size(); ++i)
        if (jf.points[i].gain_db < ref - 3.0103) {
          const auto& a = jf.points[i - 1];
          const auto& b = jf.points[i];
          const double t = (ref - 3.0103 - a.gain_db) / (b.gain_db - a.gain_db);
          jf.bandwidth_nonparametric_rad_s =
              std::exp(std::log(a.w_rad_s) + t * (std::log(b.w_rad_s) - std::log(a.w_rad_s)));
          break;
        }
    }
    if (fw.size() >= 8) {
      double best_pct = -1e300;
      const double max_delay = o.max_delay_s > 0 ? o.max_delay_s : 3.0 * first.dt;
      double gmean_re = 0, gmean_im = 0;
      for (const Complex& g : fg) {
        gmean_re += g.real();
        gmean_im += g.imag();
      }
      const Complex gmean(gmean_re / static_cast<double>(fg.size()),
                          gmean_im / static_cast<double>(fg.size()));
      for (int order : o.orders) {
        FrequencyFit best;
        double best_err = 1e300;
        for (int d = 0; d <= 30; ++d) {
          const double delay = max_delay * d / 30.0;
          FrequencyFit f;
          f.order = order;
          f.delay_s = delay;
          const double err = FitRational(fw, fg, weight, order, delay, o.sk_iterations, &f.num, &f.den);
          if (std::isfinite(err) && err < best_err) {
            best_err = err;
            best = f;
          }
        }
        double num = 0, den = 0;
        for (std::size_t i = 0; i < fw.size(); ++i) {
          const Complex sj(0, fw[i]);
          const Complex model = Poly(best.num, sj) / Poly(best.den, sj) * std::exp(-sj * best.delay_s);
          num += std::norm(fg[i] - model);
          den += std::norm(fg[i] - gmean);
        }
        best.fit_pct = 100.0 * (1.0 - std::sqrt(num / den));
        best.bandwidth_rad_s = Bandwidth(best, fw.back());
        if (best.fit_pct > best_pct) {
          best_pct = best.fit_pct;
          jf.bandwidth_rad_s = best.bandwidth_rad_s;
        }
        jf.fits.push_back(best);
      }
    }
    out.push_back(std::move(jf));
  }
  if (out.empty())
    throw std::invalid_argument(first.file.string() +
                                ": no joint has a recorded reference that moves (frequency "
                                "response needs reference and position)");
  return out;
}

}  // namespace pwsim::sysid::platform
