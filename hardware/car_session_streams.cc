#include "hardware/car_session_streams.h"

#include <cmath>
#include <stdexcept>

#include "hardware/car_drive_source.h"
#include "hardware/car_live.h"
#include "hardware/session_streams.h"
#include "mca/config.h"
#include "mca/cueing.h"
#include "mca/rail_yaw.h"

namespace pwsim::hw {
namespace {

using Quat = std::array<double, 4>;  // x, y, z, w

Quat Multiply(const Quat& a, const Quat& b) {
  return {a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
          a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
          a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
          a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}

}  // namespace

Pose CarCameraPose(const std::array<double, 3>& p, double yaw, double pitch, double roll) {
  const Quat qz{0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw)};
  const Quat qy{0.0, std::sin(-0.5 * pitch), 0.0, std::cos(-0.5 * pitch)};
  const Quat qx{std::sin(0.5 * roll), 0.0, 0.0, std::cos(0.5 * roll)};
  Pose pose;
  pose.p = p;
  pose.q = Multiply(Multiply(qz, qy), qx);
  return pose;
}

SessionStreams BuildCarSessionStreams(const vehicle::CarScene& scene, const SessionConfig& config,
                                      std::string* description, std::optional<mca::McaAlgorithm> algorithm) {
  mca::McaConfig mca_config = mca::LoadCarMcaConfig(scene);
  if (!mca_config.platform.Has(mca::Dof::kSurge) || !mca_config.platform.Has(mca::Dof::kYaw)) {
    throw std::invalid_argument("car scene platform '" + mca_config.platform.name +
                                "' lacks surge or yaw; the session drives seed 001's rail + yaw platform");
  }
  if (algorithm) mca::ChooseAlgorithm(*algorithm, mca_config);
  CheckSessionPlatform(config, mca_config.platform);
  if (scene.clock.rate_hz != config.clock_rate_hz) {
    throw std::invalid_argument("scene clock " + std::to_string(scene.clock.rate_hz) +
                                " Hz differs from the session clock " + std::to_string(config.clock_rate_hz) + " Hz");
  }
  const std::vector<vehicle::CarSample> samples = vehicle::SimulateCarScene(scene);
  std::vector<mca::HeadMotion> truth(samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const vehicle::CarHeadMotion m = vehicle::HeadMotionOfCar(samples[k], scene.head_offset);
    truth[k].fs = m.fs;
    truth[k].w = m.w;
  }
  const mca::CueingTrace trace = mca::RunRailYawCueing(mca_config, truth, scene.clock.dt());

  SessionStreams streams;
  streams.mca_algorithm = mca::McaAlgorithmName(mca_config.algorithm);
  for (std::size_t k = 0; k < trace.commands.size(); k += static_cast<std::size_t>(config.drive_cycle_ticks))
    streams.setpoints.push_back(trace.commands[k].pose);
  for (std::size_t k = 0; k < samples.size(); k += static_cast<std::size_t>(config.frame_ticks))
    streams.cameras.push_back(CarEyePose(scene, samples[k].state));
  if (description != nullptr) {
    *description = "car '" + scene.car.name + "' MCA (mca::RunRailYawCueing, " +
                   mca::McaAlgorithmName(mca_config.algorithm) + ") on platform '" +
                   mca_config.platform.name + "' (" + mca_config.platform_source + "), " +
                   std::to_string(samples.size()) + " car ticks -> " + std::to_string(streams.setpoints.size()) +
                   " setpoints, " + std::to_string(streams.cameras.size()) + " camera poses";
  }
  return streams;
}

}  // namespace pwsim::hw
