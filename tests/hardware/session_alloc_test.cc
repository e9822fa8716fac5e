// SessionCore::Step allocates nothing: global operator new is replaced by a counting one (this
// file is its own test executable so the replacement affects nothing else), and only the
// allocations made while Step runs are counted (the harness around it may allocate freely).

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <optional>
#include <sstream>

#include "tests/counting_allocator.h"
#include "tests/hardware/session_world.h"
#include "mca/config.h"

using pwsim_test::g_allocations;
using pwsim_test::g_counting;

namespace pwsim::hw {

/// In live_drive_alloc.cc: counts (through the two counters) the allocations inside
/// CarDriveSource::Fill over a drive; `speed` gets the final speed of the bus-driven car.
long LiveDriveFillAllocations(std::atomic<bool>& counting, std::atomic<long>& allocations, double* speed);
/// The same for ChairDriveSource::Fill through circuit_course with `algorithm` (--mca) over the
/// scene's; `distance` the chair's path length.
long ChairDriveFillAllocations(std::atomic<bool>& counting, std::atomic<long>& allocations, double* distance,
                               std::optional<mca::McaAlgorithm> algorithm);

namespace {

using session_testing::World;

/// Counts the allocations inside SessionCore::Step over a whole session of `w`.
long StepAllocations(World& w, const std::function<void(World&)>& inject = nullptr,
                     std::int64_t inject_at = -1) {
  g_counting = false;  // only the allocations inside Step count
  g_allocations = 0;
  w.around_step = [](bool on) { g_counting.store(on, std::memory_order_relaxed); };
  if (inject) {
    w.RunUntil(inject_at, nullptr);
    inject(w);
  }
  w.Finish();
  w.around_step = nullptr;
  return g_allocations.load();
}

TEST(SessionAlloc, CountingAllocatorSeesAnAllocation) {
  // The counter works: a vector growing while counting is on is seen.
  g_allocations = 0;
  g_counting = true;
  std::vector<int> v;
  v.push_back(1);
  g_counting = false;
  EXPECT_GE(g_allocations.load(), 1);
}

TEST(SessionAlloc, AWholeSessionStepsWithoutAllocating) {
  World w(3000);
  const long n = StepAllocations(w);
  ASSERT_TRUE(w.core->done());
  const SessionReport r = w.core->Report();
  EXPECT_EQ(r.final_state, "parked");
  EXPECT_EQ(r.stop_reason, "stop requested");
  EXPECT_GT(r.hmd_rx.accepted, 100U);  // head poses (P lines), pongs and pings all went through
  EXPECT_GT(r.skew_ms.n, 50U);
  EXPECT_EQ(n, 0) << "allocations inside SessionCore::Step";
  // And the log it wrote replays (the formatting into fixed buffers is the same text).
  std::istringstream in(w.LogText());
  const ReplayResult rr = ReplaySessionLog(in);
  EXPECT_TRUE(rr.ok) << rr.message;
}

// The PW platform's five drives: inverse kinematics of every pose command, forward kinematics
// of every measurement, five RPDOs a cycle: still nothing allocated in the step.
TEST(SessionAlloc, AWholeSessionOnTheFiveDrivesOfThePwPlatformStepsWithoutAllocating) {
  World w(3000, mca::ReadPlatformFile(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/platforms/pw4dof.yaml"));
  const long n = StepAllocations(w);
  ASSERT_TRUE(w.core->done());
  const SessionReport r = w.core->Report();
  EXPECT_EQ(r.final_state, "parked");
  EXPECT_GT(r.peak_abs_measured_pose[mca::Index(mca::Dof::kPitch)], 0.01);
  EXPECT_EQ(n, 0) << "allocations inside SessionCore::Step";
}

TEST(SessionAlloc, FaultsAndStopsStepWithoutAllocating) {
  // Each stop path writes its own log lines (supervisor reason, finishing, master phases).
  const std::vector<std::pair<const char*, std::function<void(World&)>>> cases = {
      {"headset vanishes", [](World& w) { w.hmd_alive = false; }},
      {"drives go silent", [](World& w) { w.drives.SetSilent(true); }},
      {"bus-off", [](World& w) { w.hub.SetBusOff(true); }},
  };
  for (const auto& [name, inject] : cases) {
    SCOPED_TRACE(name);
    World w(20000);
    const long n = StepAllocations(w, inject, 1200);
    ASSERT_TRUE(w.core->done());
    EXPECT_FALSE(w.core->Report().stop_reason.empty());
    EXPECT_EQ(n, 0) << "allocations inside SessionCore::Step";
  }
}

// The live drive's part of a step: poll the joystick (the shipped R-Net log, and R-Net frames
// over the in-process bus) and step the car and its MCA up to the tick (live_drive_alloc.cc:
// its own file, so that GCC does not see the replaced operator delete inlined beside
// std::allocator and warn).
TEST(SessionAlloc, TheLiveDriveSourceFillsWithoutAllocating) {
  double speed = 0.0;
  const long n = LiveDriveFillAllocations(g_counting, g_allocations, &speed);
  EXPECT_GT(speed, 1.0) << "the bus joystick should drive the car";
  EXPECT_EQ(n, 0) << "allocations inside CarDriveSource::Fill";
}

TEST(SessionAlloc, TheChairDriveSourceFillsWithoutAllocating) {
  double distance = 0.0;
  const long n = ChairDriveFillAllocations(g_counting, g_allocations, &distance, std::nullopt);
  EXPECT_GT(distance, 0.5) << "the R-Net log should drive the chair";
  EXPECT_EQ(n, 0) << "allocations inside ChairDriveSource::Fill";
}

// The same with both MCAs the model-predictive cueing (--mca mpc): a QP every 10 ms, no
// allocation in the tick; the chair drives the same path whatever cues it.
TEST(SessionAlloc, TheChairDriveSourceWithTheMpcFillsWithoutAllocating) {
  double washout_distance = 0.0, mpc_distance = 0.0;
  ChairDriveFillAllocations(g_counting, g_allocations, &washout_distance, mca::McaAlgorithm::kWashout);
  const long n = ChairDriveFillAllocations(g_counting, g_allocations, &mpc_distance, mca::McaAlgorithm::kMpc);
  EXPECT_GT(mpc_distance, 0.5) << "the R-Net log should drive the chair";
  EXPECT_EQ(mpc_distance, washout_distance);
  EXPECT_EQ(n, 0) << "allocations inside ChairDriveSource::Fill with the MPC";
}

}  // namespace
}  // namespace pwsim::hw
