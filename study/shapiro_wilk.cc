#include "study/shapiro_wilk.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <boost/math/distributions/normal.hpp>

namespace pwsim::study {
namespace {

/// c[0] + c[1] x + … (Horner).
template <std::size_t N>
double Poly(const double (&c)[N], double x) {
  double r = 0.0;
  for (std::size_t i = N; i-- > 0;) r = r * x + c[i];
  return r;
}

constexpr double kA1[] = {0.0, 0.221157, -0.147981, -2.071190, 4.434685, -2.706056};
constexpr double kA2[] = {0.0, 0.042981, -0.293762, -1.752461, 5.682633, -3.582633};
constexpr double kGamma[] = {-2.273, 0.459};
constexpr double kMuSmall[] = {0.5440, -0.39978, 0.025054, -6.714e-4};
constexpr double kSigmaSmall[] = {1.3822, -0.77857, 0.062767, -0.0020322};
constexpr double kMuLarge[] = {-1.5861, -0.31082, -0.083751, 0.0038915};
constexpr double kSigmaLarge[] = {-0.4803, -0.082676, 0.0030302};

}  // namespace

ShapiroWilk ShapiroWilkTest(std::span<const double> values) {
  const std::size_t n = values.size();
  if (n < 3 || n > 5000)
    throw std::invalid_argument("Shapiro-Wilk: sample size must be between 3 and 5000, got " +
                                std::to_string(n));
  std::vector<double> x(values.begin(), values.end());
  std::sort(x.begin(), x.end());
  if (!(x.back() - x.front() >= 1e-10))  // as R's shapiro.test
    throw std::invalid_argument("Shapiro-Wilk: all values are identical");

  const boost::math::normal normal;
  const double an = static_cast<double>(n);
  const std::size_t half = n / 2;
  std::vector<double> a(half);
  if (n == 3) {
    a[0] = std::sqrt(0.5);
  } else {
    std::vector<double> m(half);
    double m2 = 0.0;
    for (std::size_t i = 0; i < half; ++i) {
      m[i] = boost::math::quantile(normal, (static_cast<double>(i + 1) - 0.375) / (an + 0.25));
      m2 += m[i] * m[i];
    }
    m2 *= 2.0;
    const double big_m = std::sqrt(m2);
    const double u = 1.0 / std::sqrt(an);
    const double a1 = -m[0] / big_m + Poly(kA1, u);
    std::size_t first_scaled = 1;
    double phi = 0.0;
    if (n > 5) {
      const double a2 = -m[1] / big_m + Poly(kA2, u);
      phi = (m2 - 2.0 * m[0] * m[0] - 2.0 * m[1] * m[1]) / (1.0 - 2.0 * a1 * a1 - 2.0 * a2 * a2);
      a[1] = a2;
      first_scaled = 2;
    } else {
      phi = (m2 - 2.0 * m[0] * m[0]) / (1.0 - 2.0 * a1 * a1);
    }
    a[0] = a1;
    const double root_phi = std::sqrt(phi);
    for (std::size_t i = first_scaled; i < half; ++i) a[i] = -m[i] / root_phi;
  }

  // W, on data centred at the mean (the ratio is invariant to shift and scale).
  double mean = 0.0;
  for (double v : x) mean += v;
  mean /= an;
  double ss = 0.0;
  for (double v : x) ss += (v - mean) * (v - mean);
  double num = 0.0;
  for (std::size_t i = 0; i < half; ++i) num += a[i] * (x[n - 1 - i] - x[i]);
  ShapiroWilk r;
  r.w = std::min(1.0, num * num / ss);

  if (n == 3) {
    const double p = (6.0 / std::numbers::pi) * (std::asin(std::sqrt(r.w)) - std::numbers::pi / 3.0);
    r.p = std::max(0.0, p);
    return r;
  }
  double y = std::log1p(-r.w);
  double mu = 0.0;
  double sigma = 0.0;
  if (n <= 11) {
    const double gamma = Poly(kGamma, an);
    if (y >= gamma) {
      r.p = 1e-99;  // as R: beyond the range of the approximation
      return r;
    }
    y = -std::log(gamma - y);
    mu = Poly(kMuSmall, an);
    sigma = std::exp(Poly(kSigmaSmall, an));
  } else {
    const double nu = std::log(an);
    mu = Poly(kMuLarge, nu);
    sigma = std::exp(Poly(kSigmaLarge, nu));
  }
  r.p = boost::math::cdf(boost::math::complement(normal, (y - mu) / sigma));
  return r;
}

}  // namespace pwsim::study
