#pragma once
// The session's input streams from a pose track of the chair's O_V (x, z, θ on the engine
// ticks) instead of the scene's chair simulation: e.g. a measured trial replayed as tracked
// (condition T_r of seed 000's study) or the model driven by its measured x(t) (T_m); see
// report/trial_track.h. The track gives the head motion by (smoothed) central differences
// (mca::HeadMotionFromTrack), the pose commands through the session's MCA
// (SessionMcaConfig, one per drive cycle) and the head's camera pose per frame, exactly as
// BuildSessionStreams does for a scene.

#include <optional>
#include <string>

#include "engine/scene.h"
#include "hardware/session.h"
#include "hardware/session_runner.h"
#include "hardware/session_streams.h"
#include "mca/config.h"
#include "mca/head_motion.h"

namespace pwsim::hw {

/// @pre track.dt == 1 / config.clock_rate_hz (checked: std::invalid_argument), ≥ 3 samples.
/// `smooth_ticks` averages the derivatives over ±smooth_ticks (measured tracks are noisy).
/// `label` names the track in `description`.
SessionStreams BuildTrackSessionStreams(const Scene& scene, const SessionConfig& config,
                                        const mca::SagittalTrack& track, int smooth_ticks,
                                        const std::string& label, std::string* description,
                                        std::optional<mca::McaAlgorithm> algorithm = std::nullopt,
                                        const PlatformChoice* platform = nullptr);

}  // namespace pwsim::hw
