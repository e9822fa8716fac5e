#include "hardware/car_session_streams.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pwsim::hw {
namespace {

TEST(CarSessionStreams, SeedDriveGivesSetpointsInsideTheRailAndYawingCameras) {
  const vehicle::CarScene scene =
      vehicle::LoadCarScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/car_seed_drive.yaml");
  SessionConfig config;
  config.clock_rate_hz = scene.clock.rate_hz;
  config.drive_cycle_ticks = 4;
  config.frame_ticks = 10;
  std::string description;
  const SessionStreams streams = BuildCarSessionStreams(scene, config, &description);
  const std::size_t ticks = static_cast<std::size_t>(scene.tick_count());
  EXPECT_EQ(streams.setpoints.size(), (ticks + 3) / 4);
  EXPECT_EQ(streams.cameras.size(), (ticks + 9) / 10);
  double rail = 0.0, yaw = 0.0;
  for (const auto& s : streams.setpoints) {
    yaw = std::max(yaw, std::abs(s[mca::Index(mca::Dof::kYaw)]));
    rail = std::max(rail, std::abs(s[mca::Index(mca::Dof::kSurge)]));
  }
  EXPECT_LE(rail, 0.6 + 1e-9);
  EXPECT_GT(rail, 0.05);
  EXPECT_GT(yaw, 0.01);
  // the route turns +90, -90, +45 deg: the last camera looks 45 deg left of the start
  const Pose& last = streams.cameras.back();
  EXPECT_NEAR(2.0 * std::atan2(last.q[2], last.q[3]), 45.0 * M_PI / 180.0, 0.06);
  EXPECT_NE(description.find("car2dof"), std::string::npos);
}

TEST(CarSessionStreams, CameraQuaternionComposesYawPitchRoll) {
  const Pose p = CarCameraPose({1, 2, 3}, 0.5, 0.0, 0.0);
  EXPECT_NEAR(p.q[2], std::sin(0.25), 1e-12);
  EXPECT_NEAR(p.q[3], std::cos(0.25), 1e-12);
  const Pose q = CarCameraPose({0, 0, 0}, 0.0, 0.2, 0.0);  // nose up: rotation about +y by -0.2
  EXPECT_NEAR(q.q[1], std::sin(-0.1), 1e-12);
}

}  // namespace
}  // namespace pwsim::hw
