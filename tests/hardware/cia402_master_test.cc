// The CSP master against the simulated drives on an in-process bus, on a fake clock:
// thousands of SYNC cycles in milliseconds, no sleeps.
#include "hardware/cia402_master.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hardware/can_bus.h"
#include "hardware/simulated_drives.h"
#include "mca/platform.h"

namespace pwsim::hw {
namespace {

struct Rig {
  InProcessBus hub;
  std::unique_ptr<ICanBus> master_bus = hub.Connect("master");
  std::unique_ptr<ICanBus> drive_bus = hub.Connect("drives");
  Cia402Master master;
  SimulatedDrives drives;
  std::int64_t cycle = 0;
  std::vector<CanFrame> out;

  void Step(const AxisValues& setpoint) {
    const std::int64_t now_ns = cycle * 4'000'000;
    CanFrame f;
    while (master_bus->Receive(&f) == BusStatus::kOk) master.OnFrame(f);
    out.clear();
    master.Cycle(cycle, setpoint, &out);
    for (const CanFrame& x : out) master_bus->Send(x);
    out.clear();
    drives.Poll(now_ns, &out);
    while (drive_bus->Receive(&f) == BusStatus::kOk) drives.OnFrame(f, now_ns, &out);
    for (const CanFrame& x : out) drive_bus->Send(x);
    ++cycle;
  }
  int RunUntilRunning(int max_cycles, const AxisValues& hold = {}) {
    for (int i = 0; i < max_cycles; ++i) {
      if (master.running()) return i;
      Step(hold);
    }
    return -1;
  }
};

TEST(Cia402Master, StartsDrivesThroughNmtAndTheStateMachine) {
  Rig rig;
  const int cycles = rig.RunUntilRunning(200);
  ASSERT_GE(cycles, 0) << MasterPhaseName(rig.master.phase());
  EXPECT_LT(cycles, 60);
  EXPECT_EQ(rig.drives.nmt_state(), canopen::NmtState::kOperational);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(rig.drives.drive_state(i), canopen::DriveState::kOperationEnabled);
    EXPECT_EQ(rig.master.axis(i).drive, canopen::DriveState::kOperationEnabled);
  }
  EXPECT_TRUE(rig.master.heartbeats_ok());
}

TEST(Cia402Master, StreamsCspSetpointsThatTheDrivesFollow) {
  Rig rig;
  ASSERT_GE(rig.RunUntilRunning(200), 0);
  // A smooth 0.5 Hz motion: 0.2 m on the rail, 0.05 rad of yaw.
  double worst = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const double t = 0.004 * k;  // starts at rest where the drives are (0, 0)
    const AxisValues sp{0.05 * std::sin(M_PI * t), 0.2 * std::sin(M_PI * t)};
    rig.Step(sp);
    if (k > 50) {
      worst = std::max(worst, std::abs(rig.master.axis(1).position - 0.2 * std::sin(M_PI * (t - 0.004))));
    }
  }
  EXPECT_LT(worst, 0.01);  // the drives track within 1 cm (one cycle of transport delay)
  EXPECT_FALSE(rig.master.any_fault());
  EXPECT_TRUE(rig.master.tpdos_fresh());
  EXPECT_GT(std::abs(rig.master.axis(1).velocity), 0.0);
}

TEST(Cia402Master, ReportsHeartbeatLossEmcyAndRecoversAfterFaultReset) {
  Rig rig;
  ASSERT_GE(rig.RunUntilRunning(200), 0);
  rig.drives.SetSilent(true);
  int lost_after = -1;
  for (int k = 0; k < 200; ++k) {
    rig.Step({0.0, 0.0});
    if (!rig.master.heartbeats_ok()) {
      lost_after = k;
      break;
    }
  }
  EXPECT_GE(lost_after, 0);
  EXPECT_LE(lost_after, rig.master.config().heartbeat_timeout_cycles + 1);
  rig.drives.SetSilent(false);
  for (int k = 0; k < 30; ++k) rig.Step({0.0, 0.0});
  EXPECT_TRUE(rig.master.heartbeats_ok());

  std::vector<CanFrame> emcy;
  rig.drives.InjectFault(1, 0x2310, &emcy);
  for (const CanFrame& f : emcy) rig.drive_bus->Send(f);
  rig.Step({0.0, 0.0});
  EXPECT_TRUE(rig.master.any_fault());
  EXPECT_EQ(rig.master.axis(1).last_emcy_code, 0x2310);
  for (int k = 0; k < 5; ++k) rig.Step({0.0, 0.0});
  EXPECT_FALSE(rig.master.running());
  rig.master.RequestFaultReset();
  for (int k = 0; k < 30 && !rig.master.running(); ++k) rig.Step({0.0, 0.0});
  EXPECT_TRUE(rig.master.running());
  EXPECT_FALSE(rig.master.any_fault());
}

