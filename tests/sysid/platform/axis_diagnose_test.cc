// Hidden-effect tests of the axis diagnosis: recordings from the independent truth
// (truth_axis.*) with one effect each; the diagnosis must name it (or call the no-effect set
// adequate) on held-out recordings simulated with another seed. Backlash is not asserted: a
// dead band with a compliant contact is named transmission_compliance (docs/platform.md).
#include <gtest/gtest.h>

#include "sysid/platform/axis_diagnose.h"
#include "tests/sysid/platform/emps_data.h"
#include "tests/sysid/platform/hidden_effects.h"

namespace pwsim::sysid::platform {
namespace {

AxisDiagnosis DiagnoseTruth(const test::TruthAxisParams& params) {
  test::TruthAxisParams train = params, held = params;
  train.duration = 20.0;
  held.duration = 12.0;
  held.seed = params.seed + 100;
  return DiagnoseAxis({test::SimulateTruthAxis(train)}, {test::SimulateTruthAxis(held)});
}

class HiddenEffect : public ::testing::TestWithParam<std::string> {};

TEST_P(HiddenEffect, IsNamedFromHeldOutData) {
  for (const test::HiddenCase& c : test::HiddenAxisCases(1)) {
    if (c.effect != GetParam()) continue;
    const AxisDiagnosis d = DiagnoseTruth(c.params);
    if (c.effect == "none") {
      EXPECT_EQ(d.verdict, "adequate") << d.heldout_base_pct << " vs floor " << d.noise_floor_pct;
      EXPECT_EQ(d.cause, "none");
    } else {
      EXPECT_EQ(d.cause, c.effect) << "verdict " << d.verdict;
      EXPECT_TRUE(d.verdict == "explained" || d.verdict == "partly_explained") << d.verdict;
      EXPECT_LT(d.heldout_extended_pct, d.heldout_base_pct);
    }
    return;
  }
  FAIL() << "no case " << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Axis, HiddenEffect,
                         ::testing::Values("none", "asymmetric_friction", "stribeck_friction",
                                           "position_dependent_friction", "cogging",
                                           "transmission_compliance", "command_delay"));

TEST(AxisDiagnose, ClosedLoopSimulationTracksTheTruth) {
  test::TruthAxisParams p;
  p.delay_samples = 1;
  p.duration = 12.0;
  const AxisDiagnosis d = DiagnoseTruth(p);
  ASSERT_EQ(d.closed_loop.size(), 1u);
  ASSERT_TRUE(d.closed_loop[0].available);
  EXPECT_LT(d.closed_loop[0].base.position_pct, 0.1);
  EXPECT_LT(d.closed_loop[0].base.velocity_pct, 5.0);
}

TEST(AxisDiagnose, EmpsFindsDirectionDependentFrictionFirst) {
  PWSIM_REQUIRE_EMPS();
  const AxisRecording r = ReadAxisRecording(test::EmpsDir() / "DATA_EMPS.mat");
  const AxisDiagnosis d = DiagnoseAxis({r}, {});
  EXPECT_EQ(d.cause, "asymmetric_friction");
  EXPECT_NE(d.verdict, "adequate");
  EXPECT_LT(d.heldout_extended_pct, d.heldout_base_pct);
  ASSERT_FALSE(d.closed_loop.empty());
  EXPECT_TRUE(d.closed_loop[0].available);
}

}  // namespace
}  // namespace pwsim::sysid::platform
