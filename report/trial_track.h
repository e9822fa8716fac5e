#pragma once
// A measured trial (measured-trials.md) as a pose track of O_V on the session's ticks, in one
// of the two conditions of seed 000's perception study (section V, Fig. 6):
//   kMeasured (T_r): the mocap track (x, z, θ), linearly interpolated on the ticks;
//   kModel    (T_m): the model chair (GM + LM) driven by the same measured x(t) over the
//                    trial's terrain (SimulateMeasuredTrial), as `pwsim mca-validate` does.
// hardware/track_streams.h turns the track into the session's streams.
// It lives in report/ because it joins sysid (the readers) and mca (the track type).

#include <string>

#include "engine/chair.h"
#include "sysid/measured/measured_trial.h"
#include "mca/head_motion.h"

namespace pwsim::report {

enum class TrialSource { kMeasured, kModel };

/// "measured" / "model"; ParseTrialSource returns false for anything else.
const char* TrialSourceName(TrialSource source);
bool ParseTrialSource(const std::string& text, TrialSource* source);

/// The track of `source` on ticks t0 + k·dt from the first mocap sample to the last.
/// @pre model_chair has gm and lm (kModel). @throws std::invalid_argument (< 3 mocap frames).
mca::SagittalTrack TrialTrack(const MeasuredTrial& trial, TrialSource source, const Chair& model_chair,
                              double dt);

}  // namespace pwsim::report
