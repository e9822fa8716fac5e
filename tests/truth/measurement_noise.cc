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

std::vector<double> PinkFilter(const std::vector<double>& white, double lo_hz, double hi_hz, double rate_hz) {
  std::vector<double> out(white.size(), 0.0);
  std::vector<double> a, w;  // y_k = a y_{k−1} + (1 − a) x_k, weight √f
  for (double f = lo_hz; f <= hi_hz * 1.0001; f *= 4.0) {
    a.push_back(std::exp(-2.0 * std::numbers::pi * f / rate_hz));
    w.push_back(std::sqrt(f));
  }
  for (std::size_t j = 0; j < a.size(); ++j) {
    double y = 0.0;
    for (std::size_t k = 0; k < white.size(); ++k) {
      y = a[j] * y + (1.0 - a[j]) * white[k];
      out[k] += w[j] * y;
    }
  }
  // Stationary output variance per unit input variance: the sections share their input, so
  // Σ_i Σ_j w_i w_j (1 − a_i)(1 − a_j) / (1 − a_i a_j).
  double gain = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < a.size(); ++j)
      gain += w[i] * w[j] * (1.0 - a[i]) * (1.0 - a[j]) / (1.0 - a[i] * a[j]);
  const double scale = gain > 0.0 ? 1.0 / std::sqrt(gain) : 0.0;
  for (double& v : out) v *= scale;
  return out;
}

std::vector<double> ChannelNoiseSequence(const MeasurementNoise& model, const ChannelNoise& ch,
                                         std::size_t n, double rate_hz, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> e(n, 0.0);
  for (double& v : e) v = ch.white_sigma * gauss(rng);
  if (model.lowpass_order > 0)
    e = FilterZeroPhase(ButterworthLowPass(model.lowpass_order, model.lowpass_cutoff_hz, rate_hz), e);
  if (model.pink_lo_hz > 0.0) {  // after a run-in of 10 slowest time constants, dropped
    const auto run_in = static_cast<std::size_t>(10.0 * rate_hz / (2.0 * std::numbers::pi * model.pink_lo_hz));
    std::vector<double> longer(run_in);
    for (double& v : longer) v = ch.white_sigma * gauss(rng);
    longer.insert(longer.end(), e.begin(), e.end());
    longer = PinkFilter(longer, model.pink_lo_hz, model.pink_hi_hz, rate_hz);
    e.assign(longer.begin() + static_cast<std::ptrdiff_t>(run_in), longer.end());
  }
  const double dt = 1.0 / rate_hz;
  if (ch.drift_step > 0.0) {
    const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
    const auto at = static_cast<std::size_t>((0.1 + 0.8 * unit(rng)) * static_cast<double>(n));
    for (std::size_t k = at; k < n; ++k) e[k] += sign * ch.drift_step;
  } else if (model.drift_sine) {
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
    for (std::size_t k = 0; k < n; ++k) {
      if (unit(rng) >= model.outlier_prob) continue;
      const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
      const double jump = sign * ch.outlier_size * (0.5 + 0.5 * unit(rng));
      std::size_t length = 1;
      if (model.burst_length > 1)
        length = 1 + std::min<std::size_t>(static_cast<std::size_t>(unit(rng) * model.burst_length),
                                           static_cast<std::size_t>(model.burst_length - 1));
      for (std::size_t j = k; j < std::min(n, k + length); ++j) e[j] += jump;
      k += length - 1;
    }
  }
  return e;
}

}  // namespace pwsim::truth
