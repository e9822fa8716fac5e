#pragma once
// Residual diagnostics of a simulation (output-error) model, as MATLAB's resid and the
// anchors' §2.2: normalised autocorrelation (whiteness) and residual-input cross-correlation
// with 99 % bounds (the cross-correlation bound is the coloured-input one,
// var = Σ_k R_e(k) R_u(k) / (N R_e(0) R_u(0))), Welch spectra, an optimal scale/lag regression of
// measured on predicted output, and small helpers (correlation, least-squares slope).

#include <span>
#include <vector>

namespace pwsim::diagnose {

inline constexpr double kZ99 = 2.5758;  ///< two-sided 99 % normal quantile

struct CorrelationTest {
  std::vector<int> lags;   ///< [samples]
  std::vector<double> r;   ///< normalised correlation at each lag
  double bound{0.0};       ///< 99 % bound on |r| (same for every lag)
  int outside{0};          ///< lags (other than 0 for the ACF) with |r| > bound
  double worst{0.0};       ///< largest |r| (lag 0 excluded for the ACF)
  int worst_lag{0};
  bool Passes() const { return outside == 0; }
};

/// r_e(τ) = R_e(τ)/R_e(0) for τ = 0..max_lag; bound 2.58/√N. Mean removed first.
CorrelationTest AutoCorrelationTest(std::span<const double> e, int max_lag = 25);

/// r_eu(τ) = R_eu(τ)/√(R_e(0) R_u(0)) for τ = -max_lag..max_lag (τ > 0: e after u), with the
/// coloured-input 99 % bound. Means removed first. @pre e.size() == u.size().
CorrelationTest CrossCorrelationTest(std::span<const double> e, std::span<const double> u,
                                     int max_lag = 25);

struct Spectrum {
  std::vector<double> hz;   ///< [Hz]
  std::vector<double> psd;  ///< [unit²/Hz], one-sided
};

/// Welch estimate: Hann segments of `segment` samples, 50 % overlap, mean removed per segment.
/// Shorter signals use one zero-padded segment.
Spectrum WelchSpectrum(std::span<const double> e, double rate_hz, int segment = 128);

/// Share of the spectrum's power in [lo_hz, hi_hz).
double BandFraction(const Spectrum& spectrum, double lo_hz, double hi_hz);
/// Frequency of the largest PSD value at or above min_hz (0 when none).
double PeakFrequency(const Spectrum& spectrum, double min_hz);

struct ScaleLag {
  double scale{1.0};   ///< g in y ≈ g ŷ(t - τ)
  double lag_s{0.0};   ///< τ [s], positive: measured lags the model
  double fit_before{0.0};  ///< [%] MATLAB fit of ŷ
  double fit_after{0.0};   ///< [%] fit of g ŷ(t - τ)
};

/// Regression of measured on predicted output over integer-sample lags within ±max_lag_s.
ScaleLag RegressScaleLag(std::span<const double> measured, std::span<const double> model,
                         double rate_hz, double max_lag_s = 0.2);

/// Pearson correlation (0 when either side is constant).
double Correlation(std::span<const double> a, std::span<const double> b);
/// Least-squares slope of y on x (with intercept).
double Slope(std::span<const double> x, std::span<const double> y);

}  // namespace pwsim::diagnose
