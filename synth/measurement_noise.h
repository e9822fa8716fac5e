#pragma once
// Measurement noise as motion-capture exports carry it, for generators and tests:
//   n_k = f_k + d_k + o_k
//   f: filtered Gaussian noise of stationary std σ:
//        white (no filter);
//        AR(1), f_k = φ f_{k−1} + sqrt(1 − φ²) σ e_k: r(k) = φ^k, spectrum
//          S(ω) = σ² (1 − φ²) / |1 − φ e^{−iω}|²;
//        2nd-order Butterworth low-pass at `low_pass_hz` (bilinear transform, prewarped), its
//          input scaled so that the output's variance σ_in² Σ h_k² is σ²;
//   d: drift, a random walk of std `drift_per_sqrt_s` σ √t (started at 0 at the first sample);
//   o: outliers, each sample with probability `outlier_rate` moved by ±`outlier_sigmas` σ.

#include <cstdint>
#include <random>
#include <vector>

namespace pwsim::synth {

struct NoiseProcess {
  double sigma{0.0};             ///< stationary std of f
  double ar1{0.0};               ///< φ of the AR(1) filter (0: none)
  double low_pass_hz{0.0};       ///< [Hz] Butterworth cut-off (0: none)
  double drift_per_sqrt_s{0.0};  ///< random-walk drift, std after 1 s in σ
  double outlier_rate{0.0};      ///< share of samples with an outlier
  double outlier_sigmas{10.0};   ///< outlier size in σ
  bool White() const { return ar1 == 0.0 && low_pass_hz == 0.0 && drift_per_sqrt_s == 0.0 && outlier_rate == 0.0; }
};

/// Impulse response of the Butterworth filter at rate `rate_hz` (first `length` samples).
std::vector<double> ButterworthImpulse(double low_pass_hz, double rate_hz, std::size_t length);

/// `n` samples of the process at `rate_hz` (the filters started in their stationary state by a
/// run-in of 1000 samples).
std::vector<double> DrawNoise(const NoiseProcess& process, std::size_t n, double rate_hz,
                              std::mt19937_64& rng);

}  // namespace pwsim::synth
