#include "hardware/session_streams.h"

#include <cmath>
#include <stdexcept>

#include "engine/chair_simulator.h"
#include "mca/config.h"
#include "mca/cueing.h"
#include "mca/head_motion.h"

namespace pwsim::hw {

Pose CameraPose(double x, double z, double pitch) {
  Pose p;
  p.p = {x, 0.0, z};
  // Nose-up pitch turns +x toward +z: a rotation about +y by -pitch.
  p.q = {0.0, std::sin(-0.5 * pitch), 0.0, std::cos(-0.5 * pitch)};
  return p;
}

mca::McaConfig SessionMcaConfig(const Scene& scene, std::optional<mca::McaAlgorithm> algorithm,
                                const PlatformChoice* platform) {
  mca::McaConfig mca_config = mca::LoadMcaConfig(scene);
  if (platform != nullptr) {
    mca_config.platform = platform->spec;
    mca_config.platform_source = platform->source;
    // the scene's algorithm is checked again on this platform (the MPC's start from rest)
    if (!algorithm) mca::ChooseAlgorithm(mca_config.algorithm, mca_config);
  }
  if (algorithm) mca::ChooseAlgorithm(*algorithm, mca_config);
  return mca_config;
}

void CheckSessionPlatform(const SessionConfig& config, const mca::PlatformSpec& platform) {
  const mca::Mechanism& m = platform.mechanism;
  bool same = m.actuator_count() == config.mechanism.actuator_count();
  for (int i = 0; same && i < m.actuator_count(); ++i)
    same = m.actuator(i).name == config.mechanism.actuator(i).name && m.actuator(i).kind == config.mechanism.actuator(i).kind;
  if (!same)
    throw std::invalid_argument("the session drives platform '" + config.platform + "' (" +
                                std::to_string(config.mechanism.actuator_count()) + " actuators), the MCA cues '" +
                                platform.name + "' (" + std::to_string(m.actuator_count()) + ")");
}

SessionStreams BuildSessionStreams(const Scene& scene, const SessionConfig& config, std::string* description,
                                   std::optional<mca::McaAlgorithm> algorithm) {
  return BuildSessionStreams(scene, config, SessionMcaConfig(scene, algorithm), description);
}

SessionStreams BuildSessionStreams(const Scene& scene, const SessionConfig& config, const mca::McaConfig& mca_config,
                                   std::string* description) {
  CheckSessionPlatform(config, mca_config.platform);
  if (scene.clock.rate_hz != config.clock_rate_hz) {
    throw std::invalid_argument("scene clock " + std::to_string(scene.clock.rate_hz) +
                                " Hz differs from the session clock " +
                                std::to_string(config.clock_rate_hz) + " Hz");
  }
  const std::vector<ChairSample> samples = SimulateScene(scene);
  std::vector<mca::HeadMotion> truth;
  truth.reserve(samples.size());
  for (const ChairSample& s : samples)
    truth.push_back(mca::HeadMotionFromChair(s, scene.occupant.head_offset));
  const mca::CueingTrace trace = mca::RunCueing(mca_config, truth, scene.clock.dt());

  SessionStreams streams;
  streams.mca_algorithm = mca::McaAlgorithmName(mca_config.algorithm);
  for (std::size_t k = 0; k < trace.commands.size(); k += static_cast<std::size_t>(config.drive_cycle_ticks))
    streams.setpoints.push_back(trace.commands[k].pose);
  for (std::size_t k = 0; k < samples.size(); k += static_cast<std::size_t>(config.frame_ticks)) {
    const mca::HeadPose h = mca::HeadPoseFromChair(samples[k], scene.occupant.head_offset);
    streams.cameras.push_back(CameraPose(h.x, h.z, h.pitch));
  }
  if (description != nullptr) {
    *description = std::string("MCA (mca::RunCueing, ") + mca::McaAlgorithmName(mca_config.algorithm) + ") on platform '" + mca_config.platform.name + "' (" +
                   mca_config.platform_source + ", " + std::to_string(config.mechanism.actuator_count()) +
                   " drives), " + std::to_string(samples.size()) +
                   " chair ticks -> " + std::to_string(streams.setpoints.size()) +
                   " pose commands, " + std::to_string(streams.cameras.size()) + " camera poses";
  }
  return streams;
}

}  // namespace pwsim::hw
