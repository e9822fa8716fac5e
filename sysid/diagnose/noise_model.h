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
// Outliers (marker swaps, reflections: single samples far off): each sample is compared with
// what its neighbours predict, ŷ_k = (−y_{k−2} + 4 y_{k−1} + 4 y_{k+1} − y_{k+2}) / 6 (exact for
// cubics, so the chair's smooth motion leaves d_k = y_k − ŷ_k ≈ 0; for white noise
// Var d = (1 + 34/36) σ²; at the two first and last samples the line through the two nearest,
// its limit widened by that prediction's larger noise). A sample is an outlier when |d_k|
// exceeds `kOutlierLimit` scales and, of the samples beyond their limits within ±2, it is the
// one whose replacement by ŷ_k leaves no |d| beyond its limit within ±2 (the least left of
// such), or, where no single replacement does (two spikes side by side: one per pass), the
// largest |d| in limits. A spike of size M gives d = M there and −2M/3, M/6 beside it; at the
// second sample it gives the first sample's extrapolation d = −2M, so the largest |d| alone
// would replace the good first sample and keep the spike. The outlier is replaced by ŷ_k. The
// scale is the larger of 1.4826 median|d| and the noise's own σ (the MAD spread of the trial's
// initial rest):
// low-pass-filtered noise makes d tiny, and the chair's kinks at obstacles (wheel contacts)
// would then stand out of d's scale; they stay far below the noise's σ. Done on the measured
// x, Z and θ of every trial before anything else (the fit, the centring on the rest window
// and the noise model would otherwise all carry them).
//
// Drift (a marker or calibration wandering slowly): a stationary model cannot hold it. The
// rests show it at two time scales. (1) The level of a trial's final rest differs from its
// initial rest by D with E D² = q Δt for a random walk of rate q [unit²/s] (Δt between the
// windows' centres), against v = σ² (1/ν_s + 1/ν_e) for stationary noise (ν the windows'
// effective samples). (2) Within each initial rest window of n samples at step h the least-squares
// slope b = Σ c_i y_i, c_i = (t_i − t̄)/Σ(t − t̄)², has E b² = q w + σ² u under a walk plus the
// stationary noise, w = Σ_ij c_i c_j min(t_i, t_j) (≈ 6/(5 L) over a window of length L) and
// u = Σ_ij c_i c_j r(|i − j|) (1/Σ(t − t̄)² = 12/(h² n (n² − 1)) for white noise). A smooth drift
// whose period the trials nearly span (a slow sinusoid) leaves D ≈ 0 but tilts every rest: the
// slopes see it where the level changes cannot. From the base model's residual on the
// training + selection trials (at rest the model is the terrain's geometry alone; the final
// rest's later half only, as the chair settles after it stops): drift when
// Σ D²/v + Σ b²/(σ² u) exceeds χ²_M(0.99) (M the level changes and slopes, each χ²_1 under
// stationary noise) and, per family (level changes, initial-rest slopes; the final rest's tilt
// carries the chair's settling after braking and is not used),
// its mean is not told from 0 by a two-sided t test at 1 % (drift has no sign; a change or
// tilt all trials share is the model's, e.g. a settling it gets wrong; such a family is left
// out). The level changes are left out too where the final rests tilt more than the initial
// ones, (Σ b_e²/v_e) / (Σ b_s²/v_s) beyond F_{N−1,N−1}(0.99) over all trials but the one
// whose final rest tilts most (one trial's step or burst is the data's): the chair still rings
// there for the model (a cause it lacks keeps it moving after braking), with either sign; drift
// and noise tilt both rests alike. The walk-equivalent rate is the larger of the families'
// moment estimates,
//     q̂_D = Σ max(0, D² − v) / Σ Δt,   q̂_b = Σ max(0, b² − σ² u) / Σ w,
// the drift judged at least as rough as the roughest scale shows it (a sinusoid of amplitude A
// and angular frequency ω gives q̂_b ≈ (5 L/6) A² ω²/2 while q̂_D may be ≈ 0). The verdict then
// judges the residual less its slow part,
// a local-linear Gaussian smooth of scale s_d [s] (transfer ≈ 1 − e^{−(2π f s_d)²/2}); a walk
// of rate q leaves above it the variance
//     q s_d ∫₀^∞ (1 − e^{−u²/2})² / u² du / π = q s_d (√2 − 1) / √π  ≈ 0.2337 q s_d,
// and s_d is chosen so that this is `drift_budget` σ² (clamped to [0.15, 4] s; what is left
// is added to the noise variance the tests allow). s_d comes from the rests alone, never from
// the residual's own slow power, which carries the model's errors (a slow inertial-pitch error
// would be taken for drift and removed). Slow model errors below 1/(2π s_d) are not told from
// drift: the price of drifting data, paid only when the rests show drift.
// Where drift is found, the rests' variogram carries it too (a walk adds ½ q k h at lag k,
// which a stationary fit would take for colour): the colour and level are fitted again on
// γ̂(k) − ½ q̂ k h (RefitWithoutDrift).
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

