#include "sysid/diagnose/diagnose.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <random>
#include <string>

#include "synth/effect_truth_model.h"
#include "synth/synthetic_trials.h"
#include "synth/generate.h"
#include "sysid/diagnose/format_text.h"

namespace pwsim::diagnose {
namespace {

using effects::EffectId;
using effects::EffectName;

/// Options for a test that asserts `adequate` and the base model's and noise model's figures
/// alone: no candidate fitted. `adequate` is decided on the base model's residual alone
/// (DecideVerdict: base noise-like) and an adequate diagnosis clears its causes (diagnose.cc
/// ReportExtended), so the candidates' fits cannot change anything such a test asserts (they
/// came out the same to the bit with all eight candidates as with none on these tests' sets).
DiagnoseOptions BaseOnly() {
  DiagnoseOptions options;
  options.candidates.clear();
  return options;
}

effects::SyntheticSet MakeSet(std::optional<EffectId> effect, double strength, std::uint64_t seed,
                              int trials = 7) {
  effects::SyntheticConfig config;
  config.seed = seed;
  config.effect = effect;
  config.strength = strength;
  config.trials = trials;
  return effects::MakeSyntheticTrials(config);
}

TEST(ChooseHeldOutTest, LeavesTheMiddleSpeedOutThenALoad) {
  std::vector<effects::TrialRecord> trials(6);
  const double speeds[] = {0.6, 1.2, 1.2, 1.8, 2.4, 0.6};
  for (int i = 0; i < 6; ++i) {
    trials[i].speed = speeds[i];
    trials[i].load_kg = 50.0 * (i % 3);
  }
  std::string why;
  EXPECT_EQ(ChooseHeldOut(trials, &why), (std::vector<bool>{false, true, true, false, false, false}));
  EXPECT_EQ(why, "speed 1.20 m/s left out");
  for (auto& t : trials) t.speed = 1.0;  // one speed level: leave a load out
  EXPECT_EQ(ChooseHeldOut(trials, &why), (std::vector<bool>{false, true, false, false, true, false}));
  EXPECT_EQ(why, "load 50.00 kg left out");
}

TEST(SyntheticTrialsTest, SeededAndVaried) {
  const auto a = MakeSet(EffectId::kTyreCompliance, 1.0, 5);
  const auto b = MakeSet(EffectId::kTyreCompliance, 1.0, 5);
  const auto c = MakeSet(EffectId::kTyreCompliance, 1.0, 6);
  ASSERT_EQ(a.trials.size(), 7u);
  EXPECT_EQ(a.trials[3].z, b.trials[3].z);
  EXPECT_NE(a.trials.front().chair.mass, c.trials.front().chair.mass);
  std::vector<double> speeds;
  for (const auto& t : a.trials) speeds.push_back(t.speed);
  for (double v : {0.6, 1.2, 1.8, 2.4}) EXPECT_NE(std::find(speeds.begin(), speeds.end(), v), speeds.end());
}

TEST(DiagnoseTest, OneSetOfTrialsGivesOneDiagnosisWhateverTheirOrder) {
  // The same trials listed in another order (a shell glob, a hand-typed list) must give the
  // same diagnosis to the bit: the fits sum over trials in floating point, and a multi-start
  // can tip on the last bit, so Diagnose takes them in the order of their names.
  const effects::SyntheticSet set = MakeSet(EffectId::kTyreCompliance, 1.0, 21);
  std::vector<effects::TrialRecord> reversed(set.trials.rbegin(), set.trials.rend());
  ASSERT_NE(reversed.front().name, set.trials.front().name);
  const Diagnosis a = Diagnose(set.trials);
  const Diagnosis b = Diagnose(reversed);
  EXPECT_EQ(a.cause, b.cause);
  ASSERT_EQ(a.causes.size(), b.causes.size());
  for (std::size_t k = 0; k < a.causes.size(); ++k) {
    EXPECT_EQ(a.causes[k].effect, b.causes[k].effect);
    EXPECT_EQ(a.causes[k].heldout_gain_pct, b.causes[k].heldout_gain_pct);
  }
  ASSERT_EQ(a.ranking.size(), b.ranking.size());
  for (std::size_t k = 0; k < a.ranking.size(); ++k) {
    EXPECT_EQ(a.ranking[k].effect, b.ranking[k].effect);
    EXPECT_EQ(a.ranking[k].heldout_gain.pct, b.ranking[k].heldout_gain.pct);
    EXPECT_EQ(a.ranking[k].delta_bic, b.ranking[k].delta_bic);
  }
  EXPECT_EQ(a.heldout_trials, b.heldout_trials);
  EXPECT_EQ(a.extended_heldout.z, b.extended_heldout.z);
  EXPECT_EQ(a.extended_heldout.pitch, b.extended_heldout.pitch);
}

// The candidate fits run concurrently; each writes its own slot and the slots are reduced in
// order, so one thread and three give the same diagnosis to the bit.
TEST(DiagnoseTest, SameDiagnosisWhateverTheThreadCount) {
  const effects::SyntheticSet set = MakeSet(EffectId::kInertialPitch, 1.0, 24);
  DiagnoseOptions one, three;
  one.threads = 1;
  three.threads = 3;
  const Diagnosis a = Diagnose(set.trials, one);
  const Diagnosis b = Diagnose(set.trials, three);
  ASSERT_EQ(a.ranking.size(), b.ranking.size());
  for (std::size_t k = 0; k < a.ranking.size(); ++k) {
    EXPECT_EQ(a.ranking[k].effect, b.ranking[k].effect);
    EXPECT_EQ(a.ranking[k].delta_bic, b.ranking[k].delta_bic);
    EXPECT_EQ(a.ranking[k].parameters, b.ranking[k].parameters);
  }
  EXPECT_EQ(a.selected.effects, b.selected.effects);
  EXPECT_EQ(a.selected.effect_values, b.selected.effect_values);
  EXPECT_EQ(a.selected.bic, b.selected.bic);
  EXPECT_EQ(a.extended_heldout.pitch, b.extended_heldout.pitch);
}

// Every choice is made on the training and selection trials: the report trials are read once,
// at the end, to report. Changing the report trials' data (an offset, a slow wave and extra
// noise on both channels) must leave every choice and every fitted parameter unchanged to the
// bit, while the report's figures do change.
TEST(DiagnoseTest, ReportTrialsTakeNoPartInAnyChoice) {
  for (const auto& [effect, seed] : {std::pair{EffectId::kTyreCompliance, 21u},
                                     std::pair{EffectId::kCushionCompliance, 23u}}) {
    const effects::SyntheticSet set = MakeSet(effect, 1.0, seed);
    const Diagnosis a = Diagnose(set.trials);
    ASSERT_FALSE(a.heldout_trials.empty());
    std::vector<effects::TrialRecord> changed = set.trials;
    std::mt19937_64 rng(99);
    std::normal_distribution<double> noise(0.0, 1.0);
    for (auto& r : changed) {
      if (std::find(a.heldout_trials.begin(), a.heldout_trials.end(), r.name) == a.heldout_trials.end())
        continue;
      for (std::size_t k = 0; k < r.t.size(); ++k) {
        r.z[k] += 0.01 + 2e-3 * std::sin(3.0 * r.t[k]) + 5e-4 * noise(rng);
        r.pitch[k] += 0.02 + 4e-3 * std::sin(2.0 * r.t[k]) + 1e-3 * noise(rng);
      }
    }
    const Diagnosis b = Diagnose(changed);
    EXPECT_EQ(a.heldout_trials, b.heldout_trials);
    EXPECT_EQ(a.sigma_z, b.sigma_z);
    EXPECT_EQ(a.sigma_pitch, b.sigma_pitch);
    EXPECT_EQ(a.noise.z.acf, b.noise.z.acf);
    EXPECT_EQ(a.noise.pitch.acf, b.noise.pitch.acf);
    EXPECT_EQ(a.base.params.lm.k_z, b.base.params.lm.k_z);
    EXPECT_EQ(a.base.params.lm.c_theta, b.base.params.lm.c_theta);
    ASSERT_EQ(a.ranking.size(), b.ranking.size());
    for (std::size_t k = 0; k < a.ranking.size(); ++k) {
      EXPECT_EQ(a.ranking[k].effect, b.ranking[k].effect);
      EXPECT_EQ(a.ranking[k].earns, b.ranking[k].earns);
      EXPECT_EQ(a.ranking[k].delta_bic, b.ranking[k].delta_bic);
      EXPECT_EQ(a.ranking[k].selection_gain, b.ranking[k].selection_gain);
      EXPECT_EQ(a.ranking[k].parameters, b.ranking[k].parameters);
    }
    // The causes forward selection found and their joint fit.
    EXPECT_FALSE(a.selected.effects.empty());
    EXPECT_EQ(a.selected.effects, b.selected.effects);
    EXPECT_EQ(a.selected.effect_values, b.selected.effect_values);
    EXPECT_EQ(a.selected.params.lm.k_theta, b.selected.params.lm.k_theta);
    EXPECT_EQ(a.selected.bic, b.selected.bic);
    // ... while the report, read on the changed trials, does change.
    EXPECT_NE(a.base_heldout.z, b.base_heldout.z);
    EXPECT_NE(a.base_heldout.pitch, b.base_heldout.pitch);
  }
}

/// What forward selection found, for failure messages.
std::string CausesLine(const Diagnosis& d) {
  std::string s;
  for (const Cause& c : d.causes)
    s += std::string(EffectName(c.effect)) + (c.confirmed ? " confirmed" : " unconfirmed") + " gain " +
         std::to_string(c.heldout_gain_pct) + " % (lcb " + std::to_string(c.heldout_gain_lower_pct) + " %, " +
         std::to_string(c.report_trials_improved) + "/" + std::to_string(c.report_trials) + "); ";
  return s;
}

struct HiddenCase {
  std::optional<EffectId> effect;
  double strength;
  std::uint64_t seed;
};

void PrintTo(const HiddenCase& c, std::ostream* os) {
  *os << (c.effect ? EffectName(*c.effect) : "none") << " strength " << c.strength << " seed "
      << c.seed;
}

std::string CaseName(const testing::TestParamInfo<HiddenCase>& info) {
  const std::string id = info.param.effect ? EffectName(*info.param.effect) : "none";
  return id + "_s" + std::to_string(static_cast<int>(info.param.strength * 10)) + "_seed" +
         std::to_string(info.param.seed);
}

class HiddenEffectTest : public testing::TestWithParam<HiddenCase> {};

// Each effect at a moderate strength under seeded random conditions (chair, cushion, speeds,
// loads, noise): the diagnosis must name it and the extension must beat the base model on
// the held-out trials. Nothing but the trials reaches Diagnose. One effect is hidden, so forward
// selection stops after the first cause (`max_causes` 1: the extended model is that cause's).
// Without an effect the set must be `adequate`, which the base model decides alone (BaseOnly).
TEST_P(HiddenEffectTest, NamesTheCauseAndGainsOnHeldOutTrials) {
  const HiddenCase c = GetParam();
  const effects::SyntheticSet set = MakeSet(c.effect, c.strength, c.seed);
  if (!c.effect) {
    const Diagnosis d = Diagnose(set.trials, BaseOnly());
    EXPECT_FALSE(d.heldout_trials.empty());
    EXPECT_EQ(d.verdict, Verdict::kAdequate) << d.base_check.Evidence();
    EXPECT_EQ(d.cause, "none");
    EXPECT_EQ(d.extended_heldout.z, d.base_heldout.z);
    return;
  }
  DiagnoseOptions one_cause;
  one_cause.max_causes = 1;
  const Diagnosis d = Diagnose(set.trials, one_cause);
  ASSERT_EQ(d.ranking.size(), 8u);
  EXPECT_FALSE(d.heldout_trials.empty());
  EXPECT_EQ(d.cause, EffectName(*c.effect));
  EXPECT_NE(d.verdict, Verdict::kAdequate);
  ASSERT_FALSE(d.causes.empty());
  EXPECT_EQ(d.causes.front().effect, *c.effect);
  const RankEntry& top = d.ranking.front();
  EXPECT_EQ(top.effect, *c.effect);
  EXPECT_TRUE(top.earns);
  EXPECT_GT(top.heldout_gain.pct, 15.0);
  EXPECT_LT(top.delta_bic, -10.0);
  EXPECT_GE(d.extended_heldout.z + d.extended_heldout.pitch, d.base_heldout.z + d.base_heldout.pitch + 0.5);
  // The cause named is confirmed by the report trials, and its evidence line gives the gains
  // and the limits this run used.
  EXPECT_TRUE(d.causes.front().confirmed) << CausesLine(d);
  EXPECT_GT(d.causes.front().heldout_gain_lower_pct, 0.0);
  EXPECT_NE(top.evidence.find(Format("%.0f %% on the selection trials (earns at ≥ 10 %% and ΔBIC < -10)",
                                     100.0 * top.selection_gain)),
            std::string::npos)
      << top.evidence;
  for (const RankEntry& e : d.ranking) EXPECT_EQ(e.evidence.find('\n'), std::string::npos);
  // One gain: each interval holds its estimate, and the cause named is the most probable effect.
  for (const RankEntry& e : d.ranking) {
    EXPECT_LE(e.heldout_gain.lower_pct, e.heldout_gain.pct) << EffectName(e.effect);
    EXPECT_GE(e.heldout_gain.upper_pct, e.heldout_gain.pct) << EffectName(e.effect);
  }
  const Cause& named = d.causes.front();
  EXPECT_LE(named.heldout_gain_lower_pct, named.heldout_gain_pct);
  EXPECT_GE(named.heldout_gain_upper_pct, named.heldout_gain_pct);
  ASSERT_EQ(d.probabilities.size(), d.options.candidates.size());
  const auto most = std::max_element(d.probabilities.begin(), d.probabilities.end(),
                                     [](const auto& a, const auto& b) { return a.probability < b.probability; });
  EXPECT_EQ(most->effect, *c.effect);
}

// Item 3 of issue 41: a cause that removes nothing is neither confirmed nor found. A set without
// any effect, whose base model the residual tests are made to reject (rho_max < 0: the magnitude
// test fails whatever the residual) and whose one candidate earns whatever it gains (no gain or
// ΔBIC asked for): forward selection adds it, and it has nothing to remove. Its held-out gain's
// interval holds its estimate and does not lie above 0, so the report trials do not confirm it,
// `cause` stays none and the verdict `unexplained`.
TEST(DiagnoseTest, ACauseThatRemovesNothingIsNeitherConfirmedNorFound) {
  const effects::SyntheticSet set = MakeSet(std::nullopt, 0.0, 104);
  DiagnoseOptions forced;
  forced.candidates = {EffectId::kMarkerOffset};
  forced.max_causes = 1;
  forced.min_selection_gain = -1e9;
  forced.bic_threshold = 1e300;
  forced.verdict.rho_max = -1.0;
  const Diagnosis d = Diagnose(set.trials, forced);
  ASSERT_EQ(d.causes.size(), 1u) << VerdictName(d.verdict);  // added by forward selection
  const Cause& c = d.causes.front();
  EXPECT_EQ(c.effect, EffectId::kMarkerOffset);
  EXPECT_LE(c.heldout_gain_lower_pct, c.heldout_gain_pct);
  EXPECT_GE(c.heldout_gain_upper_pct, c.heldout_gain_pct);
  EXPECT_LE(c.heldout_gain_lower_pct, 0.0) << CausesLine(d);
  EXPECT_FALSE(c.confirmed) << CausesLine(d);
  EXPECT_EQ(d.cause, "none");
  EXPECT_EQ(d.verdict, Verdict::kUnexplained);
  // Its probability: no more than the prior's odds allow a model that gains nothing.
  ASSERT_EQ(d.probabilities.size(), 1u);
  EXPECT_LT(d.probabilities.front().probability, 0.5);
}

// EffectProbabilities against the posterior it states, computed here by hand for three models:
// base (MS 4, 4), {a} (MS 1, 4), {a, b} (MS 1, 2) with π = 0.2, ν = 2:
// w ∝ (π/(1−π))^{|m|} Π MS^{−ν/2}: base 1/16, {a} 0.25/4, {a,b} 0.0625/2 (and {a} visited twice,
// counted once).
TEST(EffectProbabilityTest, PosteriorInclusionOverTheVisitedModels) {
  const EffectId a = EffectId::kTyreCompliance, b = EffectId::kInertialPitch, c = EffectId::kWheelRadius;
  std::vector<VisitedModel> models{{{}, {4.0, 4.0}}, {{a}, {1.0, 4.0}}, {{a}, {2.0, 4.0}}, {{b, a}, {1.0, 2.0}},
                                   {{c}, {}}};  // c: not simulated, left out
  ProbabilityOptions o;
  o.prior = 0.2;
  o.samples_per_unit = 2.0;
  const std::vector<EffectProbability> p = EffectProbabilities(models, {a, b, c}, o);
  const double w0 = 1.0 / 16.0, wa = 0.25 / 4.0, wab = 0.0625 / 2.0, total = w0 + wa + wab;
  ASSERT_EQ(p.size(), 3u);
  EXPECT_NEAR(p[0].probability, (wa + wab) / total, 1e-12);
  EXPECT_NEAR(p[1].probability, wab / total, 1e-12);
  EXPECT_EQ(p[2].probability, 0.0);
  // Nothing weighable: the prior.
  EXPECT_EQ(EffectProbabilities({{{c}, {}}}, {a}, o).front().probability, 0.2);
}

std::vector<HiddenCase> Cases() {
  std::vector<HiddenCase> cases;
  std::uint64_t seed = 11;
  for (EffectId id : effects::AllEffects()) {
    cases.push_back({id, 0.7, seed++});
    cases.push_back({id, 1.4, seed++});
  }
  for (std::uint64_t s : {101u, 102u, 103u}) cases.push_back({std::nullopt, 0.0, s});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(EveryEffect, HiddenEffectTest, testing::ValuesIn(Cases()), CaseName);

// A correct model on data whose mocap noise was low-pass filtered (as exports often are:
// 2nd-order Butterworth at 8 Hz, 100 Hz frames) is `adequate`: the verdict is judged against the
// noise model estimated from the rest windows, not against white noise at the level the high
// frequencies show. With drift-free, outlier-free noise of the same spectrum on every channel.
TEST(NoiseModelDiagnoseTest, LowPassFilteredMocapNoiseIsAdequate) {
  for (std::uint64_t seed : {201u, 202u}) {
    effects::SyntheticConfig config;
    config.seed = seed;
    config.trials = 7;
    config.noise_process.low_pass_hz = 8.0;
    const Diagnosis d = Diagnose(effects::MakeSyntheticTrials(config).trials, BaseOnly());
    EXPECT_TRUE(d.noise.z.from_rest);
    EXPECT_GT(d.noise.z.acf.size(), 2u);  // coloured
    EXPECT_EQ(d.verdict, Verdict::kAdequate) << seed << ": " << d.base_check.Evidence();
    EXPECT_EQ(d.cause, "none");
  }
}

// Outliers in the export (1 % of the frames moved by 10 noise stds) are not structure: the
// noise model leaves them out (variogram differences beyond 4 MAD-sigmas) and the residual
// tests clip them at 5 σ̂.
TEST(NoiseModelDiagnoseTest, MocapOutliersAreNotStructure) {
  effects::SyntheticConfig config;
  config.seed = 211;
  config.trials = 7;
  config.noise_process.outlier_rate = 0.01;
  config.noise_process.outlier_sigmas = 10.0;
  const Diagnosis d = Diagnose(effects::MakeSyntheticTrials(config).trials, BaseOnly());
  EXPECT_NEAR(d.noise.z.sigma / config.noise_xz, 1.0, 0.25);
  EXPECT_EQ(d.verdict, Verdict::kAdequate) << d.base_check.Evidence();
}

// The paper's case (seed 000 §IV-3): caster (tyre) compliance strong enough that the base
// model's held-out pitch fitness falls near 57.6 %, trials from `pwsim generate`'s generator
// (the lab's chair without gm/lm: the base model is identified first, on training trials).
TEST(PaperCaseTest, CasterComplianceNearTheObservedPitchFitness) {
  GenerateConfig config;
  config.without_cushion = false;
  config.seed = 2024;
  config.truth_model = effects::MakeEffectTruthModel(EffectId::kTyreCompliance, 2.0, config.truth);
  const TrialSet set = GenerateTrialSet(config);
  std::string source;
  const std::vector<effects::TrialRecord> records = RecordsFromMeasured(set.Measured(), &source);
  EXPECT_NE(source.find("identified"), std::string::npos);
  ASSERT_TRUE(records.front().chair.gm.has_value());
  DiagnoseOptions first;  // the paper's one cause (rounds of joint fits for a second would only cost time)
  first.max_causes = 1;
  const Diagnosis d = Diagnose(records, first);
  EXPECT_EQ(d.cause, "tyre_compliance") << VerdictName(d.verdict) << "; " << CausesLine(d);
  EXPECT_EQ(d.split, "speed 1.20 m/s left out");  // the paper validates at 1.2 m/s
  EXPECT_NEAR(d.base_heldout.pitch, 57.6, 12.0);
  EXPECT_GT(d.extended_heldout.pitch, 95.0);
  EXPECT_GT(d.extended_heldout.z, d.base_heldout.z);
}

}  // namespace
}  // namespace pwsim::diagnose
