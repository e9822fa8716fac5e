// MpcCueing::Step with the active-set solver allocates nothing: global operator new is replaced
// by a counting one (its own test executable). ALGLIB's minqp, the alternative, allocates while
// it solves (one reason it is not the default, docs/mca.md): counted too.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include "mca/mpc.h"
#include "tests/counting_allocator.h"

using pwsim_test::g_allocations;

// ALGLIB allocates through malloc, not operator new: the executable's malloc interposes the C
// library's for the whole process (shared libraries included) and counts the calls.
extern "C" void* __libc_malloc(std::size_t size);
namespace {
std::atomic<long> g_mallocs{0};
}  // namespace
extern "C" void* malloc(std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}

namespace pwsim::mca {
namespace {

// Tests that 20 s of healthy, extreme and non-finite input through the MPC (chair and car
// platforms) allocate nothing after construction.
TEST(MpcAllocTest, StepDoesNotAllocate) {
  for (const PlatformSpec& platform : {MakePw4DofPlatform(), MakeCar2DofPlatform()}) {
    MpcCueing dut(MpcParams{}, DefaultWashoutParams(), VestibularParams{}, platform, 1e-3);
    const long before = g_allocations.load();
    double sink = 0.0;
    for (int k = 0; k < 20000; ++k) {
      HeadMotion m;
      m.fs[0] = 2.0 * std::sin(k * 1e-3);
      m.fs[2] += (k % 5000 == 0) ? 1e12 : 0.5 * std::cos(k * 3e-3);
      m.w[1] = (k > 10000 && k < 10500) ? std::numeric_limits<double>::quiet_NaN() : 0.1;
      m.w[2] = 0.3 * std::sin(k * 2e-3);
      sink += dut.Step(m).pose[Index(platform.Has(Dof::kPitch) ? Dof::kPitch : Dof::kSurge)];
    }
    EXPECT_EQ(g_allocations.load() - before, 0);
    EXPECT_TRUE(std::isfinite(sink));
  }
}

// Tests that ALGLIB's minqp (DENSE-IPM, the fastest of its solvers here) allocates on every
// solve: the reason, beside its time, that the real-time tick uses the active set.
TEST(MpcAllocTest, AlglibSolvesAllocate) {
  MpcParams params;
  params.solver = QpAlgorithm::kDenseIpm;
  MpcCueing dut(params, DefaultWashoutParams(), VestibularParams{}, MakePw4DofPlatform(), 1e-3);
  const long before = g_mallocs.load();
  for (int k = 0; k < 1000; ++k) {  // 100 solves
    HeadMotion m;
    m.fs[0] = 2.0 * std::sin(k * 1e-3);
    dut.Step(m);
  }
  EXPECT_EQ(dut.stats().solves, 100);
  const long mallocs = g_mallocs.load() - before;
  RecordProperty("mallocs_per_solve", std::to_string(mallocs / dut.stats().solves));
  EXPECT_GE(mallocs, dut.stats().solves);
}

}  // namespace
}  // namespace pwsim::mca
