#pragma once
// The measurement noise of each channel from what the trials themselves offer, with no model:
// the rest at the start of every trial (RestSamples; the chair still: the channel is a constant
// level plus noise n_k, stationary with variance σ² and normalised autocorrelation r(k)).
// Motion-capture exports are often low-pass filtered, so n is not assumed white.
//
//  variogram   γ(k) = ½ E[(n_{t+k} − n_t)²] = σ² (1 − r(k)),  k = 1..L; it needs no level:
//              γ̂(k) = ½ mean (Δ_k y)² over the windows' pairs, differences beyond 4 MAD-sigmas
//              (1.4826 median|Δ_k y|) left out as outliers;
//  colour      one of two forms with a correlation time τ [samples]:
//                first order (white noise through a 1st-order low-pass, AR(1)): r(k) = e^{−k/τ};
//                second order (a critically damped 2nd-order low-pass, smooth noise):
//                r(k) = (1 + k/τ) e^{−k/τ};
//              σ², form and τ by least squares on γ̂(k) = σ² (1 − r(k)), k = 1..L (σ² in closed
//              form on a log grid of τ in [0.05, 50] samples, τ = 0 white). The sill σ² is the
//              noise power a window's own level hides from a deviation-based scale.
// White noise gives φ ≈ 0, γ̂(k) ≈ σ². With fewer than `kMinRestSamples` rest samples the
// noise is taken as white at the 4th-difference σ̂ of the whole trials (verdict.h NoiseSigma).
// A filter in the export acts on every channel alike, so the diagnosis fits one colour to x, Z
// and θ together (FitNoiseColour), each with its own level: three times the data for τ.
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

/// Median of `v` (the mean of the two middle values for an even count; 0 when empty).
double Median(std::vector<double> v);

enum class NoiseColour { kFirstOrder, kSecondOrder };

/// r(k) of the colour form with correlation time τ [samples] (0: white).
double ColourAutocorrelation(NoiseColour form, double tau, std::size_t k);

struct ChannelNoise {
  double sigma{0.0};     ///< std of the measurement noise [m] or [rad]
  double sigma_hf{0.0};  ///< 4th-difference σ̂ over whole trials (equals sigma for white noise)
  /// One-sided 95 % upper bound of σ: σ̂ sqrt(ν / χ²_ν(0.05)), ν the rest windows' effective
  /// samples (Σ EffectiveSamples(n_w)); what the verdict's magnitude tests judge against (a
  /// level from a few hundred correlated samples is uncertain by ±20 %). sigma when not from rest.
  double sigma_upper{0.0};
  NoiseColour colour{NoiseColour::kFirstOrder};
  double tau_samples{0.0};       ///< correlation time [samples]; 0: white
  std::vector<double> acf{1.0};  ///< r(0..) while |r| ≥ 1e-3, r(0) = 1
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
ChannelNoise WhiteNoise(double sigma);  ///< sigma_upper = sigma

/// The estimator above: `rest` the rest windows (one per trial), `whole` the whole trials (for
/// sigma_hf and the fallback), `max_lag` L.
ChannelNoise EstimateChannelNoise(const std::vector<std::vector<double>>& rest,
                                  const std::vector<std::vector<double>>& whole,
                                  std::size_t max_lag = 20);

/// [m] departure of x from its rest level that ends a rest window at the least.
inline constexpr double kRestMotion_m = 1e-3;

/// Samples of the initial rest of a trial: at least those of the first `rest_window` s (which
/// the diagnosis takes as rest anyway), extended while x stays within max(6 σ̂_x, 1 mm) of its
/// median there (σ̂_x the MAD scale of that window), less 2 samples before the departure; not
/// extended when 6 σ̂_x > 5 mm (the chair moves in that window already).
std::size_t RestSamples(const std::vector<double>& t, const std::vector<double>& x, double rest_window);

/// γ̂(0..L) of the rest windows (fewer lags where fewer than kMinRestSamples pairs remain).
std::vector<double> RestVariogram(const std::vector<std::vector<double>>& rest, std::size_t max_lag = 20);

/// Sets noise.sigma_upper from the rest windows it was estimated on.
void SetUpperBound(const std::vector<std::vector<double>>& rest, ChannelNoise& noise);

/// One colour (form, τ) fitted to several channels' variograms at once (each in units of its
/// mean over lags), a sill σ² each.
std::vector<ChannelNoise> FitNoiseColour(const std::vector<std::vector<double>>& variograms);

/// Both channels from the initial rest of each record (RestSamples); the colour shared by x, Z
/// and θ (the export's filter acts on every channel), the level each channel's own.
NoiseModel EstimateNoiseModel(const std::vector<effects::TrialRecord>& records, double rest_window);

}  // namespace pwsim::diagnose
