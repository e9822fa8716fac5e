#include "sysid/effects/effect_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/drive_profile.h"
#include "sysid/effects/effect_catalog.h"
#include "synth/effect_truth_model.h"
#include "sysid/measured/measured_trial.h"
#include "synth/generate.h"

namespace pwsim::effects {
namespace {

/// The paper's trial: Table I chair over the speed cushion at `speed`, sampled at 100 Hz.
PreparedTrial CushionTrial(double speed, double load_kg = 100.0, double step = 1e-3) {
  DriveProfile drive;
  drive.start_x = 0.0;
  drive.speed = speed;
  drive.accel = 1.0;
  drive.decel = 1.0;
  drive.stop_x = 7.0;
  std::vector<double> t, x, a;
  for (double time = 0.0; time < drive.StopTime() + 0.3; time += 0.01) {
    const Longitudinal l = EvaluateDrive(drive, time);
    t.push_back(time);
    x.push_back(l.x);
    a.push_back(l.a);
  }
  PreparedTrial trial = PrepareTrial(MakeTableOneChair(), MakeSpeedCushion(), load_kg, t, x, a);
  trial.step = step;
  return trial;
}

double MaxAbsDiff(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  return worst;
}

TEST(EffectModelTest, NoEffectIsIdentificationsModelBitForBit) {
  // Identification and diagnosis fit one base model: the extended model with every effect off
  // is the exact-discretised GM + LM that `pwsim identify` fits, to the last bit, at the
  // identification's step and at another one.
  for (double step : {1e-3, 2.5e-3}) {
    PreparedTrial trial = CushionTrial(1.2, 100.0, step);
    const ModelOutput ours = SimulateExtended(trial, ExtendedParams{*trial.chair.lm, {}});
    const pwsim::ModelOutput exact = SimulateMeasuredTrial(
        trial.chair, trial.terrain, trial.load_kg, trial.t, trial.x, SimulationOptions{step});
    EXPECT_EQ(ours.z, exact.z) << step;
    EXPECT_EQ(ours.pitch, exact.pitch) << step;
    CacheInputs(trial);
    const ModelOutput cached = SimulateExtended(trial, ExtendedParams{*trial.chair.lm, {}});
    EXPECT_EQ(cached.z, exact.z) << step;
    EXPECT_EQ(cached.pitch, exact.pitch) << step;
  }
}

TEST(EffectModelTest, CachedInputsGiveTheSameOutput) {
  PreparedTrial trial = CushionTrial(1.8, 50.0, 0.002);
  ExtendedParams params{*trial.chair.lm, {}};
  params.fx.heave_hardening = 1.0;
  params.fx.cushion_loss_per_kn = 0.2;  // uses the wheel cache, not the GM cache
  const ModelOutput plain = SimulateExtended(trial, params);
  CacheInputs(trial);
  const ModelOutput cached = SimulateExtended(trial, params);
  EXPECT_LT(MaxAbsDiff(plain.z, cached.z), 1e-12);
  EXPECT_LT(MaxAbsDiff(plain.pitch, cached.pitch), 1e-12);
  params.fx.cushion_loss_per_kn = 0.0;  // GM cache
  const ModelOutput a = SimulateExtended(trial, params);
  trial.cache_step = 0.0;
  const ModelOutput b = SimulateExtended(trial, params);
  EXPECT_LT(MaxAbsDiff(a.z, b.z), 1e-12);
  EXPECT_LT(MaxAbsDiff(a.pitch, b.pitch), 1e-12);
}

TEST(EffectModelTest, RollingDiscEnvelopeMatchesBruteForce) {
  const Terrain terrain = MakeSpeedCushion(1.8, 0.065, 0.30, 1.5, 12.0);
  const Terrain step{{1.0, 1.0001, 3.0}, {0.0, 0.05, 0.05}};  // an almost vertical 5 cm step
  for (const Terrain* ground : {&terrain, &step}) {
    for (double radius : {0.05, 0.10, 0.17}) {
      for (double x = 0.5; x < 4.5; x += 0.013) {
        double best = -1e9;
        for (int i = -4000; i <= 4000; ++i) {
          const double s = radius * i / 4000.0;
          best = std::max(best, ground->HeightAt(x + s) + std::sqrt(radius * radius - s * s));
        }
        // The grid maximum can only fall short of the exact one.
        const double exact = RollingDiscEnvelope(*ground, x, radius).height;
        EXPECT_NEAR(exact, best - radius, 5e-5) << "x " << x << " R " << radius;
        EXPECT_GE(exact, best - radius - 1e-12) << "x " << x << " R " << radius;
      }
    }
  }
  // On a step of height h the wheel starts to rise sqrt(2Rh - h²) before the edge (anchors §0).
  const double r = 0.10, h = 0.05, d = std::sqrt(2 * r * h - h * h);
  EXPECT_NEAR(RollingDiscEnvelope(step, 1.0 - d - 1e-3, r).height, 0.0, 1e-12);
  EXPECT_GT(RollingDiscEnvelope(step, 1.0 - d + 5e-3, r).height, 1e-3);
  EXPECT_NEAR(RollingDiscEnvelope(step, 2.0, r).height, 0.05, 1e-12);
  // Slope is the derivative of the height.
  for (double x = 1.7; x < 2.3; x += 0.01) {
    const double dz = (RollingDiscEnvelope(terrain, x + 1e-6, 0.1).height -
                       RollingDiscEnvelope(terrain, x - 1e-6, 0.1).height) / 2e-6;
    EXPECT_NEAR(RollingDiscEnvelope(terrain, x, 0.1).slope, dz, 1e-3) << x;
  }
}

TEST(EffectModelTest, EveryEffectOffIsBaseAndOnChangesTheOutput) {
  const PreparedTrial trial = CushionTrial(1.2);
  const ExtendedParams base{*trial.chair.lm, {}};
  const ModelOutput reference = SimulateExtended(trial, base);
  for (EffectId id : AllEffects()) {
    ExtendedParams off = base;
    SetEffectValues(id, GetEffectValues(id, EffectParams{}), off.fx);
    const ModelOutput same = SimulateExtended(trial, off);
    EXPECT_EQ(same.z, reference.z) << EffectName(id);
    ExtendedParams on = base;
    on.fx = TruthEffect(id, 1.0, trial.chair);
    const ModelOutput changed = SimulateExtended(trial, on);
    const double dz = MaxAbsDiff(changed.z, reference.z);
    const double dp = MaxAbsDiff(changed.pitch, reference.pitch);
    EXPECT_TRUE(dz > 5e-4 || dp > 2e-3) << EffectName(id) << " dz " << dz << " dp " << dp;
    for (std::size_t k = 0; k < changed.z.size(); ++k) {
      ASSERT_TRUE(std::isfinite(changed.z[k]) && std::isfinite(changed.pitch[k])) << EffectName(id);
    }
  }
}

TEST(EffectModelTest, MarkerOffsetIsALeverArmThatMovesXAndZ) {
  // A tracked origin at (r_x, r_z) in the chair frame measures x + r_x cos θ - r_z sin θ and
  // Z + r_x sin θ + r_z (cos θ - 1): the extended model driven by that x must be the base model
  // driven by the true x (here x_measured - r_x, r_z = 0: cos θ ≈ 1 to 0.5 %), seen through the
  // lever (to 1 % of the 65 mm crossing: the contact rate ignores r_x sin θ θ̇).
  const PreparedTrial trial = CushionTrial(0.6);
  PreparedTrial moved = trial;
  for (double& x : moved.x) x -= 0.2;
  ExtendedParams params{*trial.chair.lm, {}};
  const ModelOutput base = SimulateExtended(trial, params);
  const ModelOutput truth = SimulateExtended(moved, params);
  params.fx.marker_lever_x = 0.2;
  const ModelOutput shifted = SimulateExtended(trial, params);
  double moved_by_x = 0.0;
  for (std::size_t k = 0; k < base.z.size(); ++k) {
    EXPECT_NEAR(shifted.pitch[k], truth.pitch[k], 1e-4 + 0.01 * std::abs(truth.pitch[k]));
    EXPECT_NEAR(shifted.z[k] - 0.2 * std::sin(shifted.pitch[k]), truth.z[k], 3e-4);
    moved_by_x = std::max(moved_by_x, std::abs(shifted.pitch[k] - base.pitch[k]));
  }
  EXPECT_GT(moved_by_x, 0.01);  // the 0.2 m shift of x matters
  // r_z alone: at rest (θ = 0) nothing changes; once the chair pitches, x carries -r_z sin θ
  // (4.5 cm at 0.09 rad), so the wheels meet the ramp elsewhere: more than the altitude's
  // r_z (cos θ - 1) alone.
  params.fx.marker_lever_x = 0.0;
  params.fx.marker_lever_z = 0.5;
  const ModelOutput up = SimulateExtended(trial, params);
  EXPECT_EQ(up.z.front(), base.z.front());
  double moved_by_z = 0.0;
  for (std::size_t k = 0; k < base.z.size(); ++k)
    moved_by_z = std::max(moved_by_z, std::abs(up.z[k] - 0.5 * (std::cos(up.pitch[k]) - 1.0) - base.z[k]));
  EXPECT_GT(moved_by_z, 2e-3);
}

TEST(EffectModelTest, CushionYieldsMoreUnderMoreLoadAndTyresKeepUnitGain) {
  // Quasi-static crossing (0.3 m/s): the plateau height seen by the model.
  auto plateau_z = [](double load, const EffectParams& fx) {
    const PreparedTrial trial = CushionTrial(0.3, load);
    const ModelOutput out = SimulateExtended(trial, ExtendedParams{*trial.chair.lm, fx});
    double z = 0.0;
    for (std::size_t k = 0; k < trial.x.size(); ++k) {
      if (std::abs(trial.x[k] - 2.85) < 0.01) z = out.z[k];  // every wheel on the plateau
    }
    return z;
  };
  EffectParams cushion;
  cushion.cushion_loss_per_kn = 0.2;
  const double rigid = plateau_z(0.0, {});
  EXPECT_NEAR(rigid, 0.065, 1e-4);
  const double light = plateau_z(0.0, cushion), heavy = plateau_z(100.0, cushion);
  EXPECT_LT(heavy, light);
  // h (1 - c W): drive wheel α = 0.66 of M g, casters 0.17 each; Z_GM = Σ α_i h_i.
  const Chair chair = MakeTableOneChair();
  double expected = 0.0;
  const std::vector<double> loads = StaticWheelLoads(chair, 100.0);
  for (int i = 0; i < 3; ++i) expected += chair.gm->alpha[i] * 0.065 * (1.0 - 0.2e-3 * loads[i]);
  EXPECT_NEAR(heavy, expected, 2e-4);
  EffectParams tyre;
  tyre.caster_tyre_period = 0.2;
  tyre.drive_tyre_period = 0.1;
  tyre.tyre_damping = 0.3;
  EXPECT_NEAR(plateau_z(50.0, tyre), 0.065, 5e-4);
}

TEST(EffectModelTest, TyreReactionVanishesAsTheTyreStiffens) {
  // z̈_u = ω² (h - z_u) + 2ζω (ḣ - ż_u) + ω² c_t R_i: the suspension's reaction moves a
  // compliant tyre in series with it and fades with its compliance c_t (c_t = 0: the
  // unit-gain filter of the ground).
  const PreparedTrial trial = CushionTrial(1.2, 50.0);
  ExtendedParams filter{*trial.chair.lm, {}};
  filter.fx.caster_tyre_period = 0.08;
  filter.fx.drive_tyre_period = 0.06;
  filter.fx.tyre_damping = 0.15;
  const ModelOutput reference = SimulateExtended(trial, filter);
  double previous = 1e9;
  for (double mass : {3.0, 30.0, 300.0, 3000.0, 30000.0}) {
    // Unsprung mass m_u on a tyre of the same ω: c_t = 1 / (m_u ω²).
    ExtendedParams series = filter;
    series.fx.caster_tyre_compliance = 1.0 / (mass * std::pow(2.0 * std::numbers::pi / 0.08, 2));
    series.fx.drive_tyre_compliance = 1.0 / (mass * std::pow(2.0 * std::numbers::pi / 0.06, 2));
    const ModelOutput out = SimulateExtended(trial, series);
    const double diff = MaxAbsDiff(out.z, reference.z) + 0.3 * MaxAbsDiff(out.pitch, reference.pitch);
    EXPECT_LT(diff, previous) << mass;
    if (mass == 3.0) {
      EXPECT_GT(diff, 1e-3);  // a light wheel: the series spring matters at mm level
    }
    if (mass == 30000.0) {
      EXPECT_LT(diff, 2e-5);
    }
    previous = diff;
  }
}

TEST(EffectModelTest, CompliantTyresKeepTheStaticResponseTheGmSaw) {
  // The GM is identified on ground heights, i.e. through each tyre in series with its
  // suspension; the tyre model picks the suspension's own shares s so that the series pairs
  // keep the GM's shares α, and adds each wheel's own spring on its height off the suspension
  // plane. So crawling over the cushion (quasi-static: every mode far above the input) the
  // chassis follows the GM of the ground heights whatever the tyres' compliance; casters and
  // drive wheel carry loads in the ratio 0.17 : 0.66, so a model that took α for the
  // suspension's shares would not (its series weights α_i / (1 + c_t α_i K_Z) differ from α).
  PreparedTrial trial = CushionTrial(0.05, 50.0);
  trial.chair.gm->beta = {{0, 2, 1.0}};  // the α-weighted plane's pitch (Σ α x = 0, drive at x = 0)
  ExtendedParams rigid{*trial.chair.lm, {}};
  rigid.fx.caster_tyre_period = 0.08;
  rigid.fx.drive_tyre_period = 0.08;
  rigid.fx.tyre_damping = 0.7;
  ExtendedParams soft = rigid;
  soft.fx.caster_tyre_compliance = 1.0 / trial.chair.lm->k_z;  // each tyre as stiff as K_Z
  soft.fx.drive_tyre_compliance = 1.0 / trial.chair.lm->k_z;
  const ModelOutput a = SimulateExtended(trial, rigid);
  const ModelOutput b = SimulateExtended(trial, soft);
  double rise = 0.0, tilt = 0.0;
  for (std::size_t k = 0; k < a.z.size(); ++k) {
    rise = std::max(rise, std::abs(a.z[k] - a.z.front()));
    tilt = std::max(tilt, std::abs(a.pitch[k] - a.pitch.front()));
  }
  ASSERT_GT(rise, 0.02);
  EXPECT_LT(MaxAbsDiff(a.z, b.z), 0.01 * rise);
  EXPECT_LT(MaxAbsDiff(a.pitch, b.pitch), 0.01 * tilt);
  // Driven at 1.2 m/s the same tyres matter (the hop modes are excited): the test can tell.
  const PreparedTrial fast = CushionTrial(1.2, 50.0);
  const ModelOutput fa = SimulateExtended(fast, rigid);
  const ModelOutput fb = SimulateExtended(fast, soft);
  EXPECT_GT(MaxAbsDiff(fa.z, fb.z), 0.05 * rise);
}

TEST(EffectModelTest, RearCastersTakeTheirRatioOnlyWhereCastersStandOnBothSides) {
  // ρ scales the casters behind O_V where there are casters in front too; with casters on one
  // side only it would merely rescale c_t, and is not applied.
  PreparedTrial trial;
  trial.chair.wheels = {{"front_caster", 0.4, 0.1}, {"drive", 0.0, 0.16}, {"rear_caster", -0.3, 0.08}};
  trial.is_caster = {true, false, true};
  EffectParams fx;
  fx.caster_tyre_compliance = 4e-5;
  fx.drive_tyre_compliance = 1e-5;
  fx.rear_caster_compliance_ratio = 1.5;
  const WheelArray both = TyreCompliances(fx, trial);
  EXPECT_EQ(both[0], 4e-5);
  EXPECT_EQ(both[1], 1e-5);
  EXPECT_DOUBLE_EQ(both[2], 6e-5);
  trial.chair.wheels[0].x = -0.5;  // a front-wheel-drive-like layout: every caster behind O_V
  const WheelArray behind = TyreCompliances(fx, trial);
  EXPECT_EQ(behind[0], 4e-5);
  EXPECT_EQ(behind[2], 4e-5);
}

TEST(EffectModelTest, MasslessTyresKeepTheStaticResponseAndFadeAsTheyStiffen) {
  // Massless tyres in series: each hub balances k_t (h - u) + τ_t k_t (ḣ - u̇) against its
  // suspension's reaction, solved implicitly. Crawling (quasi-static), the chassis follows the
  // GM of the ground heights whatever the tyres' compliance (the suspension's shares keep the
  // series pairs at the GM's α); driven at 1.2 m/s the tyres matter, less and less as they
  // stiffen, and the chassis tends to the base model.
  ExtendedParams massless{MakeTableOneChair().lm.value(), {}};
  massless.fx.member.tyre = TyreLaw::kMassless;
  massless.fx.tyre_time_constant = 0.004;
  auto soft = [&](double compliance) {
    ExtendedParams p = massless;
    p.fx.caster_tyre_compliance = compliance;
    p.fx.drive_tyre_compliance = 0.5 * compliance;
    return p;
  };
  PreparedTrial crawl = CushionTrial(0.05, 50.0);
  crawl.chair.gm->beta = {{0, 2, 1.0}};  // the α-weighted plane's pitch, as above
  const ModelOutput rigid = SimulateExtended(crawl, ExtendedParams{*crawl.chair.lm, {}});
  const ModelOutput crawled = SimulateExtended(crawl, soft(1.0 / crawl.chair.lm->k_z));
  double rise = 0.0;
  for (double z : rigid.z) rise = std::max(rise, std::abs(z - rigid.z.front()));
  ASSERT_GT(rise, 0.02);
  EXPECT_LT(MaxAbsDiff(rigid.z, crawled.z), 0.01 * rise);

  const PreparedTrial fast = CushionTrial(1.2, 50.0);
  const ModelOutput base = SimulateExtended(fast, ExtendedParams{*fast.chair.lm, {}});
  double previous = 1e9;
  for (double compliance : {1e-4, 1e-5, 1e-6, 1e-7}) {
    const ModelOutput out = SimulateExtended(fast, soft(compliance));
    const double diff = MaxAbsDiff(out.z, base.z) + 0.3 * MaxAbsDiff(out.pitch, base.pitch);
    EXPECT_LT(diff, previous) << compliance;
    if (compliance == 1e-4) {
      EXPECT_GT(diff, 1e-3);  // as soft as the suspension: mm
    }
    if (compliance == 1e-7) {
      EXPECT_LT(diff, 1e-4);
    }
    previous = diff;
  }
  // Stable for any damper, however small against the step, and the same motion at a finer step.
  ExtendedParams stiff_tyre = soft(2e-6);
  stiff_tyre.fx.tyre_time_constant = 1e-5;
  const ModelOutput coarse = SimulateExtended(fast, stiff_tyre);
  for (std::size_t k = 0; k < coarse.z.size(); ++k)
    ASSERT_TRUE(std::isfinite(coarse.z[k]) && std::abs(coarse.z[k]) < 1.0) << k;
  PreparedTrial fine_trial = CushionTrial(1.2, 50.0, 2.5e-4);
  const ModelOutput a = SimulateExtended(fast, soft(5e-5));
  const ModelOutput b = SimulateExtended(fine_trial, soft(5e-5));
  EXPECT_LT(MaxAbsDiff(a.z, b.z), 0.02 * rise);
}

TEST(EffectModelTest, DahlFrictionLeavesAStictionOffset) {
  const PreparedTrial trial = CushionTrial(0.8, 50.0);
  const ModelOutput base = SimulateExtended(trial, ExtendedParams{*trial.chair.lm, {}});
  // Moderate friction: after the crossing the chair comes to rest off its equilibrium, but
  // within the force band ΣF_c / K_Z of it (stiction), and the base model returns to it.
  ExtendedParams dry{*trial.chair.lm, {}};
  dry.fx.caster_friction = 60.0;
  dry.fx.drive_friction = 60.0;
  dry.fx.friction_presliding = 2e-4;
  const ModelOutput out = SimulateExtended(trial, dry);
  const std::size_t last = out.z.size() - 1;
  const double offset = std::abs(out.z[last] - out.z_gm[last]);
  EXPECT_LT(std::abs(base.z[last] - base.z_gm[last]), 1e-5);
  EXPECT_GT(offset, 2e-5);
  EXPECT_LT(offset, 3.0 * 60.0 / trial.chair.lm->k_z + 1e-4);
  for (std::size_t k = 0; k <= last; ++k) ASSERT_TRUE(std::isfinite(out.z[k]) && std::isfinite(out.pitch[k]));
}

TEST(EffectModelTest, ReboundStopsHoldTheChassisDownAndActOnlyPastTheirGap) {
  const PreparedTrial trial = CushionTrial(1.5, 0.0);
  ExtendedParams compression{*trial.chair.lm, {}};
  compression.fx.bump_gain = 2.0;
  compression.fx.bump_gap = 0.002;
  ExtendedParams both = compression;
  both.fx.member.stops = StopSides::kBoth;
  const ModelOutput a = SimulateExtended(trial, compression);
  const ModelOutput b = SimulateExtended(trial, both);
  // The chassis' largest rise above the GM's output is cut by the stops in rebound.
  double rise_a = 0.0, rise_b = 0.0;
  for (std::size_t k = 0; k < a.z.size(); ++k) {
    rise_a = std::max(rise_a, a.z[k] - a.z_gm[k]);
    rise_b = std::max(rise_b, b.z[k] - b.z_gm[k]);
  }
  ASSERT_GT(rise_a, 0.004);  // the crossing extends the suspension past the gap
  EXPECT_LT(rise_b, 0.9 * rise_a);
  // Stops in rebound only cut the rise as well, and with a gap wider than any extension they
  // never engage: the base model, to the bit.
  ExtendedParams rebound = both;
  rebound.fx.member.stops = StopSides::kRebound;
  const ModelOutput r = SimulateExtended(trial, rebound);
  double rise_r = 0.0;
  for (std::size_t k = 0; k < r.z.size(); ++k) rise_r = std::max(rise_r, r.z[k] - r.z_gm[k]);
  EXPECT_LT(rise_r, 0.9 * rise_a);
  // A gap wider than any stroke: the rebound stops never engage, to the bit.
  compression.fx.bump_gap = both.fx.bump_gap = rebound.fx.bump_gap = 0.5;
  EXPECT_EQ(SimulateExtended(trial, compression).z, SimulateExtended(trial, both).z);
  EXPECT_EQ(SimulateExtended(trial, rebound).z, SimulateExtended(trial, ExtendedParams{*trial.chair.lm, {}}).z);
}

TEST(EffectModelTest, InertialPitchTorqueFollowsAcceleration) {
  const PreparedTrial trial = CushionTrial(1.2, 100.0);
  // Both centres of mass at h = 0.43 m: Γ = (M_0 + M_u) h a.
  ExtendedParams params{*trial.chair.lm, {}};
  params.fx.cm_lever = 0.43;
  params.fx.load_cm_lever = 0.43;
  const ModelOutput out = SimulateExtended(trial, params);
  // Only the empty chair's centre of mass raised: Γ = M_0 h a (the occupant adds nothing).
  ExtendedParams chair_only{*trial.chair.lm, {}};
  chair_only.fx.cm_lever = 0.43;
  const ModelOutput out_chair = SimulateExtended(trial, chair_only);
  const ModelOutput base = SimulateExtended(trial, ExtendedParams{*trial.chair.lm, {}});
  // Mid-acceleration on the flat floor: quasi-static θ = Γ / K_θ.
  const double m = MovingMass(trial.chair, 100.0);
  const std::size_t k = 150;  // t = 1.5 s, still accelerating at 1 m/s² (start_delay 0.5 s)
  ASSERT_NEAR(trial.accel[k], 1.0, 1e-9);
  EXPECT_NEAR(out.pitch[k] - base.pitch[k], m * 0.43 * 1.0 / trial.chair.lm->k_theta, 5e-4);
  EXPECT_NEAR(out_chair.pitch[k] - base.pitch[k],
              trial.chair.mass * 0.43 * 1.0 / trial.chair.lm->k_theta, 5e-4);
}

/// The Table I chair, its pitch weights β scaled to sum to 1 (a rigid chord), standing still
/// at x = 0 on a long ramp of slope `slope`, 6 s at 100 Hz.
PreparedTrial RampTrial(double slope) {
  Terrain ramp;
  ramp.x = {-20.0, 20.0};
  ramp.z = {-20.0 * slope, 20.0 * slope};
  std::vector<double> t, x, a;
  for (int k = 0; k <= 600; ++k) {
    t.push_back(0.01 * k);
    x.push_back(0.0);
    a.push_back(0.0);
  }
  Chair chair = MakeTableOneChair();
  double sum = 0.0;
  for (const PairWeight& b : chair.gm->beta) sum += b.weight;
  for (PairWeight& b : chair.gm->beta) b.weight /= sum;
  return PrepareTrial(chair, ramp, 0.0, t, x, a);
}

// A rigid chassis at rest on a ramp of slope s (the GM's θ_GM = asin of the contacts' chord
// over the wheelbase). Small angles (the paper's): wheel i touches at x_i, the chord rises
// s·L over L and the chassis rests at θ = θ_GM = asin s. Exact: wheel i touches at x_i cos θ,
// the chord rises s L cos θ, θ_GM = asin(s cos θ), and the chassis rests where
// sin θ = sin θ_GM: tan θ = s, parallel to the ramp. With compliant tyres too (their
// reaction vanishes at rest). Z at O_V (x = 0) is 0 either way.
TEST(EffectModelTest, ExactKinematicsRestsParallelToARamp) {
  const double s = 0.35;
  const PreparedTrial trial = RampTrial(s);
  ExtendedParams small{*trial.chair.lm, {}};
  ExtendedParams exact = small;
  exact.fx.member.kinematics = Kinematics::kExact;
  ExtendedParams exact_tyres = exact;
  exact_tyres.fx.caster_tyre_period = 0.15;
  exact_tyres.fx.drive_tyre_period = 0.08;
  exact_tyres.fx.caster_tyre_compliance = 1e-4;
  exact_tyres.fx.drive_tyre_compliance = 2e-5;
  const std::size_t last = trial.t.size() - 1;
  const ModelOutput a = SimulateExtended(trial, small);
  EXPECT_NEAR(a.pitch[last], std::asin(s), 1e-9);
  EXPECT_NEAR(a.pitch_gm[last], std::asin(s), 1e-9);
  for (const ExtendedParams& p : {exact, exact_tyres}) {
    const ModelOutput b = SimulateExtended(trial, p);
    EXPECT_NEAR(b.pitch[last], std::atan(s), 1e-5);
    EXPECT_NEAR(b.pitch_gm[last], std::atan(s), 1e-5);
    EXPECT_NEAR(b.z[last], 0.0, 1e-5);
    EXPECT_GT(std::abs(b.pitch[last] - a.pitch[last]), 0.01);  // atan 0.35 = 0.337, asin 0.358
  }
}

// Exact and small-angle kinematics differ by O(θ³): on the paper's cushion (pitch within
// ±0.05 rad) the exact model's pitch stays within 2 % of its swing of the small-angle one,
// and the default (small angles) is identification's model bit for bit (the test above).
TEST(EffectModelTest, ExactKinematicsIsTheSmallAngleModelAtSmallAngles) {
  const PreparedTrial trial = CushionTrial(1.2, 100.0);
  ExtendedParams small{*trial.chair.lm, {}};
  ExtendedParams exact = small;
  exact.fx.member.kinematics = Kinematics::kExact;
  const ModelOutput a = SimulateExtended(trial, small);
  const ModelOutput b = SimulateExtended(trial, exact);
  double swing = 0.0;
  for (double p : a.pitch) swing = std::max(swing, std::abs(p - a.pitch.front()));
  ASSERT_GT(swing, 0.01);
  const double diff = MaxAbsDiff(a.pitch, b.pitch);
  EXPECT_GT(diff, 0.0);
  EXPECT_LT(diff, 0.02 * swing);
  EXPECT_LT(MaxAbsDiff(a.z, b.z), 0.02 * swing);
}

// Copying one effect into a model that already holds others (a joint fit's start) carries
// that effect's discrete member and leaves every other effect's, its member included, alone.
TEST(EffectCatalogTest, CopyEffectCarriesItsOwnMemberOnly) {
  EffectParams found;  // causes found so far: whole-chair cushion, rebound stops
  found.member.cushion_load = CushionLoad::kWholeChair;
  found.cushion_loss_per_kn = 0.3;
  found.member.stops = StopSides::kBoth;
  found.bump_gain = 0.2;
  EffectParams solo;  // an extension fitted alone: every other effect at its default
  solo.caster_tyre_period = 0.2;
  solo.caster_tyre_compliance = 3e-4;
  EffectParams to = found;
  CopyEffect(EffectId::kTyreCompliance, solo, to);
  EXPECT_EQ(to.caster_tyre_period, 0.2);
  EXPECT_EQ(to.caster_tyre_compliance, 3e-4);
  EXPECT_EQ(to.member.cushion_load, CushionLoad::kWholeChair);
  EXPECT_EQ(to.member.stops, StopSides::kBoth);
  EXPECT_EQ(to.cushion_loss_per_kn, 0.3);
  EffectParams basis;
  basis.member.cushion_load = CushionLoad::kWholeChair;
  basis.cushion_loss_per_kn = 0.1;
  EffectParams into;
  CopyEffect(EffectId::kCushionCompliance, basis, into);
  EXPECT_EQ(into.member.cushion_load, CushionLoad::kWholeChair);
  EXPECT_EQ(into.cushion_loss_per_kn, 0.1);
}

TEST(EffectCatalogTest, IdsParseAndParametersRoundTrip) {
  EXPECT_EQ(AllEffects().size(), 8u);
  for (EffectId id : AllEffects()) {
    EXPECT_EQ(ParseEffect(EffectName(id)), id);
    const auto& specs = EffectParameters(id);
    ASSERT_FALSE(specs.empty());
    std::vector<double> values;
    for (const ParamSpec& s : specs) {
      EXPECT_LT(s.lower, s.upper) << s.name;
      for (double start : s.starts) {
        EXPECT_GE(start, s.lower) << s.name;
        EXPECT_LE(start, s.upper) << s.name;
      }
      values.push_back(0.5 * (s.lower + s.upper));
    }
    EffectParams fx;
    SetEffectValues(id, values, fx);
    EXPECT_EQ(GetEffectValues(id, fx), values);
    // Truth values lie inside the fit's bounds at the tested strengths.
    const Chair chair = MakeTableOneChair();
    std::vector<double> strengths{0.7, 1.0, 1.5};
    if (id == EffectId::kTyreCompliance) strengths.push_back(2.0);  // the paper's case
    for (double strength : strengths) {
      const std::vector<double> truth = GetEffectValues(id, TruthEffect(id, strength, chair));
      for (std::size_t j = 0; j < specs.size(); ++j) {
        EXPECT_GE(truth[j], specs[j].lower) << specs[j].name << " at " << strength;
        EXPECT_LE(truth[j], specs[j].upper) << specs[j].name << " at " << strength;
      }
    }
  }
  EXPECT_FALSE(ParseEffect("caster_shimmy").has_value());
}

// Each parameter of the catalogue is bound to its own field of EffectParams, so writing one
// effect's values changes that effect's fields and no other effect's.
TEST(EffectCatalogTest, EachParameterOwnsOneFieldAndAUnit) {
  std::vector<double EffectParams::*> seen;
  for (EffectId id : AllEffects())
    for (const ParamSpec& s : EffectParameters(id)) {
      ASSERT_NE(s.field, nullptr) << s.name;
      EXPECT_EQ(std::count(seen.begin(), seen.end(), s.field), 0) << s.name << " shares a field";
      seen.push_back(s.field);
      EXPECT_GT(std::string(s.unit).size(), 0u) << s.name;
    }
  for (EffectId id : AllEffects()) {
    EffectParams fx;
    std::vector<double> values;
    for (const ParamSpec& s : EffectParameters(id)) values.push_back(s.upper);
    SetEffectValues(id, values, fx);
    for (EffectId other : AllEffects()) {
      if (other == id) continue;
      EXPECT_EQ(GetEffectValues(other, fx), GetEffectValues(other, EffectParams{}))
          << EffectName(id) << " wrote into " << EffectName(other);
    }
  }
}

TEST(EffectTruthModelTest, GeneratesTheHiddenEffectAndRejectsBadOverrides) {
  GenerateConfig config;
  config.speeds = {1.2};
  config.loads = {100.0};
  config.without_cushion = false;
  const TrialSet base = GenerateTrialSet(config);
  config.truth_model = MakeEffectTruthModel(EffectId::kMarkerOffset, 1.0, config.truth,
                                            {{"marker_lever_x_m", 0.3}});
  const TrialSet hidden = GenerateTrialSet(config);
  ASSERT_EQ(hidden.truth_model_id, "marker_offset");
  const MocapTrack& a = base.trials.front().measured.track;
  const MocapTrack& b = hidden.trials.front().measured.track;
  ASSERT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(b.z[k] - a.z[k]));
  EXPECT_GT(worst, 0.02);  // 0.3 m lever × sin(~0.2 rad)
  EXPECT_THROW(MakeEffectTruthModel(EffectId::kMarkerOffset, 1.0, config.truth, {{"lever", 0.1}}),
               std::invalid_argument);
  EXPECT_THROW(MakeEffectTruthModel(EffectId::kMarkerOffset, 1.0, config.truth,
                                    {{"marker_lever_x_m", 5.0}}),
               std::invalid_argument);
}

}  // namespace
}  // namespace pwsim::effects
