#pragma once
// Frequency response of a position loop from chirp (or other broadband) recordings of the
// reference u and the measured position y (shared/spec/platform-data.md,
// `pwsim platform frequency-response`).
//
// Nonparametric: every segment (each recording, or each of `sweeps` equal parts of it, or —
// for a single record — 8 Hann segments with 50 % overlap as MATLAB tfestimate) is detrended
// (mean removed), Hann-windowed and transformed (Eigen FFT); the auto and cross spectra are
// summed over segments and over the FFT bins of log-spaced bands (`bands_per_decade`):
//   H1 = Σ Y U* / Σ |U|²,   γ² = |Σ Y U*|² / (Σ |U|² Σ |Y|²).
// Bands whose input power is below `min_input_fraction` of the strongest are dropped; bands
// with γ² < `min_coherence` are reported but not fitted.
//
// Parametric: G(s) = B(s)/A(s)·e^{−sτ}, A monic of degree n = 2 or 3, B of degree n − 1,
// fitted by Levy's linearised least squares followed by Sanathanan–Koerner iterations
// (weights γ²/(1 − γ²) capped), for every delay τ of a grid (0 … `max_delay_s`), keeping the
// best; fit_pct = 100·(1 − ‖G − Ĝ‖/‖G − mean G‖) on the fitted bands.
// Bandwidth: the lowest ω where |Ĝ(jω)| = |Ĝ(0)|/√2 (bisection on a log grid), from the best
// fit; the nonparametric −3 dB crossing (interpolated between bands) is reported too.

#include <string>
#include <vector>

#include "sysid/platform/axis_recording.h"

namespace pwsim::sysid::platform {

struct FrequencyResponseOptions {
  int sweeps{0};                 ///< equal sweeps per recording; 0 = automatic (see above)
  std::vector<int> orders{2, 3};
  double min_coherence{0.8};
  double min_input_fraction{1e-9};  ///< of the strongest band's input power (guards 0/0 only;
                                    ///< coherence decides what is fitted)
  int bands_per_decade{20};
  double max_delay_s{0.0};       ///< 0 = 3 samples
  int sk_iterations{20};
};

struct FrequencyPoint {
  double w_rad_s{0.0};
  double gain_db{0.0};
  double phase_deg{0.0};  ///< unwrapped
  double coherence{0.0};
  bool fitted{false};
  double re{0.0}, im{0.0};
};

struct FrequencyFit {
  int order{2};
  std::vector<double> num, den;  ///< descending powers of s, den[0] = 1
  double delay_s{0.0};
  double fit_pct{0.0};
  double bandwidth_rad_s{0.0};
};

struct JointFrequencyResponse {
  std::string joint;
  double bandwidth_rad_s{0.0};                ///< from the best fit
  double bandwidth_nonparametric_rad_s{0.0};  ///< 0 when the data never fall 3 dB
  int segments{0};
  std::vector<FrequencyFit> fits;
  std::vector<FrequencyPoint> points;
};

/// @throws std::invalid_argument when no joint has a reference with energy, or the
/// recordings do not share their joints and sampling.
std::vector<JointFrequencyResponse> EstimateFrequencyResponse(
    const std::vector<AxisRecording>& recordings, const FrequencyResponseOptions& options = {});

/// |G(jω)| of a fit (delay ignored: it does not change the gain).
double FitGain(const FrequencyFit& fit, double w_rad_s);

}  // namespace pwsim::sysid::platform
