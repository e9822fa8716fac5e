#pragma once
// The measurement noise of each channel from what the trials themselves offer, with no model:
// the rest window at the start of every trial (the chair still: the channel is a constant
// level plus noise n_k, stationary with variance σ² and normalised autocorrelation r(k)).
// Motion-capture exports are often low-pass filtered, so n is not assumed white.
//
//  variogram   γ(k) = ½ E[(n_{t+k} − n_t)²] = σ² (1 − r(k)),  k = 1..L; it needs no level, and
//              γ̂(k) = ½ (1.4826 median|Δ_k y|)² (Gaussian MAD; robust to outliers), pooled
//              over the windows' pairs;
//  scale       s = 1.4826 median|y − median_window(y)|: deviations about each window's own
//              level, which absorbs part of the noise: E[s²] ≈ σ² (1 − c) with
//              c = (1/n²) Σ_{i,j} r(|i − j|) (large for low-passed noise, whose slow part looks
//              like the level);
//  fixed point σ² ← s² / (1 − c(r)), r(k) = 1 − γ̂(k)/σ² (clamped to [−1, 1]; r(k) = 0 beyond
//              L), iterated to convergence.
// For white noise c = 1/n and r(k) ≈ 0. With fewer than `kMinRestSamples` rest samples the
// noise is taken as white at the 4th-difference σ̂ of the whole trials (verdict.h NoiseSigma).
//
// What the verdict needs from the model (verdict.h):
//  effective samples of n consecutive residual samples, n_eff = n² / Σ_{i,j} r(|i − j|)²
//    (the degrees of freedom of their mean square's χ² allowance);
//  the noise's own mean autocorrelation r̄_n over lags 1..5, against which the residual's
//    whiteness is judged.

#include <cstddef>
#include <vector>

#include "sysid/effects/effect_model.h"

namespace pwsim::diagnose {

struct ChannelNoise {
  double sigma{0.0};     ///< std of the measurement noise [m] or [rad]
  double sigma_hf{0.0};  ///< 4th-difference σ̂ over whole trials (equals sigma for white noise)
  std::vector<double> acf{1.0};  ///< r(0..L), r(0) = 1
  std::size_t rest_samples{0};   ///< samples of the rest windows used
  bool from_rest{false};         ///< false: white noise at sigma_hf assumed

  /// n² / Σ_{i,j<n} r(|i − j|)² (n for white noise).
  double EffectiveSamples(std::size_t n) const;
  /// Mean of r(1..lags) (0 for white noise).
  double MeanAutocorrelation(std::size_t lags = 5) const;
};

struct NoiseModel {
  ChannelNoise z, pitch;
};

inline constexpr std::size_t kMinRestSamples = 20;

/// White noise of std `sigma`.
ChannelNoise WhiteNoise(double sigma);

/// The estimator above: `rest` the rest windows (one per trial), `whole` the whole trials (for
/// sigma_hf and the fallback), `max_lag` L.
ChannelNoise EstimateChannelNoise(const std::vector<std::vector<double>>& rest,
                                  const std::vector<std::vector<double>>& whole,
                                  std::size_t max_lag = 10);

/// Both channels from the first `rest_window` s of each record.
NoiseModel EstimateNoiseModel(const std::vector<effects::TrialRecord>& records, double rest_window);

}  // namespace pwsim::diagnose