/// Huber's M-estimate of location with the scale held at s = 1.4826 median|y − median y| (the
/// form of R's MASS::huber): μ solves Σ ψ((y_i − μ) / s) = 0, ψ(u) = max(−k, min(k, u)),
/// k = `k_scales`, by the fixed point μ ← mean(clamp(y_i, μ − k s, μ + k s)) from the median
/// (monotone, at most 50 steps, stops at a change below 1e-12 s). 96 % as efficient as the mean
/// for Gaussian data at k = 1.5; a few samples far off (a burst of outliers the replacement
/// leaves) move it by at most k s each / n. The mean where s = 0; 0 when empty.
double HuberLocation(const std::vector<double>& y, double k_scales = 1.5);

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
  double drift_rate{0.0};        ///< q̂ [unit²/s]; 0: no drift found
  double slow_scale_s{0.0};      ///< s_d [s] of the slow part the verdict removes; 0: none
  double drift_left{0.0};        ///< [unit²] drift variance left above it (0.2337 q̂ s_d)
  double drift_statistic{0.0};   ///< Σ D²/v over the trials with both rests
  double drift_bound{0.0};       ///< χ²_N(0.99)
  bool drift_systematic{false};  ///< the changes share a sign (t test): the model's, not drift
  /// the final rests tilt more than the initial ones (F test): the chair still moves there for
  /// the model, so the level changes are the model's and not drift evidence
  bool final_rest_unsettled{false};

  /// n² / Σ_{i,j<n} r(|i − j|)² (n for white noise).
  double EffectiveSamples(std::size_t n) const;
  /// u = Σ_ij c_i c_j r(|i − j|) for the least-squares slope of n samples at step h [1/s²]:
  /// Var b = σ² u under this noise.
  double SlopeVarianceFactor(std::size_t n, double h) const;
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

inline constexpr double kOutlierLimit = 5.0;  ///< scales of d_k beyond which a sample is an outlier

/// Replaces the outliers of `y` (above) by their neighbours' prediction, two passes, with the
/// scale max(1.4826 median|d|, noise_sigma); returns how many were replaced. Series shorter
/// than 7 samples are left as they are.
std::size_t ReplaceOutliers(std::vector<double>& y, double noise_sigma = 0.0, double limit = kOutlierLimit);
/// 1.4826 median|y_k − median y| over the first n samples (0 for n = 0).
double RestSpread(const std::vector<double>& y, std::size_t n);
/// The record with ReplaceOutliers applied to x, Z and θ, each with its RestSpread over the
/// initial rest (RestSamples) as the noise σ.
effects::TrialRecord WithoutOutliers(effects::TrialRecord record, double rest_window);

/// Samples of the final rest of a trial (RestSamples on the time-reversed trial).
std::size_t EndRestSamples(const std::vector<double>& t, const std::vector<double>& x, double rest_window);

/// One trial's level change between its initial and final rest windows, and the slope within each.
struct RestLevelChange {
  double change{0.0};  ///< D: mean over the final rest − mean over the initial rest
  double dt_s{0.0};    ///< Δt between the windows' centres [s]
  std::size_t n_start{0}, n_end{0};
  double slope_start{0.0}, slope_end{0.0};  ///< least-squares slopes b within each window [unit/s]
  double step_s{0.0};                       ///< h, the sampling step of the windows [s]
};

/// w = Σ_ij c_i c_j min(t_i, t_j) of the least-squares slope of n samples at step h: E b² = q w
/// for a random walk of rate q (→ 6/(5 L) for a window of length L = (n − 1) h).
double SlopeWalkFactor(std::size_t n, double h);

/// D of `e` (a residual or a channel) on the trial (t, x); n_start = n_end = 0 when either rest
/// has fewer than kMinRestSamples samples or the two overlap.
RestLevelChange LevelChangeAtRest(const std::vector<double>& t, const std::vector<double>& x,
                                  const std::vector<double>& e, double rest_window);

/// 0.2337 = (√2 − 1)/√π: drift variance left above a slow part of scale s_d, per q s_d.
inline constexpr double kDriftLeftPerScale = 0.2336950;
inline constexpr double kMinSlowScale_s = 0.15;
inline constexpr double kMaxSlowScale_s = 4.0;

/// Sets noise's drift fields from the trials' level changes (above); `budget` the drift
/// variance, in σ², the verdict allows above the slow part.
void EstimateDrift(const std::vector<RestLevelChange>& changes, double budget, ChannelNoise& noise);

/// y less its local-linear Gaussian smooth of scale `scale_s` (kernel cut at ±4 scales): the
/// part of y above ≈ 1/(2π scale_s). y itself when scale_s ≤ 0.
std::vector<double> WithoutSlowPart(const std::vector<double>& t, const std::vector<double>& y, double scale_s);

}  // namespace pwsim::diagnose
