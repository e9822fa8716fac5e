// The per-step path allocates nothing: global operator new is replaced by a counting one
// (this file is its own test executable so the replacement affects nothing else).

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>

#include "mca/platform.h"
#include "mca/vestibular.h"
#include "mca/washout.h"
#include "tests/counting_allocator.h"

using pwsim_test::g_allocations;

namespace pwsim::mca {
namespace {

// Tests that ClassicalWashout::Step, the limiter and the vestibular model never allocate,
// on healthy, extreme and non-finite input alike.
TEST(WashoutAllocTest, StepDoesNotAllocate) {
  for (const PlatformSpec& platform : {MakePw4DofPlatform(), MakeCar2DofPlatform()}) {
    ClassicalWashout dut(DefaultWashoutParams(), platform, 1e-3);
    VestibularModel vestibular(VestibularParams{}, 1e-3);
    const long before = g_allocations.load();
    double sink = 0.0;
    for (int k = 0; k < 20000; ++k) {
      HeadMotion m;
      m.fs[0] = 2.0 * std::sin(k * 1e-3);
      m.fs[2] += (k % 5000 == 0) ? 1e12 : 0.5 * std::cos(k * 3e-3);
      m.w[1] = (k > 10000 && k < 10500) ? std::numeric_limits<double>::quiet_NaN() : 0.1;
      const McaCommand& c = dut.Step(m);
      sink += c.pose[Index(Dof::kPitch)] + vestibular.Step(m).fs[0];
    }
    EXPECT_EQ(g_allocations.load() - before, 0);
    EXPECT_TRUE(std::isfinite(sink));
  }
}

}  // namespace
}  // namespace pwsim::mca
