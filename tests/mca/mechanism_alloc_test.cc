// The mechanism's per-tick calls allocate nothing: global operator new is replaced by a counting
// one (this file is its own test executable so the replacement affects nothing else).

#include <gtest/gtest.h>

#include <cmath>

#include "mca/mechanism.h"
#include "mca/platform.h"
#include "tests/counting_allocator.h"

using pwsim_test::g_allocations;

namespace pwsim::mca {
namespace {

// Tests that Inverse, Forward, Jacobian, ActuatorForces and PayloadWrench never allocate, on
// the PW platform (stages and redundant legs) and the Stewart platform.
TEST(MechanismAllocTest, PerTickCallsDoNotAllocate) {
  const std::filesystem::path dir = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/platforms";
  for (const PlatformSpec& p : {ReadPlatformFile(dir / "pw4dof.yaml"), ReadPlatformFile(dir / "stewart6dof.yaml")}) {
    const Mechanism& m = p.mechanism;
    const long before = g_allocations.load();
    double sink = 0.0;
    DofArray last{};
    for (int k = 0; k < 2000; ++k) {
      const double t = 1e-3 * k;
      DofArray x{};
      for (Dof dof : kAllDofs) {
        if (m.Moves(dof)) x[static_cast<std::size_t>(Index(dof))] = 0.02 * std::sin((1.0 + Index(dof)) * t);
      }
      ActuatorVector q, f;
      ActuatorJacobian j;
      DofArray pose{};
      if (m.Inverse(x, &q)) {
        const KinematicsStatus s = m.Forward(q, last, &pose);
        sink += s.residual + pose[2];
        last = pose;
      }
      m.Jacobian(x, &j);
      if (m.ActuatorForces(x, m.PayloadWrench(x), &f)) sink += f.sum();
      sink += j.sum();
    }
    EXPECT_EQ(g_allocations.load() - before, 0) << p.name;
    EXPECT_TRUE(std::isfinite(sink));
  }
}

}  // namespace
}  // namespace pwsim::mca
