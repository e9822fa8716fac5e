// The simulated drives allocate nothing per drive cycle (RPDOs, SYNC, the physics, forward
// kinematics, the payload's leg forces, heartbeats, the quick stop on their own clock): global
// operator new is replaced by a counting one (its own executable), counted only around the
// drives' calls; the frames go to a vector reserved beforehand, as platform-sim's loop reuses.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <vector>

#include "tests/counting_allocator.h"
#include "hardware/canopen.h"
#include "hardware/simulated_drives.h"
#include "mca/platform.h"

using pwsim_test::g_allocations;
using pwsim_test::g_counting;

namespace pwsim::hw {
namespace {

/// Runs the drives of `mechanism` through a start-up, 2 s of motion and 1 s without a master;
/// returns the allocations counted inside OnFrame and Poll after the first cycle.
long CycleAllocations(const mca::Mechanism& mechanism) {
  g_counting = false;
  SimulatedDrives drives(mechanism);
  std::vector<CanFrame> out;
  out.reserve(256);
  std::int64_t now = 1'000'000'000;
  const int n = drives.axis_count();
  const mca::ActuatorVector neutral = mechanism.Neutral();
  g_allocations = 0;
  auto call = [&](auto&& f) {
    g_counting = true;
    f();
    g_counting = false;
    out.clear();
  };
  call([&] { drives.Poll(now, &out); });
  call([&] { drives.OnFrame(canopen::EncodeNmt(canopen::NmtCommand::kResetComm, 0), now, &out); });
  call([&] { drives.OnFrame(canopen::EncodeNmt(canopen::NmtCommand::kStart, 0), now, &out); });
  const std::uint16_t walk[4] = {canopen::controlword::kDisableVoltage, canopen::controlword::kShutdown,
                                 canopen::controlword::kSwitchOn, canopen::controlword::kEnableOperation};
  std::uint8_t counter = 0;
  for (int k = 0; k < 500; ++k) {
    const double s = 0.01 * std::sin(2.0 * k * 0.004);  // a small motion of every actuator
    for (int i = 0; i < n; ++i) {
      const canopen::CspCommand cmd{walk[std::min(k, 3)],
                                    static_cast<std::int32_t>(std::lround((neutral(i) + s) * 1e6))};
      const CanFrame f = canopen::EncodeCspCommand(drives.node(i), cmd);
      call([&] { drives.OnFrame(f, now, &out); });
    }
    counter = static_cast<std::uint8_t>(counter % 240 + 1);
    const CanFrame sync = canopen::EncodeSync(counter);
    call([&] { drives.OnFrame(sync, now, &out); });
    call([&] { drives.Poll(now, &out); });
    now += 4'000'000;
  }
  EXPECT_TRUE(drives.all_enabled());
  for (int k = 0; k < 250; ++k) {  // the master vanished: quick stop on the drives' own clock
    now += 4'000'000;
    call([&] { drives.Poll(now, &out); });
  }
  EXPECT_TRUE(drives.master_lost());
  EXPECT_EQ(drives.syncs(), 500u);
  return g_allocations.load();
}

TEST(SimulatedDrivesAlloc, CountingAllocatorSeesAnAllocation) {
  g_allocations = 0;
  g_counting = true;
  std::vector<int> v;
  v.push_back(1);
  g_counting = false;
  EXPECT_GE(g_allocations.load(), 1);
}

TEST(SimulatedDrivesAlloc, NoAllocationPerCycleOnAnyShippedPlatform) {
  g_counting = false;
  const std::filesystem::path dir = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/platforms";
  EXPECT_EQ(CycleAllocations(SimulatedDrives::CarMechanism()), 0);
  for (const char* file : {"car2dof.yaml", "pw4dof.yaml", "stewart6dof.yaml"}) {
    const mca::PlatformSpec spec = mca::ReadPlatformFile(dir / file);
    EXPECT_EQ(CycleAllocations(spec.mechanism), 0) << file;
  }
}

}  // namespace
}  // namespace pwsim::hw
