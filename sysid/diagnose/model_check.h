#pragma once
// Does an identified model reproduce measured trials down to their measurement noise? The check
// `pwsim identify` runs on its own result, with the diagnosis' noise model and residual tests,
// so that "measurably wrong" means there what it means to `pwsim diagnose` (whose `adequate` is
// this check passing on the base model).
//
//  1. Noise model from the data alone (noise_model.h): each trial's initial rest (no model
//     involved), outliers replaced first; drift from the model's residual level change between
//     each trial's initial and final rest (AddDrift), as the diagnosis does.
//  2. The model's residual on the judged trials (identification's validation trials, held out
//     of its fits; every trial when there are none) under the verdict's tests (verdict.h
//     (a)-(d)): structured RMS ρ = √max(0, mean e² − σ̂²)/σ̂ against rho_max, the worst window,
//     whiteness against the noise's own colour, correlation with the GM input.
//  3. Measurably wrong when any test fails in either channel. The noise floor (verdict.h
//     NoiseFloorFitPct) is the fitness a model whose residual is that noise would reach on the
//     judged trials: the distance of the model's fitness from it is what the noise cannot
//     explain.
// The model is simulated as the diagnosis simulates its base (greybox_fit.h, no effect:
// identification's model bit for bit), centred on the rest window.

#include <string>
#include <vector>

#include "engine/chair.h"
#include "sysid/diagnose/noise_model.h"
#include "sysid/diagnose/verdict.h"
#include "sysid/measured/measured_trial.h"

namespace pwsim::diagnose {

struct ModelCheck {
  NoiseModel noise;                   ///< from the rests of every trial, drift from the model's residual
  NoiseCheck check;                   ///< the residual tests on the judged trials
  std::vector<std::string> judged;    ///< the trials judged (names)
  bool held_out{true};                ///< the judged trials took no part in the fit
  double noise_floor_z{0.0};          ///< [%] fitness of a model whose residual is the noise
  double noise_floor_pitch{0.0};      ///< [%]
  bool MeasurablyWrong() const { return !check.NoiseLike(); }
};

/// Checks `chair` (with gm and lm) on `trials`: those with `judged[i]` (all when none is) are
/// judged, every trial gives the noise model. @pre trials and judged of one size, ≥ 1 trial.
ModelCheck CheckModelOnTrials(const std::vector<MeasuredTrial>& trials, const Chair& chair,
                              const std::vector<bool>& judged, double rest_window = 0.25,
                              const VerdictOptions& options = {});

}  // namespace pwsim::diagnose
