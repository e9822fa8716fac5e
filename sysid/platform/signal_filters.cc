#include "sysid/platform/signal_filters.h"

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pwsim::sysid::platform {
namespace {

using Complex = std::complex<double>;

std::vector<double> PolyFromRoots(const std::vector<Complex>& roots) {
  std::vector<Complex> c{Complex(1.0, 0.0)};
  for (const Complex& r : roots) {
    c.push_back(Complex(0.0, 0.0));
    for (std::size_t i = c.size() - 1; i > 0; --i) c[i] -= r * c[i - 1];
  }
  std::vector<double> out(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) out[i] = c[i].real();
  return out;
}

// Low-pass analogue prototype (poles, gain) at cut-off 1 rad/s -> digital low-pass at wn.
TransferFunction DigitalLowpass(std::vector<Complex> poles, double gain, double wn) {
  const double fs2 = 4.0;  // 2 * fs with fs = 2
  const double warped = fs2 * std::tan(std::numbers::pi * wn / 2.0);
  const auto n = static_cast<int>(poles.size());
  for (Complex& p : poles) p *= warped;
  gain *= std::pow(warped, n);
  std::vector<Complex> zd(poles.size(), Complex(-1.0, 0.0));
  std::vector<Complex> pd;
  Complex denominator(1.0, 0.0);
  for (const Complex& p : poles) {
    pd.push_back((fs2 + p) / (fs2 - p));
    denominator *= (fs2 - p);
  }
  gain = gain * (Complex(1.0, 0.0) / denominator).real();
  TransferFunction tf;
  tf.b = PolyFromRoots(zd);
  for (double& v : tf.b) v *= gain;
  tf.a = PolyFromRoots(pd);
  return tf;
}

void CheckDesign(int order, double wn) {
  if (order < 1 || order > 20) throw std::invalid_argument("filter order: expected 1..20");
  if (!(wn > 0.0 && wn < 1.0))
    throw std::invalid_argument("filter cut-off: expected 0 < Wn < 1 (fraction of Nyquist), got " +
                                std::to_string(wn));
}

}  // namespace

TransferFunction Butterworth(int order, double wn) {
  CheckDesign(order, wn);
  std::vector<Complex> poles;
  for (int k = 1; k <= order; ++k) {
    const double angle = std::numbers::pi * (2.0 * k + order - 1.0) / (2.0 * order);
    poles.push_back(std::polar(1.0, angle));
  }
  return DigitalLowpass(poles, 1.0, wn);
}

TransferFunction ChebyshevI(int order, double ripple_db, double wn) {
  CheckDesign(order, wn);
  if (!(ripple_db > 0.0)) throw std::invalid_argument("Chebyshev ripple: expected > 0 dB");
  const double eps = std::sqrt(std::pow(10.0, 0.1 * ripple_db) - 1.0);
  const double mu = std::asinh(1.0 / eps) / order;
  std::vector<Complex> poles;
  Complex product(1.0, 0.0);
  for (int m = -order + 1; m < order; m += 2) {
    const double theta = std::numbers::pi * m / (2.0 * order);
    const Complex p = -std::sinh(Complex(mu, theta));
    poles.push_back(p);
    product *= -p;
  }
  double gain = product.real();
  if (order % 2 == 0) gain /= std::sqrt(1.0 + eps * eps);
  return DigitalLowpass(poles, gain, wn);
}

void Filter(const TransferFunction& tf, const std::vector<double>& x, std::vector<double>& y,
            std::vector<double>& z) {
  const std::size_t n = std::max(tf.a.size(), tf.b.size());
  std::vector<double> b(n, 0.0), a(n, 0.0);
  for (std::size_t i = 0; i < tf.b.size(); ++i) b[i] = tf.b[i] / tf.a[0];
  for (std::size_t i = 0; i < tf.a.size(); ++i) a[i] = tf.a[i] / tf.a[0];
  z.resize(n - 1, 0.0);
  y.resize(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double xk = x[k];
    const double yk = b[0] * xk + (n > 1 ? z[0] : 0.0);
    for (std::size_t i = 0; i + 2 < n; ++i) z[i] = b[i + 1] * xk + z[i + 1] - a[i + 1] * yk;
    if (n > 1) z[n - 2] = b[n - 1] * xk - a[n - 1] * yk;
    y[k] = yk;
  }
}

std::vector<double> SteadyStateInitial(const TransferFunction& tf) {
  const std::size_t n = std::max(tf.a.size(), tf.b.size());
  if (n < 2) return {};
  std::vector<double> b(n, 0.0), a(n, 0.0);
  for (std::size_t i = 0; i < tf.b.size(); ++i) b[i] = tf.b[i] / tf.a[0];
  for (std::size_t i = 0; i < tf.a.size(); ++i) a[i] = tf.a[i] / tf.a[0];
  const auto m = static_cast<Eigen::Index>(n - 1);
  // I - companion(a)^T, with companion(a) first row -a[1:], ones on the subdiagonal.
  Eigen::MatrixXd lhs = Eigen::MatrixXd::Identity(m, m);
  Eigen::VectorXd rhs(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    lhs(i, 0) += a[static_cast<std::size_t>(i) + 1];
    if (i + 1 < m) lhs(i, i + 1) -= 1.0;
    rhs(i) = b[static_cast<std::size_t>(i) + 1] - a[static_cast<std::size_t>(i) + 1] * b[0];
  }
  const Eigen::VectorXd zi = lhs.fullPivLu().solve(rhs);
  return std::vector<double>(zi.data(), zi.data() + m);
}

std::vector<double> PolynomialSteadyState(const TransferFunction& tf, double c0, double c1,
                                          double c2) {
  const std::size_t n = std::max(tf.a.size(), tf.b.size());
  if (n < 2) return {};
  std::vector<double> b(n, 0.0), a(n, 0.0);
  for (std::size_t i = 0; i < tf.b.size(); ++i) b[i] = tf.b[i] / tf.a[0];
  for (std::size_t i = 0; i < tf.a.size(); ++i) a[i] = tf.a[i] / tf.a[0];
  auto moment = [n](const std::vector<double>& c, int j) {
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) s += std::pow(static_cast<double>(i), j) * c[i];
    return s;
  };
  const double sa0 = moment(a, 0), sa1 = moment(a, 1), sa2 = moment(a, 2);
  const double sb0 = moment(b, 0), sb1 = moment(b, 1), sb2 = moment(b, 2);
  if (std::abs(sa0) < 1e-14)
    throw std::invalid_argument("PolynomialSteadyState: the filter has a pole at z = 1");
  const double d2 = c2 * sb0 / sa0;
  const double d1 = (c1 * sb0 - 2.0 * c2 * sb1 + 2.0 * d2 * sa1) / sa0;
  const double d0 = (c0 * sb0 - c1 * sb1 + c2 * sb2 + d1 * sa1 - d2 * sa2) / sa0;
  auto x = [&](double k) { return c0 + c1 * k + c2 * k * k; };
  auto y = [&](double k) { return d0 + d1 * k + d2 * k * k; };
  std::vector<double> z(n - 1, 0.0);
  for (std::size_t j = 0; j + 1 < n; ++j)
    for (std::size_t i = j + 1; i < n; ++i) {
      const double k = static_cast<double>(j) - static_cast<double>(i);
      z[j] += b[i] * x(k) - a[i] * y(k);
    }
  return z;
}

