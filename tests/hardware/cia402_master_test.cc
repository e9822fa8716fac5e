// The CSP master against the simulated drives on an in-process bus, on a fake clock:
// thousands of SYNC cycles in milliseconds, no sleeps.
#include "hardware/cia402_master.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hardware/can_bus.h"
#include "hardware/simulated_drives.h"

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

  void Step(const std::array<double, 2>& setpoint) {
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
  int RunUntilRunning(int max_cycles) {
    for (int i = 0; i < max_cycles; ++i) {
      if (master.running()) return i;
      Step({0.0, 0.0});
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
    const std::array<double, 2> sp{0.05 * std::sin(M_PI * t), 0.2 * std::sin(M_PI * t)};
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
