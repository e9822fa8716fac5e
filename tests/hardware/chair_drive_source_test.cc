// The chair's live drive source (hardware/chair_drive_source.h): joystick -> chair deflection,
// the chair stepped through its circuit over every tick between session steps, the platform's
// setpoints and the camera on their ticks only, the trace for the training metrics.
#include "hardware/chair_drive_source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "hardware/rnet_joystick.h"
#include "hardware/session_streams.h"

namespace pwsim::hw {
namespace {

TEST(ChairDeflectionFromJoystick, ForwardIsYTurnIsLeftAndLossReleases) {
  JoystickSample s;
  s.valid = true;
  s.x = 0.5;  // right
  s.y = 0.8;
  JoystickInput in = ChairDeflectionFromJoystick(s);
  EXPECT_EQ(in.forward, 0.8);
  EXPECT_EQ(in.turn, -0.5);  // pushed right: turn right (negative)
  s.x = -2.0;                // out of range: clamped
  s.y = -3.0;
  in = ChairDeflectionFromJoystick(s);
  EXPECT_EQ(in.forward, -1.0);
  EXPECT_EQ(in.turn, 1.0);
  s.x = 0.0;
  EXPECT_FALSE(std::signbit(ChairDeflectionFromJoystick(s).turn));  // no -0 in the logs
  s.valid = false;  // lost: released, whatever (x, y) says
  s.y = 1.0;
  in = ChairDeflectionFromJoystick(s);
  EXPECT_EQ(in.forward, 0.0);
  EXPECT_EQ(in.turn, 0.0);
}

struct Drive {
  std::vector<mca::DofArray> setpoints;
  std::vector<Pose> cameras;
  double x{0.0};
  std::size_t trace{0};
};

Drive DriveCourse(const Scene& scene, std::int64_t ticks) {
  RnetLogJoystick log(ReadCandumpFile(std::filesystem::path(PWSIM_SOURCE_DIR) / "assets/rnet/joystick_synthetic.log"),
                      scene.clock.rate_hz, {-1, 100}, "log");
  ChairDriveSource source(scene, log, ticks, SessionMcaConfig(scene));
  Drive d;
  for (std::int64_t tick = 0; tick <= ticks; tick += 2) {  // session steps every 2 ticks
    SessionInputs in;
    const bool drive = tick % 4 == 0, frame = tick % 10 == 0;
    source.Fill(tick, drive, frame, tick, &in);
    EXPECT_EQ(in.setpoint.has_value(), drive) << tick;
    EXPECT_EQ(in.camera.has_value(), frame) << tick;
    if (in.setpoint) d.setpoints.push_back(*in.setpoint);
    if (in.camera) d.cameras.push_back(*in.camera);
  }
  d.x = source.last_sample().planar.x;
  d.trace = source.trace().size();
  EXPECT_EQ(source.invalid_polls() > 0, true) << "the log loses the joystick for a while";
  return d;
}

// Tests that the recorded R-Net log drives the chair forward along the course, the MCA's pose
// command on the PW platform (the scene's pw4dof) tilts it (pitch from the surge acceleration)
// within its travel and never asks for the axes the platform lacks, every tick is in the trace,
// and the same drive gives the same bits.
TEST(ChairDriveSource, TheRnetLogDrivesTheChairAndThePlatformDeterministically) {
  const Scene scene = LoadScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/circuit_course.yaml");
  const Drive a = DriveCourse(scene, 4000);
  EXPECT_GT(a.x, 0.5);
  EXPECT_EQ(a.trace, 4001u);
  double peak_pitch = 0.0;
  for (const auto& s : a.setpoints) {
    for (double x : s) ASSERT_TRUE(std::isfinite(x));
    ASSERT_EQ(s[mca::Index(mca::Dof::kSurge)], 0.0);  // pw4dof moves heave, roll, pitch, yaw
    ASSERT_EQ(s[mca::Index(mca::Dof::kSway)], 0.0);
    peak_pitch = std::max(peak_pitch, std::abs(s[mca::Index(mca::Dof::kPitch)]));
  }
  EXPECT_GT(peak_pitch, 1e-3) << "the chair's acceleration should tilt the platform";
  EXPECT_LE(peak_pitch, 15.0 * mca::kDegToRad);
  // the camera is the head: 1.25 m above O_V, ahead of it by 0.05 m on the course's axis
  EXPECT_NEAR(a.cameras.front().p[2], 1.25, 0.05);
  const Drive b = DriveCourse(scene, 4000);
  ASSERT_EQ(a.setpoints.size(), b.setpoints.size());
  for (std::size_t i = 0; i < a.setpoints.size(); ++i) ASSERT_EQ(a.setpoints[i], b.setpoints[i]) << i;
}

}  // namespace
}  // namespace pwsim::hw
