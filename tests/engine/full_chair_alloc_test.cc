// The full-DoF chair's real-time tick allocates nothing: FullChairSimulator::Advance and the
// circuit runner's tick (driver, contacts, gates), counted by a replaced global operator new.

#include <gtest/gtest.h>

#include <filesystem>

#include "engine/circuit.h"
#include "engine/scene.h"
#include "tests/counting_allocator.h"

namespace pwsim {
namespace {

// Tests that 20 s of the shipped course (closed-loop driver, floor features, walls, obstacles,
// gates) and 20 s of the recorded joystick run without one allocation per tick.
TEST(FullChairAllocTest, CircuitTicksAllocateNothing) {
  pwsim_test::g_allocations = 0;
  ::operator delete(::operator new(16));  // the counter counts (a call, not an elidable new-expression)
  ASSERT_EQ(pwsim_test::g_allocations.load(), 1);
  const std::filesystem::path scenes = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes";
  for (const char* name : {"circuit_course.yaml", "circuit_recorded.yaml", "circuit_room.yaml"}) {
    const Scene scene = LoadScene(scenes / name);
    CircuitRunner runner(scene.chair, *scene.circuit, scene.load_kg, scene.clock.dt(), scene.pitch_torque);
    runner.Start();
    pwsim_test::g_allocations = 0;
    for (std::int64_t tick = 1; tick <= 20000; ++tick) runner.Advance(scene.clock.TimeAt(tick - 1));
    EXPECT_EQ(pwsim_test::g_allocations.load(), 0) << name;
    EXPECT_GT(runner.sample().distance, 5.0) << name;  // it really drove
  }
}

}  // namespace
}  // namespace pwsim