namespace {

// Normalised, equal-length coefficients (a[0] = 1).
struct Coefficients {
  std::vector<double> b, a;
  explicit Coefficients(const TransferFunction& tf) {
    const std::size_t n = std::max(tf.a.size(), tf.b.size());
    b.assign(n, 0.0);
    a.assign(n, 0.0);
    for (std::size_t i = 0; i < tf.b.size(); ++i) b[i] = tf.b[i] / tf.a[0];
    for (std::size_t i = 0; i < tf.a.size(); ++i) a[i] = tf.a[i] / tf.a[0];
  }
};

// Direct form II transposed, in place, over data[0..n) forward (step +1) or backward (step −1),
// from the steady state zi scaled by the first sample visited.
void FilterInPlace(const Coefficients& c, const std::vector<double>& zi, double* data,
                   std::size_t n, bool backward) {
  const std::size_t order = c.a.size();
  double z[32] = {};
  const double first = backward ? data[n - 1] : data[0];
  for (std::size_t i = 0; i + 1 < order; ++i) z[i] = zi[i] * first;
  for (std::size_t step = 0; step < n; ++step) {
    const std::size_t k = backward ? n - 1 - step : step;
    const double xk = data[k];
    const double yk = c.b[0] * xk + (order > 1 ? z[0] : 0.0);
    for (std::size_t i = 0; i + 2 < order; ++i) z[i] = c.b[i + 1] * xk + z[i + 1] - c.a[i + 1] * yk;
    if (order > 1) z[order - 2] = c.b[order - 1] * xk - c.a[order - 1] * yk;
    data[k] = yk;
  }
}

// Zero-phase filters x into `ext` (padded by nfact samples at both ends); returns nfact.
std::size_t FiltFiltPadded(const TransferFunction& tf, const std::vector<double>& x,
                           std::vector<double>& ext) {
  const std::size_t nfilt = std::max(tf.a.size(), tf.b.size());
  const std::size_t nfact = 3 * (nfilt - 1);
  const std::size_t n = x.size();
  if (n <= nfact)
    throw std::invalid_argument("zero-phase filter: the signal has " + std::to_string(n) +
                                " samples, expected more than " + std::to_string(nfact));
  if (nfilt > 32) throw std::invalid_argument("zero-phase filter: order above 31");
  ext.resize(n + 2 * nfact);
  for (std::size_t i = 0; i < nfact; ++i) ext[i] = 2.0 * x[0] - x[nfact - i];
  std::copy(x.begin(), x.end(), ext.begin() + static_cast<std::ptrdiff_t>(nfact));
  for (std::size_t i = 1; i <= nfact; ++i) ext[nfact + n - 1 + i] = 2.0 * x[n - 1] - x[n - 1 - i];
  const Coefficients c(tf);
  const std::vector<double> zi = SteadyStateInitial(tf);
  FilterInPlace(c, zi, ext.data(), ext.size(), false);
  FilterInPlace(c, zi, ext.data(), ext.size(), true);
  return nfact;
}

}  // namespace

