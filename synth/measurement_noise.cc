#include "synth/measurement_noise.h"

#include <cmath>
#include <numbers>

#include "engine/check.h"

namespace pwsim::synth {
namespace {

struct Biquad {
  double b0, b1, b2, a1, a2;  ///< y_k = b0 x_k + b1 x_{k-1} + b2 x_{k-2} - a1 y_{k-1} - a2 y_{k-2}
};

/// 2nd-order Butterworth low-pass, bilinear transform with the cut-off prewarped.
Biquad Butterworth(double fc_hz, double rate_hz) {
  const double k = std::tan(std::numbers::pi * fc_hz / rate_hz);
  const double q = std::numbers::sqrt2;
  const double norm = 1.0 / (1.0 + q * k + k * k);
  Biquad f;
  f.b0 = k * k * norm;
  f.b1 = 2.0 * f.b0;
  f.b2 = f.b0;
  f.a1 = 2.0 * (k * k - 1.0) * norm;
  f.a2 = (1.0 - q * k + k * k) * norm;
  return f;
}

std::vector<double> Filter(const Biquad& f, const std::vector<double>& x) {
  std::vector<double> y(x.size());
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    y[k] = f.b0 * x[k] + f.b1 * x1 + f.b2 * x2 - f.a1 * y1 - f.a2 * y2;
    x2 = x1;
    x1 = x[k];
    y2 = y1;
    y1 = y[k];
  }
  return y;
}

}  // namespace

std::vector<double> ButterworthImpulse(double low_pass_hz, double rate_hz, std::size_t length) {
  std::vector<double> x(length, 0.0);
  if (length > 0) x[0] = 1.0;
  return Filter(Butterworth(low_pass_hz, rate_hz), x);
}

std::vector<double> DrawNoise(const NoiseProcess& p, std::size_t n, double rate_hz, std::mt19937_64& rng) {
  PWSIM_DEMAND(p.sigma >= 0.0 && std::abs(p.ar1) < 1.0 && p.low_pass_hz >= 0.0 &&
               p.low_pass_hz < 0.5 * rate_hz && p.outlier_rate >= 0.0 && p.outlier_rate <= 1.0);
  std::normal_distribution<double> unit(0.0, 1.0);
  const std::size_t run_in = 1000;
  std::vector<double> e(n + run_in);
  for (double& v : e) v = unit(rng);
  std::vector<double> f = e;
  if (p.ar1 != 0.0) {
    const double gain = std::sqrt(1.0 - p.ar1 * p.ar1);
    f[0] = e[0];
    for (std::size_t k = 1; k < f.size(); ++k) f[k] = p.ar1 * f[k - 1] + gain * e[k];
  }
  if (p.low_pass_hz > 0.0) {
    double energy = 0.0;
    for (double h : ButterworthImpulse(p.low_pass_hz, rate_hz, 4000)) energy += h * h;
    f = Filter(Butterworth(p.low_pass_hz, rate_hz), f);
    for (double& v : f) v /= std::sqrt(energy);
  }
  std::vector<double> out(f.begin() + static_cast<long>(run_in), f.end());
  std::bernoulli_distribution outlier(p.outlier_rate);
  std::bernoulli_distribution sign(0.5);
  double drift = 0.0;
  const double drift_step = p.drift_per_sqrt_s * p.sigma / std::sqrt(rate_hz);
  for (std::size_t k = 0; k < n; ++k) {
    out[k] *= p.sigma;
    if (p.drift_per_sqrt_s > 0.0) {
      if (k > 0) drift += drift_step * unit(rng);
      out[k] += drift;
    }
    if (p.outlier_rate > 0.0 && outlier(rng)) out[k] += (sign(rng) ? 1.0 : -1.0) * p.outlier_sigmas * p.sigma;
  }
  return out;
}

}  // namespace pwsim::synth
