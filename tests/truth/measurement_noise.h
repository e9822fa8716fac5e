#pragma once
// measurement_noise: what a motion-capture export adds to the true track, beyond white
// Gaussian noise (part of the independent truth; shares no code with sysid/ or synth/).
//
//   white:    e_k = σ ξ_k, ξ_k ~ N(0, 1) independent.
//   low-pass: the white sequence filtered forward and backward (zero phase, as exports apply a
//             "zero-lag" Butterworth) by a digital Butterworth low-pass of order n at f_c,
//             designed by the bilinear transform with the cut-off pre-warped, K = tan(π f_c / f_s).
//             Each conjugate analog pole pair at angle ψ from the negative real axis gives
//             H(s) = 1 / (s² + s/Q + 1), Q = 1 / (2 cos ψ), ψ = π (2k + 1 - n) / (2n) > 0, and
//               b = [K², 2K², K²] / D,  a = [1, 2 (K² - 1) / D, (1 - K/Q + K²) / D],
//               D = 1 + K/Q + K²;
//             an odd order adds the real pole: b = [K, K] / (1 + K), a = [1, (K - 1) / (K + 1)].
//             For f_c ≪ f_s the variance of the output is σ² (2 f_c / f_s) B, with the
//             noise-equivalent bandwidth factor of |H|^{2r} (r = 1 one pass, r = 2 forward-
//             backward; m = 2n): B = Γ(1/m) Γ(r - 1/m) / (m Γ(r)), i.e. (π/m) / sin(π/m) for
//             one pass and (1 - 1/m) (π/m) / sin(π/m) forward-backward.
//   drift:    a random walk d_k = d_{k-1} + σ_rw √Δt ξ_k (variance σ_rw² t) or a slow sinusoid
//             A sin(2π f t + φ) with a random phase.
//   outliers: each sample independently with probability p jumps by ± M (sign and 0.5-1 × M
//             at random): marker swaps and reflections; with burst_length b > 1 an outlier
//             starts a burst of 1..b consecutive samples (length uniform) all off by that jump.
// Kinds the law space never draws (only when forced, law_space.h ExtraNoiseKinds), for testing
// the diagnosis on noise it was not calibrated on:
//   pink:      the white sequence through a bank of first-order low-passes at corners spaced by
//              factors of 4 from f_lo to f_hi, each weighted by the square root of its corner:
//              a power spectrum ≈ 1/f between the corners (Σ_j f_j / (f_j² + f²)), scaled back
//              to the white part's variance;
//   step:      the drift as a level step of ± S (sign at random) at a uniform time in the middle
//              80 % of the trial (a marker knocked, a camera moved);
//   quantised: the whole noisy value (truth + noise) rounded to a grid of `quantum`
//              (independent_truth.cc applies it after the noise is added).
// A noise model is any mixture of these, added channel by channel.

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace pwsim::truth {

/// One second-order (or first-order: b2 = a2 = 0) section, a0 = 1.
struct Biquad {
  double b0{1.0}, b1{0.0}, b2{0.0}, a1{0.0}, a2{0.0};
};

/// Butterworth low-pass of `order` (1-8) at `cutoff_hz` for samples at `rate_hz`, as a cascade
/// of sections. @throws std::invalid_argument outside 0 < cutoff < rate / 2 or order 1-8.
std::vector<Biquad> ButterworthLowPass(int order, double cutoff_hz, double rate_hz);

/// The cascade applied forward (direct form II transposed, zero initial state).
std::vector<double> FilterForward(const std::vector<Biquad>& filter, std::vector<double> signal);

/// Forward then backward (zero phase, squared magnitude response). The ends are padded by odd
/// reflection of 3 × (sections + 1) samples (as scipy's filtfilt pads), removed afterwards.
std::vector<double> FilterZeroPhase(const std::vector<Biquad>& filter, const std::vector<double>& signal);

/// Output variance per unit input variance for white input, Σ h_k² of the impulse response
/// (forward, or forward-backward when zero_phase), summed over `length` samples.
double NoiseVarianceGain(const std::vector<Biquad>& filter, bool zero_phase, std::size_t length = 20000);

/// The noise of one channel (m or rad), every term optional (0 = off).
struct ChannelNoise {
  double white_sigma{0.0};       ///< σ of the white part (before the low-pass)
  double drift_walk_sigma{0.0};  ///< σ_rw [unit/√s]
  double drift_sine_amp{0.0};    ///< A
  double outlier_size{0.0};      ///< M
  double drift_step{0.0};        ///< S (step kind)
  double quantum{0.0};           ///< grid of the recorded value (0: not quantised)
};

struct MeasurementNoise {
  /// White only (the historical truth: per sample x, z, pitch drawn in that order, kept bit for
  /// bit) or the general model below.
  bool white_only{true};
  int lowpass_order{0};          ///< 0: not filtered
  double lowpass_cutoff_hz{0.0};
  bool drift_sine{false};        ///< drift as a sinusoid instead of a random walk
  double drift_sine_hz{0.1};
  double outlier_prob{0.0};      ///< p per sample and channel
  int burst_length{1};           ///< outliers in bursts of 1..burst_length samples
  double pink_lo_hz{0.0};        ///< pink part between these corners (0: none)
  double pink_hi_hz{0.0};
  ChannelNoise x, z, pitch;
  std::string kind{"white"};     ///< label: white, lowpass, drift, outliers, mix
};

/// The pink-shaping bank applied to `white` from a zero state, scaled to unit stationary
/// variance per unit input variance (see above).
std::vector<double> PinkFilter(const std::vector<double>& white, double lo_hz, double hi_hz, double rate_hz);

/// The noise sequence of one channel, n samples at rate_hz, from its own generator.
std::vector<double> ChannelNoiseSequence(const MeasurementNoise& model, const ChannelNoise& channel,
                                         std::size_t n, double rate_hz, std::mt19937_64& rng);

}  // namespace pwsim::truth
