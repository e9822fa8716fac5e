#include "tests/truth/measurement_noise.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace pwsim::truth {

std::vector<Biquad> ButterworthLowPass(int order, double cutoff_hz, double rate_hz) {
  if (order < 1 || order > 8) throw std::invalid_argument("Butterworth order must be 1-8");
  if (!(cutoff_hz > 0.0 && cutoff_hz < 0.5 * rate_hz))
    throw std::invalid_argument("Butterworth cut-off must lie in (0, rate/2)");
  const double k = std::tan(std::numbers::pi * cutoff_hz / rate_hz);
  const double k2 = k * k;
  std::vector<Biquad> out;
  for (int i = 0; i < order; ++i) {
    const double psi = std::numbers::pi * (2.0 * i + 1.0 - order) / (2.0 * order);
    if (psi <= 1e-12) continue;  // one section per conjugate pair (ψ > 0), the real pole below
    const double inv_q = 2.0 * std::cos(psi);
    const double d = 1.0 + k * inv_q + k2;
    out.push_back({k2 / d, 2.0 * k2 / d, k2 / d, 2.0 * (k2 - 1.0) / d, (1.0 - k * inv_q + k2) / d});
  }
  if (order % 2 == 1) out.push_back({k / (1.0 + k), k / (1.0 + k), 0.0, (k - 1.0) / (k + 1.0), 0.0});
  return out;
}

std::vector<double> FilterForward(const std::vector<Biquad>& filter, std::vector<double> signal) {
  for (const Biquad& s : filter) {
    double w1 = 0.0, w2 = 0.0;  // transposed direct form II state
    for (double& v : signal) {
      const double in = v;
      const double out = s.b0 * in + w1;
      w1 = s.b1 * in - s.a1 * out + w2;
      w2 = s.b2 * in - s.a2 * out;
      v = out;
    }
  }
  return signal;
}

std::vector<double> FilterZeroPhase(const std::vector<Biquad>& filter, const std::vector<double>& signal) {
  const std::size_t n = signal.size();
  if (n < 2) return signal;
  const std::size_t pad = std::min(n - 1, 3 * (filter.size() + 1));
  std::vector<double> ext;
  ext.reserve(n + 2 * pad);
  for (std::size_t j = pad; j >= 1; --j) ext.push_back(2.0 * signal.front() - signal[j]);
  ext.insert(ext.end(), signal.begin(), signal.end());
  for (std::size_t j = 1; j <= pad; ++j) ext.push_back(2.0 * signal.back() - signal[n - 1 - j]);
  ext = FilterForward(filter, std::move(ext));
  std::reverse(ext.begin(), ext.end());
  ext = FilterForward(filter, std::move(ext));
  std::reverse(ext.begin(), ext.end());
  return {ext.begin() + static_cast<std::ptrdiff_t>(pad), ext.begin() + static_cast<std::ptrdiff_t>(pad + n)};
}

double NoiseVarianceGain(const std::vector<Biquad>& filter, bool zero_phase, std::size_t length) {
  std::vector<double> impulse(length, 0.0);
  impulse[length / 2] = 1.0;  // in the middle: the backward pass rings on both sides
  const std::vector<double> h = zero_phase ? FilterZeroPhase(filter, impulse) : FilterForward(filter, impulse);
  double sum = 0.0;
  for (double v : h) sum += v * v;
  return sum;
}

std::vector<double> ChannelNoiseSequence(const MeasurementNoise& model, const ChannelNoise& ch,
                                         std::size_t n, double rate_hz, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> e(n, 0.0);
  for (double& v : e) v = ch.white_sigma * gauss(rng);
  if (model.lowpass_order > 0)
    e = FilterZeroPhase(ButterworthLowPass(model.lowpass_order, model.lowpass_cutoff_hz, rate_hz), e);
  const double dt = 1.0 / rate_hz;
  if (model.drift_sine) {
    const double phase = 2.0 * std::numbers::pi * unit(rng);
    for (std::size_t k = 0; k < n; ++k)
      e[k] += ch.drift_sine_amp *
              std::sin(2.0 * std::numbers::pi * model.drift_sine_hz * static_cast<double>(k) * dt + phase);
  } else if (ch.drift_walk_sigma > 0.0) {
    double walk = 0.0;
    const double step = ch.drift_walk_sigma * std::sqrt(dt);
    for (std::size_t k = 0; k < n; ++k) {
      if (k > 0) walk += step * gauss(rng);
      e[k] += walk;
    }
  }
  if (model.outlier_prob > 0.0 && ch.outlier_size > 0.0) {
    for (double& v : e) {
      if (unit(rng) >= model.outlier_prob) continue;
      const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
      v += sign * ch.outlier_size * (0.5 + 0.5 * unit(rng));
    }
  }
  return e;
}

}  // namespace pwsim::truth
