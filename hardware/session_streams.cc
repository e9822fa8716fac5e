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

mca::McaConfig SessionMcaConfig(const Scene& scene, std::optional<mca::McaAlgorithm> algorithm) {
  mca::McaConfig mca_config = mca::LoadMcaConfig(scene);
  // The hardware link drives the 2-DoF rail + yaw platform of seed 001. A scene platform with
  // both axes is used as given; otherwise (e.g. the 4-DoF PW platform) the MCA is re-targeted
  // to the car platform, and the description says so.
  std::string note;
  if (scene.section("platform") == nullptr || !mca_config.platform.Has(mca::Dof::kSurge) ||
      !mca_config.platform.Has(mca::Dof::kYaw)) {
    if (scene.section("platform") != nullptr)
      note = " (scene platform '" + mca_config.platform.name + "' lacks surge or yaw: replaced)";
    mca_config.platform = mca::MakeCar2DofPlatform();
    mca_config.platform_source = "built-in car 2-DoF (seed 001)" + note;
  }
  if (algorithm) mca::ChooseAlgorithm(*algorithm, mca_config);
  return mca_config;
}

SessionStreams BuildSessionStreams(const Scene& scene, const SessionConfig& config,
                                   std::string* description, std::optional<mca::McaAlgorithm> algorithm) {
  const mca::McaConfig mca_config = SessionMcaConfig(scene, algorithm);
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
  for (std::size_t k = 0; k < trace.commands.size(); k += static_cast<std::size_t>(config.drive_cycle_ticks)) {
    const auto& pose = trace.commands[k].pose;
    streams.setpoints.push_back({pose[static_cast<std::size_t>(mca::Index(mca::Dof::kYaw))],
                                 pose[static_cast<std::size_t>(mca::Index(mca::Dof::kSurge))]});
  }
  for (std::size_t k = 0; k < samples.size(); k += static_cast<std::size_t>(config.frame_ticks)) {
    const mca::HeadPose h = mca::HeadPoseFromChair(samples[k], scene.occupant.head_offset);
    streams.cameras.push_back(CameraPose(h.x, h.z, h.pitch));
  }
  if (description != nullptr) {
    *description = std::string("MCA (mca::RunCueing, ") + mca::McaAlgorithmName(mca_config.algorithm) + ") on platform '" + mca_config.platform.name + "' (" +
                   mca_config.platform_source + "), " + std::to_string(samples.size()) +
                   " chair ticks -> " + std::to_string(streams.setpoints.size()) +
                   " setpoints, " + std::to_string(streams.cameras.size()) + " camera poses";
  }
  return streams;
}

}  // namespace pwsim::hw
