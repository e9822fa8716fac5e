// The extended model against the independent truth (tests/truth/, which shares no code with
// it) at the same physical parameters: a family's member must follow the law it stands for,
// or no fit can find that law in data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/chair.h"
#include "engine/terrain.h"
#include "sysid/effects/effect_model.h"
#include "tests/truth/independent_truth.h"

namespace pwsim::effects {
namespace {

/// The largest distance [m, rad] of the model's motion (relative to its first sample) from the
/// truth's noise-free motion (a deviation from static equilibrium).
struct Gap {
  double z_m{0.0};
  double pitch_rad{0.0};
};
Gap Distance(const ModelOutput& model, const truth::TruthTrial& truth) {
  Gap gap;
  for (std::size_t k = 0; k < truth.t.size(); ++k) {
    gap.z_m = std::max(gap.z_m, std::abs(model.z[k] - model.z.front() - truth.true_z[k]));
    gap.pitch_rad = std::max(gap.pitch_rad, std::abs(model.pitch[k] - model.pitch.front() - truth.true_pitch[k]));
  }
  return gap;
}

/// A 3-contact chair whose casters differ (development seed 113's: the front caster stiffer and
/// nearer O_V than the rear one, Σ k x = 0, c ∝ k, a soft drive wheel) on massless tyres of
/// k_t = 1.05 k_i at the casters (the truth's law: each tyre in proportion to its wheel's
/// suspension, so the rear caster's tyre is the softer), rigid at the drive wheel, τ_t 9.8 ms;
/// small-angle kinematics, no noise, 100 kg load over a 6 cm cushion.
constexpr double kRatio = 1.05, kTau = 0.0098;
truth::TruthTrialConfig TruthConfig(double speed) {
  truth::TruthTrialConfig c;
  c.chair.mass_kg = 58.0;
  c.chair.inertia_kgm2 = 10.7;
  c.chair.cm_height_m = 0.41;
  c.chair.wheels = {{"front_caster", 0.354, 0.11, 15728.0, 861.4, true},
                    {"drive", 0.0, 0.16, 6398.0, 350.4, false},
                    {"rear_caster", -0.4372, 0.09, 12733.0, 697.4, true}};
  c.effects.tyre_massless = true;
  c.effects.caster_tyre_ratio = kRatio;
  c.effects.tyre_tau_s = kTau;
  c.terrain.x_m = {0.0, 4.0, 4.3, 5.8, 6.1, 14.0};
  c.terrain.z_m = {0.0, 0.0, 0.06, 0.06, 0.0, 0.0};
  c.drive.speed_mps = speed;
  c.load_kg = 100.0;
  c.noise_x_m = c.noise_z_m = c.noise_pitch_rad = 0.0;
  c.small_angle = true;
  return c;
}

/// The same chair in the paper's terms: the GM's α the series pairs' shares (what
/// identification sees through the tyres), β the front-rear slope (exact here: Σ k x = 0 for the
/// series pairs too), the LM the suspension's own K_Z = Σ k, K_θ = Σ k x², C alike.
PreparedTrial OurTrial(const truth::TruthTrialConfig& c, const truth::TruthTrial& t) {
  Chair chair;
  chair.mass = c.chair.mass_kg;
  chair.inertia = c.chair.inertia_kgm2;
  chair.cm_height = c.chair.cm_height_m;
  GeometricParams gm;
  LumpedParams lm{0.0, 0.0, 0.0, 0.0};
  double series_sum = 0.0;
  for (const truth::TruthWheel& w : c.chair.wheels) {
    chair.wheels.push_back({w.name, w.x_m, w.radius_m});
    const double r = w.caster ? c.effects.caster_tyre_ratio : c.effects.drive_tyre_ratio;
    gm.alpha.push_back(r > 0.0 ? w.k_npm * r / (1.0 + r) : w.k_npm);
    series_sum += gm.alpha.back();
    lm.k_z += w.k_npm;
    lm.c_z += w.c_nspm;
    lm.k_theta += w.k_npm * w.x_m * w.x_m;
    lm.c_theta += w.c_nspm * w.x_m * w.x_m;
  }
  for (double& a : gm.alpha) a /= series_sum;
  gm.beta = {{0, 2, 1.0}};
  chair.gm = gm;
  chair.lm = lm;
  Terrain terrain;
  terrain.x = c.terrain.x_m;
  terrain.z = c.terrain.z_m;
  return PrepareTrial(chair, terrain, c.load_kg, t.t, t.true_x);
}

TEST(EffectModelVsTruthTest, MasslessTyresFollowTheTruthsHubBalanceWithTheRearCastersOwnCompliance) {
  for (double speed : {0.5, 1.3, 1.7}) {
    const truth::TruthTrialConfig config = TruthConfig(speed);
    const truth::TruthTrial truth = truth::SimulateTruthTrial(config);
    const PreparedTrial trial = OurTrial(config, truth);
    const double front_k = config.chair.wheels[0].k_npm, rear_k = config.chair.wheels[2].k_npm;
    ExtendedParams massless{*trial.chair.lm, {}};
    massless.fx.member.tyre = TyreLaw::kMassless;
    massless.fx.caster_tyre_compliance = 1.0 / (kRatio * front_k);
    massless.fx.rear_caster_compliance_ratio = front_k / rear_k;  // k_t ∝ k_i: softer behind
    massless.fx.tyre_time_constant = kTau;
    const Gap ours = Distance(SimulateExtended(trial, massless), truth);
    // One compliance for both casters (their mean): the family without the rear casters' ratio.
    ExtendedParams one_caster = massless;
    one_caster.fx.caster_tyre_compliance = 0.5 * (1.0 + front_k / rear_k) / (kRatio * front_k);
    one_caster.fx.rear_caster_compliance_ratio = 1.0;
    const Gap shared = Distance(SimulateExtended(trial, one_caster), truth);
    // No tyres: the suspension's own LM on the ground heights.
    const Gap rigid = Distance(SimulateExtended(trial, ExtendedParams{*trial.chair.lm, {}}), truth);
    // Within a fraction of a typical motion-capture noise (0.2-0.5 mm): the time steps differ
    // (1 ms fixed against Dormand-Prince) and the GM takes the slope's asin.
    EXPECT_LT(ours.z_m, 2e-4) << speed;
    EXPECT_LT(ours.pitch_rad, 2e-3) << speed;
    EXPECT_GT(rigid.z_m, 5.0 * ours.z_m) << speed;  // the tyres matter: the test can tell
    EXPECT_GT(rigid.pitch_rad, 5.0 * ours.pitch_rad) << speed;
    if (speed > 1.0) {
      EXPECT_GT(shared.z_m, 5.0 * ours.z_m) << speed;  // mm: a fit would see it
    }
  }
}

}  // namespace
}  // namespace pwsim::effects
