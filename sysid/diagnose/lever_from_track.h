#pragma once
// The marker lever's height as the measured track bears it out. A marker at r = (r_x, r_z)
// from O_V on a chair pitched by θ (from its rest value θ₀) records
//   x_m = x_O + r_x cos θ − r_z sin θ,
// so a lever that sits above or below O_V swings the measured x with the pitch, a rigid-body
// fact no dynamics of the model can fake. Against a centred moving average over `window_s`
// (H: y ↦ y − MA_w(y), which removes the chair's travel and a slow drift), per trial i
//   H(x_m) = H(x_O) + r_z H(−sin θ)   (r_x cos θ ≈ r_x: second order),
// and the least squares over every trial given, with a_i = Σ H(x_m) H(−sin θ), b_i = Σ H(−sin θ)²,
//   r̂_z = Σ a_i / Σ b_i,   se = √(Σ (a_i − r̂_z b_i)²) / Σ b_i   (trials as clusters).
// H(x_O) is not white: a chair that pitches with its acceleration (an inertial pitch) moves x_O
// with θ, and that bias is larger the slower the part kept. It is measured by the estimate's
// change between the windows w and 2w (a lever is a geometric gain, the same at every
// frequency); the range the lever's height may take is
//   r̂_z ± (3 se + |r̂_z(2w) − r̂_z(w)| + margin).
// Used by the diagnosis to narrow the marker lever's fit (greybox_fit.h FitOptions::narrowed):
// a lever whose height the x channel refutes cannot take the z and θ residual of another
// effect for its own.

#include <optional>
#include <vector>

#include "sysid/effects/effect_model.h"

namespace pwsim::diagnose {

struct LeverHeightOptions {
  double window_s{0.6};   ///< w [s], the moving average of H
  double margin_m{0.03};  ///< what the range adds to the estimate's spread [m]
  double rest_window_s{0.25};  ///< θ₀: the mean pitch over the first rest_window_s
};

struct LeverHeight {
  double estimate_m{0.0};   ///< r̂_z(w) [m]
  double se_m{0.0};         ///< its standard error over trials [m]
  double bias_m{0.0};       ///< |r̂_z(2w) − r̂_z(w)| [m]
  double lower_m{0.0}, upper_m{0.0};  ///< the range [m]
};

/// r̂_z from `records` (at least two with pitch motion); nullopt where the pitch has nothing
/// faster than the window (Σ b_i = 0) or fewer than two trials move it.
std::optional<LeverHeight> LeverHeightFromTrack(const std::vector<effects::TrialRecord>& records,
                                                const LeverHeightOptions& options = {});

/// θ₀ of a record: its mean pitch over the first `rest_window_s` (the chair at rest, level; at
/// least the first sample). Shared with TrackUnderMarkerLever (diagnose.h).
double RestPitch(const effects::TrialRecord& record, double rest_window_s);

/// y − its centred moving average over `samples` (odd; the window shrinks at the ends).
std::vector<double> MinusMovingAverage(const std::vector<double>& y, std::size_t samples);

}  // namespace pwsim::diagnose