std::vector<double> FiltFilt(const TransferFunction& tf, const std::vector<double>& x) {
  thread_local std::vector<double> ext;
  const std::size_t nfact = FiltFiltPadded(tf, x, ext);
  return std::vector<double>(ext.begin() + static_cast<std::ptrdiff_t>(nfact),
                             ext.begin() + static_cast<std::ptrdiff_t>(nfact + x.size()));
}

int DecimateFirstIndex(int n, int r) {
  const int nout = (n + r - 1) / r;
  return r - (r * nout - n) - 1;
}

std::vector<double> Decimate(const std::vector<double>& x, int r) {
  if (r < 1) throw std::invalid_argument("decimation factor: expected >= 1");
  if (r == 1) return x;
  static thread_local int cached_r = 0;
  static thread_local TransferFunction cached;
  if (cached_r != r) {
    cached = ChebyshevI(8, 0.05, 0.8 / r);
    cached_r = r;
  }
  thread_local std::vector<double> ext;
  const std::size_t nfact = FiltFiltPadded(cached, x, ext);
  std::vector<double> out;
  const int n = static_cast<int>(x.size());
  out.reserve(static_cast<std::size_t>(n / r + 1));
  for (int i = DecimateFirstIndex(n, r); i < n; i += r)
    out.push_back(ext[nfact + static_cast<std::size_t>(i)]);
  return out;
}

std::vector<double> DiffCentral(const std::vector<double>& x, double dt) {
  const std::size_t n = x.size();
  if (n < 2) throw std::invalid_argument("differentiation: expected at least 2 samples");
  std::vector<double> d(n);
  for (std::size_t k = 1; k + 1 < n; ++k) d[k] = (x[k + 1] - x[k - 1]) / (2.0 * dt);
  d[0] = (x[1] - x[0]) / dt;
  d[n - 1] = (x[n - 1] - x[n - 2]) / dt;
  return d;
}

}  // namespace pwsim::sysid::platform