// A drive that restarts (a new process on the bus: its boot-up after the start-up) is started
// again: NMT start to it, the controlword walk, holding every drive where it is, and the master
// streams the setpoints again once all are operation enabled; SYNCs never stop.
TEST(Cia402Master, ReadmitsADriveThatRestartedThroughTheStartUp) {
  Rig rig;
  ASSERT_GE(rig.RunUntilRunning(200), 0);
  for (int k = 0; k < 100; ++k) rig.Step({0.0, 0.001 * k});  // rail out to 0.1 m
  // the drives' process dies and a new one starts on the bus: everything it knew is gone
  rig.drives.SetSilent(true);
  for (int k = 0; k < 10; ++k) rig.Step({0.0, 0.1});
  EXPECT_FALSE(rig.master.tpdos_fresh());
  rig.drives = SimulatedDrives();
  const std::uint8_t before = rig.master.sync_counter();
  int running_again = -1;
  for (int k = 0; k < 300 && running_again < 0; ++k) {
    rig.Step({0.0, 0.0});  // the new process starts at 0 (its caller ramps from the measured position)
    if (rig.master.running() && rig.master.axis(0).readmissions == 1 && rig.master.axis(1).readmissions == 1)
      running_again = k;
  }
  ASSERT_GE(running_again, 0) << MasterPhaseName(rig.master.phase());
  EXPECT_LT(running_again, 60);
  EXPECT_NE(rig.master.sync_counter(), before);  // SYNCs went on
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(rig.master.axis(i).restarts, 1U) << i;
    EXPECT_EQ(rig.master.axis(i).readmissions, 1U) << i;
    EXPECT_FALSE(rig.master.axis(i).readmitting) << i;
    EXPECT_EQ(rig.drives.drive_state(i), canopen::DriveState::kOperationEnabled) << i;
  }
  EXPECT_TRUE(rig.master.tpdos_fresh());
  EXPECT_GT(rig.drives.syncs(), 0U);
  // and it follows the setpoints again: a ramp to 0.05 m over 0.4 s
  for (int k = 0; k < 200; ++k) rig.Step({0.0, 0.05 * std::min(1.0, k / 100.0)});
  EXPECT_NEAR(rig.master.axis(1).position, 0.05, 2e-3);
  EXPECT_FALSE(rig.master.any_fault());
}

// A drive whose heartbeat comes back without a boot-up (it was cut off, not restarted) is in an
// unknown state: the master resets its communication, waits for the boot-up, and starts it.
TEST(Cia402Master, ResetsADriveWhoseHeartbeatReturnsWithoutABootUp) {
  Rig rig;
  ASSERT_GE(rig.RunUntilRunning(200), 0);
  rig.drives.SetSilent(true);
  for (int k = 0; k < rig.master.config().heartbeat_timeout_cycles + 5; ++k) rig.Step({0.0, 0.0});
  ASSERT_TRUE(rig.master.axis(0).heartbeat_lost);
  rig.drives.SetSilent(false);
  int running_again = -1;
  for (int k = 0; k < 400 && running_again < 0; ++k) {
    rig.Step({0.0, 0.0});
    if (rig.master.running() && rig.master.axis(0).readmissions == 1) running_again = k;
  }
  ASSERT_GE(running_again, 0) << MasterPhaseName(rig.master.phase());
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(rig.master.axis(i).returns, 1U) << i;
    EXPECT_EQ(rig.master.axis(i).restarts, 1U) << i;  // the boot-up that answered the reset
    EXPECT_GE(rig.drives.boot_count(i), 2U) << i;
  }
}

// Five drives of the PW platform (a yaw stage and four legs): nodes 1..5 all started (no boot-up
// taken for a restart), and each follows its own setpoint.
TEST(Cia402Master, StartsAndStreamsFiveDrivesOfThePwPlatform) {
  const mca::Mechanism pw = mca::MakePw4DofPlatform().mechanism;
  ASSERT_EQ(pw.actuator_count(), 5);
  Rig rig;
  rig.drives = SimulatedDrives(pw);
  MasterConfig config;
  config.axis_count = 5;
  rig.master = Cia402Master(config);
  const mca::ActuatorVector q0 = pw.Neutral();
  AxisValues sp{};
  for (int i = 0; i < 5; ++i) sp[static_cast<std::size_t>(i)] = q0(i);
  ASSERT_GE(rig.RunUntilRunning(200, sp), 0) << MasterPhaseName(rig.master.phase());
  // each leg 5 mm longer than neutral, the yaw stage 0.01 rad: small steps the servos follow
  AxisValues moved = sp;
  for (std::size_t i = 0; i < 5; ++i) moved[i] += i == 0 ? 0.01 : 0.005;
  for (int k = 0; k < 300; ++k) rig.Step(moved);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(rig.drives.drive_state(i), canopen::DriveState::kOperationEnabled) << i;
    EXPECT_NEAR(rig.master.axis(i).position, moved[static_cast<std::size_t>(i)], 1e-4) << i;
    EXPECT_EQ(rig.master.axis(i).restarts, 0U) << i;
  }
}

TEST(SimulatedDrives, QuickStopWhenTheMasterVanishes) {
  Rig rig;
  ASSERT_GE(rig.RunUntilRunning(200), 0);
  for (int k = 0; k < 100; ++k) rig.Step({0.0, 0.004 * k});  // rail moving at 1 m/s
  const std::int64_t t0 = rig.cycle * 4'000'000;
  std::vector<CanFrame> out;
  for (std::int64_t t = t0; t < t0 + 2'000'000'000; t += 4'000'000) rig.drives.Poll(t, &out);
  EXPECT_TRUE(rig.drives.master_lost());
  EXPECT_EQ(rig.drives.drive_state(1), canopen::DriveState::kQuickStopActive);
  EXPECT_LT(std::abs(rig.drives.platform().qd[1]), 0.01);
}

}  // namespace
}  // namespace pwsim::hw
