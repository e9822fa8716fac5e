#pragma once
// The session's input streams from a scene: the chair trial of the engine, run through the
// MCA (mca/cueing.h: washout + the platform limiter) on the 2-DoF car platform of seed 001,
// gives the platform setpoints (surge -> rail q2, yaw -> q1) per drive cycle; the head pose of
// the visual channel gives the camera pose per frame.

#include <optional>
#include <string>

#include "engine/scene.h"
#include "mca/config.h"
#include "hardware/session.h"
#include "hardware/session_runner.h"

namespace pwsim::hw {

/// A scene platform without surge and yaw is replaced by the car 2-DoF platform (noted in
/// `description`). @throws InputError (scene sections), std::invalid_argument (clock mismatch).
/// `algorithm` (a command line's --mca) overrides the scene's mca.algorithm.
SessionStreams BuildSessionStreams(const Scene& scene, const SessionConfig& config,
                                   std::string* description,
                                   std::optional<mca::McaAlgorithm> algorithm = std::nullopt);

/// Camera pose for a head at (x, z) [m] with nose-up `pitch` [rad] (y left, z up).
Pose CameraPose(double x, double z, double pitch);

/// The scene's MCA configuration as the session runs it: a scene platform without surge and
/// yaw is replaced by the car 2-DoF platform (said in platform_source).
/// `algorithm`, when given, overrides the scene's mca.algorithm (mca::ChooseAlgorithm).
mca::McaConfig SessionMcaConfig(const Scene& scene, std::optional<mca::McaAlgorithm> algorithm = std::nullopt);

}  // namespace pwsim::hw
