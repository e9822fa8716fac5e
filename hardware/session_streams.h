#pragma once
// The session's input streams from a scene: the chair trial of the engine, run through the
// MCA (mca/cueing.h: washout or MPC with the platform's limits) on the session's platform,
// gives the MCA's pose command per drive cycle (the core turns it into actuator setpoints by
// inverse kinematics: session_core.h); the head pose of the visual channel gives the camera
// pose per frame. The platform is the scene's own (a chair scene's `platform:`, by default
// the PW platform pw4dof: heave, roll, pitch and yaw on five drives), or one chosen on the
// command line (`--platform FILE`).

#include <optional>
#include <string>

#include "engine/scene.h"
#include "mca/config.h"
#include "mca/platform.h"
#include "hardware/session.h"
#include "hardware/session_runner.h"

namespace pwsim::hw {

/// A platform chosen over the scene's (a command line's --platform FILE).
struct PlatformChoice {
  mca::PlatformSpec spec;
  std::string source;  ///< where it came from (the file), for the record
};

/// The scene's MCA configuration as the session runs it: the scene's platform, or `platform`
/// over it; `algorithm`, when given, overrides the scene's mca.algorithm (mca::ChooseAlgorithm).
/// @throws InputError (scene sections), std::invalid_argument (an MPC that cannot start).
mca::McaConfig SessionMcaConfig(const Scene& scene, std::optional<mca::McaAlgorithm> algorithm = std::nullopt,
                                const PlatformChoice* platform = nullptr);

/// The streams of `scene` through `mca` (SessionMcaConfig). @throws std::invalid_argument
/// (clock mismatch, or a session configured for another mechanism than mca.platform's).
SessionStreams BuildSessionStreams(const Scene& scene, const SessionConfig& config, const mca::McaConfig& mca,
                                   std::string* description);
/// The same with SessionMcaConfig(scene, algorithm).
SessionStreams BuildSessionStreams(const Scene& scene, const SessionConfig& config, std::string* description,
                                   std::optional<mca::McaAlgorithm> algorithm = std::nullopt);

/// Throws std::invalid_argument unless `config` drives `platform`'s mechanism (same actuators).
void CheckSessionPlatform(const SessionConfig& config, const mca::PlatformSpec& platform);

/// Camera pose for a head at (x, z) [m] with nose-up `pitch` [rad] (y left, z up).
Pose CameraPose(double x, double z, double pitch);

}  // namespace pwsim::hw
