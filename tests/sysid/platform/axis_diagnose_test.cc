// Hidden-effect tests of the axis diagnosis: recordings from the independent truth
// (truth_axis.*) with one effect each; the diagnosis must name it (or call the no-effect set
// adequate) on held-out recordings simulated with another seed. Backlash is not asserted: a
// dead band with a compliant contact is named transmission_compliance (docs/platform.md).
// Then the split's promise: the report rows take part in no choice and no fit, and a cause
// chosen on the selection rows that the report rows do not confirm never makes the verdict.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

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
      EXPECT_EQ(d.verdict, diagnose::Verdict::kAdequate) << d.heldout_base_pct << " vs floor " << d.noise_floor_pct;
      EXPECT_EQ(d.cause, "none");
    } else {
      EXPECT_EQ(d.cause, c.effect) << "verdict " << diagnose::VerdictName(d.verdict);
      EXPECT_TRUE(d.verdict == diagnose::Verdict::kExplained ||
                  d.verdict == diagnose::Verdict::kPartlyExplained)
          << diagnose::VerdictName(d.verdict);
      EXPECT_LT(d.heldout_extended_pct, d.heldout_base_pct);
      ASSERT_FALSE(d.causes.empty());
      EXPECT_TRUE(d.causes.front().confirmed) << d.causes.front().heldout_gain_pct;
      EXPECT_GT(d.causes.front().heldout_gain_lower_pct, 0.0);
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
  EXPECT_NE(d.verdict, diagnose::Verdict::kAdequate);
  EXPECT_LT(d.heldout_extended_pct, d.heldout_base_pct);
  ASSERT_FALSE(d.closed_loop.empty());
  EXPECT_TRUE(d.closed_loop[0].available);
}

void ExpectSameValues(const std::vector<NamedValue>& a, const std::vector<NamedValue>& b,
                      const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name) << what;
    EXPECT_EQ(a[i].value, b[i].value) << what << " " << a[i].name;  // to the bit
  }
}

// Every choice and every fitted value of two diagnoses, compared to the bit.
void ExpectSameChoices(const AxisDiagnosis& a, const AxisDiagnosis& b) {
  ASSERT_EQ(a.causes.size(), b.causes.size());
  for (std::size_t i = 0; i < a.causes.size(); ++i) {
    EXPECT_EQ(a.causes[i].effect, b.causes[i].effect);
    EXPECT_EQ(a.causes[i].selection_gain_pct, b.causes[i].selection_gain_pct);
  }
  ASSERT_EQ(a.ranking.size(), b.ranking.size());
  for (std::size_t i = 0; i < a.ranking.size(); ++i) {
    const EffectResult &x = a.ranking[i], &y = b.ranking[i];
    EXPECT_EQ(x.effect, y.effect);
    EXPECT_EQ(x.delta_bic, y.delta_bic);
    EXPECT_EQ(x.train_relative_error_pct, y.train_relative_error_pct);
    EXPECT_EQ(x.selection_relative_error_pct, y.selection_relative_error_pct);
    EXPECT_EQ(x.selection_gain_pct, y.selection_gain_pct);
    EXPECT_EQ(x.earns, y.earns);
    EXPECT_EQ(x.evidence, y.evidence);
    ExpectSameValues(x.parameters, y.parameters, AxisEffectId(x.effect));
  }
  ExpectSameValues(a.base_parameters, b.base_parameters, "base");
  ExpectSameValues(a.extended_parameters, b.extended_parameters, "extended");
  EXPECT_EQ(a.noise_sigma, b.noise_sigma);
  EXPECT_EQ(a.selection_base_pct, b.selection_base_pct);
  EXPECT_EQ(a.selection_extended_pct, b.selection_extended_pct);
  EXPECT_EQ(a.selection_floor_pct, b.selection_floor_pct);
  EXPECT_EQ(a.base_train_relative_error_pct, b.base_train_relative_error_pct);
}

// Overwrites a recording's samples [begin, end) with other data: another effort (a ripple and
// a step added) and a position disturbed by a slow wave.
void Disturb(AxisRecording* r, std::size_t begin, std::size_t end) {
  JointRecording& j = r->joints[0];
  for (std::size_t i = begin; i < end; ++i) {
    const double t = r->t[i];
    j.command[i] = 1.3 * j.command[i] + 0.2 * std::sin(40.0 * t) + 0.1;
    j.effort[i] = j.command_to_effort * j.command[i];
    j.position[i] += 2e-4 * std::sin(3.0 * t);
  }
}

test::TruthAxisParams TwoEffects() {
  test::TruthAxisParams p;
  p.delay_samples = 0;
  p.fv_pos = 160;  // asymmetric friction and cogging together: two rounds of the selection
  p.fv_neg = 240;
  p.cogging_amplitude = 4.0;
  p.cogging_period = 0.02;
  p.duration = 32.0;
  return p;
}

