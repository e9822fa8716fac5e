// The live drive source (hardware/car_drive_source.h) and the latency measure it feeds
// (hardware/input_latency.h): joystick -> two-pedal car controls, the car stepped over every tick
// between session steps exactly as the per-tick loop would, the latency counted once per reading.
#include "hardware/car_drive_source.h"

#include <gtest/gtest.h>

#include "hardware/input_latency.h"
#include "hardware/rnet_joystick.h"

namespace pwsim::hw {
namespace {

TEST(CarControlsFromJoystick, PedalsSteeringClutchAndLoss) {
  const JoystickCarParams p;
  JoystickSample s;
  s.valid = true;
  s.y = 0.5;
  s.x = 0.5;
  vehicle::DriverInput in = CarControlsFromJoystick(s, 0.0, p);
  EXPECT_EQ(in.throttle, 0.5);
  EXPECT_EQ(in.brake, 0.0);
  EXPECT_EQ(in.steer, -0.5 * p.steer_lock_rad);  // pushed right: steer right (negative)
  EXPECT_EQ(in.gear, 1);
  EXPECT_EQ(in.clutch, p.bite_clutch);            // launching: at the biting point
  EXPECT_EQ(CarControlsFromJoystick(s, 1.5, p).clutch, 0.5 * p.bite_clutch);
  EXPECT_EQ(CarControlsFromJoystick(s, 10.0, p).clutch, 0.0);  // closed above v_engage
  s.y = -0.25;
  in = CarControlsFromJoystick(s, 0.5, p);
  EXPECT_EQ(in.throttle, 0.0);
  EXPECT_EQ(in.brake, 0.25);
  EXPECT_EQ(in.clutch, 1.0);  // no throttle, slow: open, no stall
  s.valid = false;            // lost joystick: full brake, clutch open, whatever (x, y) says
  s.y = 1.0;
  in = CarControlsFromJoystick(s, 5.0, p);
  EXPECT_EQ(in.throttle, 0.0);
  EXPECT_EQ(in.brake, 1.0);
  EXPECT_EQ(in.clutch, 1.0);
}

TEST(InputLatency, EachReadingCountsOnceAtItsFirstOutput) {
  InputLatency latency(3);
  latency.OnOutput({0, -1}, 100);               // no reading yet: nothing
  latency.OnOutput({1, 1'000'000}, 3'000'000);  // 2 ms
  latency.OnOutput({1, 1'000'000}, 7'000'000);  // the same reading again: not counted
  latency.OnOutput({3, 5'000'000}, 5'500'000);  // reading 2 was superseded unseen: 0.5 ms
  latency.OnOutput({4, 6'000'000}, 10'000'000); // 4 ms
  latency.OnOutput({5, 6'000'000}, 10'000'000); // beyond the capacity: counted as overflow
  const Percentiles p = latency.Summary();
  EXPECT_EQ(p.n, 3U);
  EXPECT_DOUBLE_EQ(p.p50, 2.0);
  EXPECT_DOUBLE_EQ(p.max, 4.0);
  EXPECT_DOUBLE_EQ(p.mean, (2.0 + 0.5 + 4.0) / 3.0);
  EXPECT_EQ(latency.overflow(), 1U);
}

/// A joystick that plays a fixed script: (x, y) of each tick, one new reading per change.
class ScriptedJoystick final : public JoystickSource {
 public:
  JoystickSample Poll(std::int64_t tick, std::int64_t now_ns) override {
    JoystickSample s;
    s.valid = true;
    s.y = tick < 500 ? 0.0 : 0.7;
    s.x = tick < 2000 ? 0.0 : -0.3;
    if (s.y != last_y_ || s.x != last_x_) {
      ++seq_;
      input_ns_ = now_ns;
    }
    last_y_ = s.y;
    last_x_ = s.x;
    s.input_seq = seq_;
    s.input_ns = input_ns_;
    return s;
  }
  std::string name() const override { return "script"; }

 private:
  double last_x_{-2}, last_y_{-2};
  std::uint64_t seq_{0};
  std::int64_t input_ns_{-1};
};

TEST(CarDriveSource, StepsTheCarOverEveryTickLikeThePerTickLoop) {
  const vehicle::CarScene scene =
      vehicle::LoadCarScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/car_launch.yaml");
  const mca::McaConfig mca = mca::LoadCarMcaConfig(scene);
  ScriptedJoystick joystick;
  CarDriveSource source(scene, mca, joystick);
  // The truth: the per-tick loop with the reading held between session steps.
  ScriptedJoystick truth_joystick;
  CarLiveLoop truth(scene, mca);
  std::int64_t truth_tick = 0;
  SessionInputs in;
  for (std::int64_t tick = 0; tick <= 3000; ++tick) {
    const bool drive = tick % 4 == 0, frame = tick % 10 == 0;
    if (!drive && !frame) continue;
    in.setpoint.reset();
    in.camera.reset();
    source.Fill(tick, drive, frame, tick * 1000, &in);
    const JoystickSample s = truth_joystick.Poll(tick, tick * 1000);
    for (; truth_tick < tick; ++truth_tick)
      truth.Step(CarControlsFromJoystick(s, vehicle::Speed(truth.last().sample.state), {}));
    ASSERT_EQ(source.last_tick().sample.state, truth.last().sample.state) << tick;
    ASSERT_EQ(in.setpoint.has_value(), drive);
    ASSERT_EQ(in.camera.has_value(), frame);
    if (drive) {
      EXPECT_EQ(*in.setpoint, truth.last().command.pose);  // the pose command (the core's IK: yaw, rail)
    }
    if (frame) {
      EXPECT_EQ(*in.camera, CarEyePose(scene, truth.last().sample.state));
    }
  }
  EXPECT_GT(vehicle::Speed(source.last_tick().sample.state), 1.0) << "the joystick should drive the car";
  EXPECT_EQ(source.input().seq, 3U);  // three readings: centred, forward, forward + left
}

TEST(CarDriveSource, TheShippedRnetLogDrivesTheCarAndItsLossBrakes) {
  const vehicle::CarScene scene =
      vehicle::LoadCarScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/car_launch.yaml");
  RnetLogJoystick joystick(ReadCandumpFile(std::filesystem::path(PWSIM_SOURCE_DIR) / "assets/rnet/joystick_synthetic.log"),
                           scene.clock.rate_hz, {-1, WatchdogTicks(100.0, scene.clock.rate_hz)}, "log");
  CarDriveSource source(scene, mca::LoadCarMcaConfig(scene), joystick);
  SessionInputs in;
  double v_at_loss = 0.0;
  for (std::int64_t tick = 0; tick <= 3300; tick += 2) {
    source.Fill(tick, tick % 4 == 0, tick % 10 == 0, tick * 1'000'000, &in);
    if (tick == 3090) v_at_loss = vehicle::Speed(source.last_tick().sample.state);
  }
  EXPECT_GT(v_at_loss, 1.0);
  // 210 ms of full braking after the watchdog: slower than at the loss
  EXPECT_LT(vehicle::Speed(source.last_tick().sample.state), v_at_loss - 0.5);
  EXPECT_EQ(source.invalid_polls(), 105U);  // ticks 3090..3298, every second tick
}

}  // namespace
}  // namespace pwsim::hw
