// MpcCueing::Step with the active-set solver allocates nothing: global operator new is replaced
// by a counting one (its own test executable). The ALGLIB solvers are not covered: minqp
// allocates while it solves (docs/mca.md).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mca/mpc.h"
#include "tests/counting_allocator.h"

using pwsim_test::g_allocations;

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

}  // namespace
}  // namespace pwsim::mca
