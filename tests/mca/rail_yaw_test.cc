// The rail + yaw chain against the closed forms of a point on a turning rail.
#include "mca/rail_yaw.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pwsim::mca {
namespace {

constexpr double kDt = 1e-3;

std::vector<DofArray> Poses(std::size_t n, auto&& rail, auto&& yaw) {
  std::vector<DofArray> poses(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * kDt;
    poses[k][Index(Dof::kSurge)] = rail(t);
    poses[k][Index(Dof::kYaw)] = yaw(t);
  }
  return poses;
}

TEST(RailYaw, CabinOffTheAxisFeelsCentripetalAndCoriolis) {
  PlatformSpec p = MakeCar2DofPlatform();
  p.head_from_pivot = {0.0, 0.0, 0.8};
  const double w = 0.3;  // rad/s turntable
  // cabin held at x = 0.5 m: centripetal -w² x along the rail, nothing across
  auto held = DeliveredRailYawHeadMotion(p, Poses(200, [](double) { return 0.5; }, [&](double t) { return w * t; }), kDt);
  EXPECT_NEAR(held[100].fs[0], -w * w * 0.5, 1e-6);
  EXPECT_NEAR(held[100].fs[1], 0.0, 1e-6);
  EXPECT_NEAR(held[100].fs[2], kGravity, 1e-9);
  EXPECT_NEAR(held[100].w[2], w, 1e-9);
  // cabin moving at 0.4 m/s through the axis: Coriolis 2 w v across the rail
  auto moving = DeliveredRailYawHeadMotion(p, Poses(200, [](double t) { return -0.04 + 0.4 * t; }, [&](double t) { return w * t; }), kDt);
  EXPECT_NEAR(moving[100].fs[1], 2.0 * w * 0.4, 1e-5);
  EXPECT_NEAR(moving[100].fs[0], 0.0, 1e-5);  // at x = 0 at t = 0.1 s
  // yaw accelerating at 0.5 rad/s² with the cabin at 0.5 m: tangential ψ̈ x across the rail
  auto accel = DeliveredRailYawHeadMotion(p, Poses(200, [](double) { return 0.5; }, [](double t) { return 0.25 * t * t; }), kDt);
  const double r = 0.5 * 0.1;
  EXPECT_NEAR(accel[100].fs[1], 0.5 * 0.5, 1e-5);
  EXPECT_NEAR(accel[100].fs[0], -r * r * 0.5, 1e-5);
}

TEST(RailYaw, FalseCueFromCommands) {
  std::vector<McaCommand> commands(3);
  commands[1].pose[Index(Dof::kSurge)] = 0.4;
  commands[1].rate[Index(Dof::kSurge)] = -0.2;
  commands[1].rate[Index(Dof::kYaw)] = 0.3;
  commands[1].accel[Index(Dof::kYaw)] = 0.5;
  const RailYawFalseCues cues = RailYawFalseCue(VestibularParams{}, commands, kDt);
  EXPECT_NEAR(cues.surge[1], -0.09 * 0.4, 1e-15);
  EXPECT_NEAR(cues.sway[1], 0.5 * 0.4 + 2.0 * 0.3 * -0.2, 1e-15);
  EXPECT_EQ(cues.surge[0], 0.0);
  EXPECT_NEAR(cues.peak_sway, std::abs(0.2 - 0.12), 1e-15);
  EXPECT_EQ(cues.sway_above_threshold_count, 0);  // 0.08 < 0.17 m/s²
}

TEST(RailYaw, AtTheAxisItIsTheGenericPlatform) {
  // cabin at x = 0 and the head on the yaw axis: no false cue, same as cue_analysis's kinematics
  PlatformSpec p = MakeCar2DofPlatform();
  auto poses = Poses(300, [](double) { return 0.0; }, [](double t) { return 0.2 * std::sin(3.0 * t); });
  const auto rail = DeliveredRailYawHeadMotion(p, poses, kDt);
  const auto generic = DeliveredHeadMotion(p, poses, kDt);
  for (std::size_t k = 1; k + 1 < poses.size(); ++k) {
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(rail[k].fs[i], generic[k].fs[i], 1e-6);
      EXPECT_NEAR(rail[k].w[i], generic[k].w[i], 1e-6);
    }
  }
}

}  // namespace
}  // namespace pwsim::mca
