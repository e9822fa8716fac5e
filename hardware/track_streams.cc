#include "hardware/track_streams.h"

#include <cmath>
#include <stdexcept>

#include "engine/chair_simulator.h"
#include "hardware/session_streams.h"
#include "mca/cueing.h"

namespace pwsim::hw {

SessionStreams BuildTrackSessionStreams(const Scene& scene, const SessionConfig& config,
                                        const mca::SagittalTrack& track, int smooth_ticks,
                                        const std::string& label, std::string* description,
                                        std::optional<mca::McaAlgorithm> algorithm,
                                        const PlatformChoice* platform) {
  const double dt = 1.0 / config.clock_rate_hz;
  if (std::abs(track.dt - dt) > 1e-12 * dt)
    throw std::invalid_argument("track sampled every " + std::to_string(track.dt) +
                                " s, the session ticks every " + std::to_string(dt) + " s");
  if (track.x.size() < 3 || track.z.size() != track.x.size() || track.pitch.size() != track.x.size())
    throw std::invalid_argument("track '" + label + "': expected at least 3 samples of x, z and pitch");
  const mca::McaConfig mca_config = SessionMcaConfig(scene, algorithm, platform);
  CheckSessionPlatform(config, mca_config.platform);
  const std::vector<mca::HeadMotion> head =
      mca::HeadMotionFromTrack(track, scene.occupant.head_offset, smooth_ticks);
  const mca::CueingTrace trace = mca::RunCueing(mca_config, head, dt);
  SessionStreams streams;
  streams.mca_algorithm = mca::McaAlgorithmName(mca_config.algorithm);
  for (std::size_t k = 0; k < trace.commands.size(); k += static_cast<std::size_t>(config.drive_cycle_ticks))
    streams.setpoints.push_back(trace.commands[k].pose);
  for (std::size_t k = 0; k < track.x.size(); k += static_cast<std::size_t>(config.frame_ticks)) {
    ChairSample sample;  // only the pose enters the head pose
    sample.drive.x = track.x[k];
    sample.lm.z = track.z[k];
    sample.lm.pitch = track.pitch[k];
    const mca::HeadPose h = mca::HeadPoseFromChair(sample, scene.occupant.head_offset);
    streams.cameras.push_back(CameraPose(h.x, h.z, h.pitch));
  }
  if (description != nullptr) {
    *description = label + ", MCA (mca::RunCueing, " + mca::McaAlgorithmName(mca_config.algorithm) + ") on platform '" + mca_config.platform.name + "' (" +
                   mca_config.platform_source + "), " + std::to_string(track.x.size()) + " ticks -> " +
                   std::to_string(streams.setpoints.size()) + " setpoints, " +
                   std::to_string(streams.cameras.size()) + " camera poses";
  }
  return streams;
}

}  // namespace pwsim::hw