TEST(AxisDiagnose, ReportBlocksTakePartInNoChoice) {
  const AxisRecording r = test::SimulateTruthAxis(TwoEffects());
  const AxisDiagnosis d = DiagnoseAxis({r}, {});
  ASSERT_GE(d.causes.size(), 2u);  // the test covers more than one round
  // Both hidden effects found and confirmed on the report blocks of the one recording.
  for (AxisEffect hidden : {AxisEffect::kAsymmetricFriction, AxisEffect::kCogging}) {
    const auto found = std::find_if(d.causes.begin(), d.causes.end(),
                                    [&](const AxisCause& c) { return c.effect == hidden; });
    ASSERT_NE(found, d.causes.end()) << AxisEffectId(hidden);
    EXPECT_TRUE(found->confirmed) << AxisEffectId(hidden) << " " << found->heldout_gain_pct;
  }
  EXPECT_EQ(d.verdict, diagnose::Verdict::kExplained) << diagnose::VerdictName(d.verdict);
  AxisRecording changed = r;
  std::size_t report_samples = 0;
  for (const AxisBlock& b : d.blocks) {
    if (b.role != AxisRole::kReport) continue;
    Disturb(&changed, b.begin, b.end);
    report_samples += b.end - b.begin;
  }
  ASSERT_GT(report_samples, r.size() / 5);
  const AxisDiagnosis e = DiagnoseAxis({changed}, {});
  ExpectSameChoices(d, e);
  // The report rows did change what is reported.
  EXPECT_NE(d.heldout_base_pct, e.heldout_base_pct);
  EXPECT_NE(d.causes.front().heldout_gain_pct, e.causes.front().heldout_gain_pct);
}

TEST(AxisDiagnose, ValidationRecordingTakesPartInNoChoice) {
  test::TruthAxisParams p = TwoEffects(), q = TwoEffects();
  p.duration = 20.0;
  q.duration = 12.0;
  q.seed = p.seed + 100;
  const AxisRecording train = test::SimulateTruthAxis(p);
  const AxisRecording held = test::SimulateTruthAxis(q);
  const AxisDiagnosis d = DiagnoseAxis({train}, {held});
  AxisRecording changed = held;
  Disturb(&changed, 0, changed.size());
  const AxisDiagnosis e = DiagnoseAxis({train}, {changed});
  ExpectSameChoices(d, e);
  EXPECT_NE(d.heldout_base_pct, e.heldout_base_pct);
  EXPECT_GE(d.report_blocks, 10);  // 12 s in blocks of 1 s for the uncertainty
}

// Cogging in the training recording, none in the validation recording (which has Stribeck
// friction instead): cogging earns on the selection rows, the report rows do not confirm it, so
// it is listed unconfirmed and the verdict is unexplained with cause none.
TEST(AxisDiagnose, UnconfirmedCauseNeverMakesTheVerdict) {
  test::TruthAxisParams p, q;
  p.delay_samples = q.delay_samples = 0;
  p.cogging_amplitude = 4.0;
  p.cogging_period = 0.02;
  p.duration = 20.0;
  q.stribeck_extra = 10.0;
  q.stribeck_speed = 0.03;
  q.duration = 12.0;
  q.seed = p.seed + 100;
  const AxisDiagnosis d =
      DiagnoseAxis({test::SimulateTruthAxis(p)}, {test::SimulateTruthAxis(q)});
  ASSERT_FALSE(d.causes.empty());
  EXPECT_EQ(d.causes.front().effect, AxisEffect::kCogging);
  EXPECT_FALSE(d.causes.front().confirmed);
  EXPECT_LE(d.causes.front().heldout_gain_lower_pct, 0.0);
  EXPECT_EQ(d.verdict, diagnose::Verdict::kUnexplained);
  EXPECT_EQ(d.cause, "none");
  EXPECT_NE(d.unexplained_evidence.find("not confirmed"), std::string::npos) << d.unexplained_evidence;
}

TEST(AxisDiagnose, TooShortARecordingIsNamed) {
  test::TruthAxisParams p;
  p.duration = 0.5;
  const AxisRecording r = test::SimulateTruthAxis(p);
  try {
    DiagnoseAxis({r}, {});
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("too few for the diagnosis' split"), std::string::npos)
        << e.what();
  }
  p.duration = 10.0;  // long enough, but blocks of 5 s give two blocks for three roles
  AxisDiagnoseOptions o;
  o.block_s = 5.0;
  try {
    DiagnoseAxis({test::SimulateTruthAxis(p)}, {}, o);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("of at most 3.33 s"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pwsim::sysid::platform
