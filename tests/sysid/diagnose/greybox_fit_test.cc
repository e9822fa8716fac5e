// FitModelJoint's multi-start over a family's members x starts (effect_catalog.h, EffectFamily):
// it keeps the member the data were made with, a joint fit's multi-start changes only the new
// extension's member, and the family descriptions solve the starts they say.

#include "sysid/diagnose/greybox_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "synth/synthetic_trials.h"

namespace pwsim::diagnose {
namespace {

using effects::EffectId;

/// Fit trials of a seeded chair (pwsim's generator's drives, speeds and loads) whose measured
/// heave and pitch are the extended model's with `truth`, plus white mocap noise.
std::vector<FitTrial> TrialsWith(const effects::EffectParams& truth, int trials = 4, double noise_scale = 1.0) {
  effects::SyntheticConfig config;
  config.seed = 7;
  config.trials = trials;
  config.speeds = {1.2, 1.8, 2.4};
  const effects::SyntheticSet set = effects::MakeSyntheticTrials(config);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<FitTrial> out;
  for (const effects::TrialRecord& record : set.trials) {
    FitTrial trial = MakeFitTrial(record, record.chair);
    const effects::ModelOutput model =
        effects::SimulateExtended(trial.prepared, effects::ExtendedParams{*record.chair.lm, truth});
    for (std::size_t k = 0; k < trial.z.size(); ++k) {
      trial.z[k] = model.z[k] + noise_scale * 3e-4 * noise(rng);
      trial.pitch[k] = model.pitch[k] + noise_scale * 6e-4 * noise(rng);
    }
    out.push_back(std::move(trial));
  }
  return out;
}

effects::EffectParams StopsBothWays() {
  effects::EffectParams fx;
  fx.member.stops = effects::StopSides::kBoth;
  fx.bump_gain = 2.0;
  fx.bump_gap = 0.002;
  return fx;
}

// Stops acting in rebound as well as compression: the family's two members are each solved
// from their best start; the compression-only member's fits are worse and not kept.
TEST(FitModelJointTest, MultiStartKeepsTheMemberTheTrialsWereMadeWith) {
  const std::vector<FitTrial> trials = TrialsWith(StopsBothWays());
  const LumpedParams lm = *trials.front().prepared.chair.lm;
  const FitResult fit = FitModel(trials, EffectId::kNonlinearStiffness, lm, MakeChannelWeights(trials));
  EXPECT_EQ(fit.member, "both");
  EXPECT_EQ(fit.params.fx.member.stops, effects::StopSides::kBoth);
  ASSERT_EQ(fit.starts.size(), 3u);  // the best start of each member
  EXPECT_EQ(fit.starts[0].member, "compression");
  EXPECT_EQ(fit.starts[1].member, "both");
  EXPECT_EQ(fit.starts[2].member, "rebound");
  EXPECT_GT(fit.starts[2].sse, 1.5 * fit.sse);
  EXPECT_GT(fit.starts[0].sse, 1.5 * fit.sse) << fit.starts[0].sse << " " << fit.starts[1].sse;
  EXPECT_NEAR(fit.params.fx.bump_gap / 0.002, 1.0, 0.2);
}

// Massless tyres in series (TyreLaw::kMassless): the tyre family keeps that member, with the
// truth's caster compliance, over the unsprung members that cannot reach it.
TEST(FitModelJointTest, MultiStartKeepsMasslessTyres) {
  effects::EffectParams truth;
  truth.member.tyre = effects::TyreLaw::kMassless;
  truth.caster_tyre_compliance = 8e-5;
  truth.drive_tyre_compliance = 2e-5;
  truth.tyre_time_constant = 0.006;
  const std::vector<FitTrial> trials = TrialsWith(truth);
  const LumpedParams lm = *trials.front().prepared.chair.lm;
  const FitResult fit = FitModel(trials, EffectId::kTyreCompliance, lm, MakeChannelWeights(trials));
  EXPECT_EQ(fit.member, "massless");
  EXPECT_EQ(fit.params.fx.member.tyre, effects::TyreLaw::kMassless);
  EXPECT_NEAR(fit.params.fx.caster_tyre_compliance / 8e-5, 1.0, 0.25);
  double unsprung = std::numeric_limits<double>::infinity();
  for (const FitResult::SolvedStart& s : fit.starts)
    if (s.member != "massless") unsprung = std::min(unsprung, s.sse);
  EXPECT_GT(unsprung, 1.2 * fit.sse);
}

// A range narrowed by another measurement (FitOptions::narrowed) intersects the family's
// bounds; a start outside it moves to its middle; a range disjoint from the bounds is ignored.
TEST(FitBoundsTest, ANarrowedRangeIntersectsTheFamilysBounds) {
  const effects::ParamSpec spec{"marker_lever_z_m", 0.2, -1.5, 1.5, {0.0, 0.5}};
  FitOptions options;
  EXPECT_EQ(FitBounds(spec, options), std::make_pair(-1.5, 1.5));
  EXPECT_EQ(StartWithin(2.0, spec, options), 1.5);
  options.narrowed.push_back({"marker_lever_z_m", 0.3, 2.0});
  options.narrowed.push_back({"marker_lever_x_m", -0.01, 0.01});  // another parameter's
  EXPECT_EQ(FitBounds(spec, options), std::make_pair(0.3, 1.5));
  EXPECT_EQ(StartWithin(0.5, spec, options), 0.5);
  EXPECT_EQ(StartWithin(0.0, spec, options), 0.9);
  options.narrowed.front() = {"marker_lever_z_m", 1.6, 2.0};
  EXPECT_EQ(FitBounds(spec, options), std::make_pair(-1.5, 1.5));
}

// A marker lever 0.4 m high: fitted freely, its height is found; held within a range the
// measured x would allow for a marker at O_V, the fit stays inside it, and fits worse.
TEST(FitModelJointTest, ANarrowedLeverHeightStaysInItsRange) {
  effects::EffectParams truth;
  truth.marker_lever_x = 0.1;
  truth.marker_lever_z = 0.4;
  const std::vector<FitTrial> trials = TrialsWith(truth);
  const LumpedParams lm = *trials.front().prepared.chair.lm;
  const ChannelWeights w = MakeChannelWeights(trials);
  const FitResult free = FitModel(trials, EffectId::kMarkerOffset, lm, w);
  EXPECT_NEAR(free.params.fx.marker_lever_z, 0.4, 0.04);
  FitOptions held;
  held.narrowed.push_back({"marker_lever_z_m", -0.05, 0.05});
  const FitResult narrowed = FitModel(trials, EffectId::kMarkerOffset, lm, w, held);
  EXPECT_GE(narrowed.params.fx.marker_lever_z, -0.05);
  EXPECT_LE(narrowed.params.fx.marker_lever_z, 0.05);
  EXPECT_GT(narrowed.sse, 1.5 * free.sse);
}

// PlausibleLm keeps a plausible LM (the paper's on its chair) and replaces an axis that fled
// to K ≈ 0 by the paper's mode on the chair's own mass and inertia.
TEST(PlausibleLmTest, ReplacesOnlyTheAxisThatFled) {
  Chair chair = MakeTableOneChair();
  const LumpedParams paper = *chair.lm;
  const LumpedParams kept = PlausibleLm(chair, paper, 50.0);
  EXPECT_EQ(kept.k_z, paper.k_z);
  EXPECT_EQ(kept.k_theta, paper.k_theta);
  chair.mass = 80.0;
  chair.inertia = 14.0;
  LumpedParams fled = paper;
  fled.k_theta = 1e-38;
  const LumpedParams fixed = PlausibleLm(chair, fled, 20.0);
  EXPECT_EQ(fixed.k_z, paper.k_z);
  EXPECT_EQ(fixed.c_z, paper.c_z);
  chair.lm = fixed;
  const Chair table = MakeTableOneChair();
  EXPECT_NEAR(PitchMode(chair, 20.0).omega_n, PitchMode(table, 50.0).omega_n, 1e-9);
  EXPECT_NEAR(PitchMode(chair, 20.0).zeta, PitchMode(table, 50.0).zeta, 1e-12);
  EXPECT_NEAR(PitchMode(table, 50.0).omega_n / (2.0 * std::numbers::pi), 3.0, 0.1);
}

// A base whose pitch stiffness fled to 1e-38 (as identification's did on development set 13):
// the LM may move only e^±2.5 from where it starts, so a fit from there alone cannot find the
// inertial pitch; the multi-start from the plausible LM does.
TEST(FitModelJointTest, AFledBaseIsRefittedFromAPlausibleLm) {
  effects::EffectParams truth;
  truth.cm_lever = 0.4;
  truth.load_cm_lever = 0.3;
  const std::vector<FitTrial> trials = TrialsWith(truth);
  effects::ExtendedParams fled{*trials.front().prepared.chair.lm, {}};
  fled.lm.k_theta = 1e-38;
  const FitResult fit = FitModelJoint(trials, {EffectId::kInertialPitch}, fled, MakeChannelWeights(trials));
  EXPECT_NEAR(fit.params.lm.k_theta / trials.front().prepared.chair.lm->k_theta, 1.0, 0.1)
      << fit.params.lm.k_theta << " " << fit.params.fx.cm_lever << " " << fit.sse << " " << fit.iterations;
  EXPECT_NEAR(fit.params.fx.cm_lever / 0.4, 1.0, 0.2);
  FitOptions one;
  one.multi_start = false;
  const FitResult stuck = FitModelJoint(trials, {EffectId::kInertialPitch}, fled, MakeChannelWeights(trials), one);
  EXPECT_LT(stuck.params.lm.k_theta, 1e-30);
  EXPECT_GT(stuck.sse, 10.0 * fit.sse) << stuck.sse << " " << stuck.params.lm.k_theta;
}

// Stops acting in rebound only: the family's third member is kept, with the truth's gap.
TEST(FitModelJointTest, MultiStartKeepsReboundOnlyStops) {
  effects::EffectParams truth = StopsBothWays();
  truth.member.stops = effects::StopSides::kRebound;
  const std::vector<FitTrial> trials = TrialsWith(truth);
  const LumpedParams lm = *trials.front().prepared.chair.lm;
  const FitResult fit = FitModel(trials, EffectId::kNonlinearStiffness, lm, MakeChannelWeights(trials));
  EXPECT_EQ(fit.member, "rebound");
  EXPECT_EQ(fit.params.fx.member.stops, effects::StopSides::kRebound);
  ASSERT_EQ(fit.starts.size(), 3u);
  for (const FitResult::SolvedStart& s : fit.starts) {
    if (s.member != "rebound") {
      EXPECT_GT(s.sse, 1.5 * fit.sse) << s.member;
    }
  }
  EXPECT_NEAR(fit.params.fx.bump_gap / 0.002, 1.0, 0.2);
}

// A joint fit multi-starts only its last effect: the earlier effect's member (a whole-chair
// cushion found before) stays as given, the new family's members are the only ones tried.
TEST(FitModelJointTest, AJointStartCarriesOnlyTheNewExtensionsMember) {
  effects::EffectParams truth = StopsBothWays();
  truth.member.cushion_load = effects::CushionLoad::kWholeChair;
  truth.cushion_loss_per_kn = 0.1;
  const std::vector<FitTrial> trials = TrialsWith(truth, 3);
  effects::ExtendedParams start{*trials.front().prepared.chair.lm, {}};
  start.fx.member.cushion_load = effects::CushionLoad::kWholeChair;
  start.fx.cushion_loss_per_kn = 0.1;
  FitOptions options;
  options.max_iterations = 6;
  const FitResult fit = FitModelJoint(trials, {EffectId::kCushionCompliance, EffectId::kNonlinearStiffness},
                                      start, MakeChannelWeights(trials), options);
  EXPECT_EQ(fit.params.fx.member.cushion_load, effects::CushionLoad::kWholeChair);
  ASSERT_EQ(fit.starts.size(), 3u);
  for (const FitResult::SolvedStart& s : fit.starts)
    EXPECT_TRUE(s.member == "compression" || s.member == "both" || s.member == "rebound") << s.member;
  EXPECT_EQ(fit.member, "both");
  // Without a multi-start, the one start given, every member as given.
  options.multi_start = false;
  effects::ExtendedParams refine = fit.params;
  const FitResult again = FitModelJoint(trials, fit.effects, refine, MakeChannelWeights(trials), options);
  ASSERT_EQ(again.starts.size(), 1u);
  EXPECT_EQ(again.member, "");
  EXPECT_EQ(again.params.fx.member.cushion_load, effects::CushionLoad::kWholeChair);
  EXPECT_EQ(again.params.fx.member.stops, effects::StopSides::kBoth);
}

// Exact kinematics is a member of the whole model: where the measured pitch swings past
// options.small_angle_limit the multi-start is run under it as well. These trials swing less
// than the default 0.2 rad, so only small angles are tried; with the limit at 0 both are (the
// small-angle solves as before, to the bit), and trials made (noise-free) under exact
// kinematics keep it, every small-angle solve worse.
TEST(FitModelJointTest, ExactKinematicsIsTriedPastTheSmallAngleLimitAndKeptWhenTheDataSaySo) {
  effects::EffectParams truth = StopsBothWays();
  truth.member.kinematics = effects::Kinematics::kExact;
  const std::vector<FitTrial> trials = TrialsWith(truth, 3, 0.0);
  const LumpedParams lm = *trials.front().prepared.chair.lm;
  const ChannelWeights w = MakeChannelWeights(trials);
  FitOptions options;
  options.max_iterations = 8;
  const FitResult small = FitModel(trials, EffectId::kNonlinearStiffness, lm, w, options);
  ASSERT_EQ(small.starts.size(), 3u);
  for (const FitResult::SolvedStart& s : small.starts)
    EXPECT_EQ(s.kinematics, effects::Kinematics::kSmallAngle);
  options.small_angle_limit = 0.0;
  const FitResult both = FitModel(trials, EffectId::kNonlinearStiffness, lm, w, options);
  ASSERT_EQ(both.starts.size(), 6u);  // each member under each kinematics
  // The small-angle multi-start is run by itself, as without the limit, to the bit.
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(both.starts[k].kinematics, effects::Kinematics::kSmallAngle);
    EXPECT_EQ(both.starts[k].sse, small.starts[k].sse);
  }
  EXPECT_EQ(both.params.fx.member.kinematics, effects::Kinematics::kExact);
  EXPECT_EQ(both.member, "both");
  for (const FitResult::SolvedStart& s : both.starts)
    if (s.kinematics == effects::Kinematics::kSmallAngle) {
      EXPECT_GT(s.sse, both.sse) << s.member;
    }
  EXPECT_LT(both.sse, small.sse);
}

// The family descriptions: each member's starts are full parameter vectors within bounds; the
// tyre family's stiff member holds both compliances at 0 and its compliant member never starts
// both at 0; the stops' rebound member always starts with stops.
TEST(EffectFamilyTest, MembersStartWithinBoundsAndHoldWhatTheySay) {
  for (EffectId id : effects::AllEffects()) {
    const effects::EffectFamily& family = effects::Family(id);
    EXPECT_EQ(family.id, id);
    ASSERT_FALSE(family.members.empty());
    for (const effects::FamilyMember& m : family.members) {
      ASSERT_FALSE(m.starts.empty()) << m.name;
      for (const std::vector<double>& s : m.starts) {
        ASSERT_EQ(s.size(), family.params.size());
        for (std::size_t j = 0; j < s.size(); ++j) {
          EXPECT_GE(s[j], family.params[j].lower) << m.name << " " << family.params[j].name;
          EXPECT_LE(s[j], family.params[j].upper) << m.name << " " << family.params[j].name;
        }
      }
    }
  }
  const effects::EffectFamily& tyre = effects::Family(EffectId::kTyreCompliance);
  ASSERT_EQ(tyre.members.size(), 3u);
  EXPECT_EQ(tyre.members[0].held, (std::vector<std::size_t>{3, 4, 5, 6}));
  EXPECT_EQ(tyre.members[1].held, (std::vector<std::size_t>{5, 6}));  // one c_t for every caster
  EXPECT_EQ(tyre.members[0].starts.size(), 6u);  // 3 caster x 2 drive periods x 1 damping
  for (const auto& s : tyre.members[0].starts) EXPECT_TRUE(s[3] == 0.0 && s[4] == 0.0);
  EXPECT_EQ(tyre.members[1].starts.size(), 6u * 8u);  // the 9 compliance pairs but (0, 0)
  for (const auto& s : tyre.members[1].starts) EXPECT_TRUE(s[3] > 0.0 || s[4] > 0.0);
  // Massless: the periods and ζ held (unused), the 8 compliance pairs x 2 time constants; the
  // rear casters' ratio fitted from 1 (the front casters' compliance).
  EXPECT_EQ(tyre.members[2].setting.tyre, effects::TyreLaw::kMassless);
  EXPECT_EQ(tyre.members[2].held, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(tyre.members[2].starts.size(), 8u * 2u);
  for (const auto& s : tyre.members[2].starts) EXPECT_TRUE((s[3] > 0.0 || s[4] > 0.0) && s[6] == 1.0);
  const effects::EffectFamily& stops = effects::Family(EffectId::kNonlinearStiffness);
  ASSERT_EQ(stops.members.size(), 3u);
  for (std::size_t m = 1; m < 3; ++m)
    for (const auto& s : stops.members[m].starts) EXPECT_GT(s[2], 0.0);
  EXPECT_EQ(stops.members[1].setting.stops, effects::StopSides::kBoth);
  EXPECT_EQ(stops.members[2].setting.stops, effects::StopSides::kRebound);
}

// The drift terms (greybox_fit.h DriftTerms): K = 1 + ⌊T/(π s_d)⌋ cosines, orthonormal over
// the trial's (unevenly spaced) samples; a residual made of an offset and cosines below the
// knee leaves entirely, one well above it stays (its leak only what its cosine shares with the
// slow terms over the finite trial), and the model output absorbs what left the residual.
TEST(DriftTermsTest, OrthonormalSlowCosinesLeaveTheResidualFastOnesStay) {
  EXPECT_EQ(DriftModes(10.0, 0.5, 1000), 7u);   // 1 + floor(10 / (π 0.5)) = 1 + 6
  EXPECT_EQ(DriftModes(10.0, 0.0, 1000), 0u);   // no slow part: no terms
  EXPECT_EQ(DriftModes(100.0, 0.15, 1000), kMaxDriftModes);
  EXPECT_EQ(DriftModes(10.0, 0.15, 50), 5u);    // a tenth of the samples at most
  std::vector<FitTrial> trials = TrialsWith(effects::EffectParams{}, 1, 0.0);
  FitTrial& trial = trials.front();
  for (std::size_t k = 0; k < trial.t.size(); ++k) trial.t[k] += 1e-3 * std::sin(0.37 * static_cast<double>(k));
  SetDriftTerms(trial, 0.5, 0.0);
  const std::size_t n = trial.t.size();
  const double t0 = trial.t.front(), span = trial.t.back() - t0;
  const std::size_t modes = DriftModes(span, 0.5, n);
  ASSERT_EQ(trial.drift.modes_z, modes);
  EXPECT_EQ(trial.drift.modes_pitch, 0u);
  ASSERT_EQ(trial.drift.basis.size(), n * modes);
  for (std::size_t a = 0; a < modes; ++a)
    for (std::size_t b = 0; b <= a; ++b) {
      double dot = 0.0;
      for (std::size_t i = 0; i < n; ++i) dot += trial.drift.basis[a * n + i] * trial.drift.basis[b * n + i];
      EXPECT_NEAR(dot, a == b ? 1.0 : 0.0, 1e-12) << a << " " << b;
    }
  // Measured Z = the model's + 2 mm + a slow wander (cosines 1 and K-1 below the knee) + a fast
  // cosine at 8 Hz; pitch the model's + 1 mrad (centred on the rest: the offset goes).
  const effects::ExtendedParams base{*trial.prepared.chair.lm, {}};
  const effects::ModelOutput model = effects::SimulateExtended(trial.prepared, base);
  const double pi = std::numbers::pi;
  std::vector<double> fast(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = (trial.t[i] - t0) / span;
    fast[i] = 3e-4 * std::sin(2.0 * pi * 8.0 * (trial.t[i] - t0));
    trial.z[i] = model.z[i] + 2e-3 + 1e-3 * std::cos(pi * u) +
                 5e-4 * std::cos(pi * static_cast<double>(modes - 1) * u) + fast[i];
    trial.pitch[i] = model.pitch[i] + 1e-3;
  }
  const TrialResidual res = ComputeResidual(trial, base);
  ASSERT_TRUE(res.finite);
  double leak = 0.0, fast_power = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    leak += (res.e_z[i] - fast[i]) * (res.e_z[i] - fast[i]);
    fast_power += fast[i] * fast[i];
    EXPECT_NEAR(res.e_pitch[i], 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(res.z_model[i], trial.z[i] - res.e_z[i]);
  }
  EXPECT_LT(leak, 1e-2 * fast_power) << leak / fast_power;
}

}  // namespace
}  // namespace pwsim::diagnose
