#pragma once
// The session's input streams from one measured trial (measured-trials.md), for a perception
// study that compares the tracked motion of the real chair with the model's (seed 000, sec. V):
//   kMeasured (condition T_r, Fig. 6a): the mocap track of O_V (x, z, θ), resampled linearly
//             on the engine ticks;
//   kModel    (condition T_m, Fig. 6b): the model chair (GM + LM) driven by the same measured
//             x(t) over the trial's terrain (engine/measured SimulateMeasuredTrial).
// Either track gives the head motion by smoothed central differences (mca::HeadMotionFromTrack),
// the platform setpoints through the session's MCA (SessionMcaConfig, per drive cycle) and the
// camera poses of the head (per frame), exactly as BuildSessionStreams does for a scene.

#include <string>

#include "engine/chair.h"
#include "engine/measured/measured_trial.h"
#include "engine/scene.h"
#include "hardware/session.h"
#include "hardware/session_runner.h"
#include "mca/head_motion.h"

namespace pwsim::hw {

enum class TrialSource { kMeasured, kModel };

/// "measured" / "model"; ParseTrialSource returns false for anything else.
const char* TrialSourceName(TrialSource source);
bool ParseTrialSource(const std::string& text, TrialSource* source);

/// The O_V track of `source` on ticks of `dt` [s] from the first mocap sample to the last.
/// @pre model_chair has gm and lm (kModel). @throws std::invalid_argument (< 3 mocap frames).
mca::SagittalTrack TrialTrack(const MeasuredTrial& trial, TrialSource source, const Chair& model_chair,
                              double dt);

/// Streams for a session of `trial` replayed as `source`. `smooth_ticks` averages the track's
/// derivatives (measured tracks are noisy). @throws std::invalid_argument, InputError.
SessionStreams BuildTrialSessionStreams(const Scene& scene, const SessionConfig& config,
                                        const MeasuredTrial& trial, TrialSource source,
                                        const Chair& model_chair, int smooth_ticks,
                                        std::string* description);

}  // namespace pwsim::hw
