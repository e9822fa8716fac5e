#include "sysid/identify/identify.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/input_error.h"
#include "synth/generate.h"

namespace pwsim {
namespace {

/// The paper's protocol, trimmed for speed: 0.6 (GM), 1.2 (validation), 2.4 m/s (LM),
/// three loads, over the cushion, two repeats, realistic mocap noise.
GenerateConfig SmallProtocol(std::uint64_t seed) {
  GenerateConfig config;
  config.speeds = {0.6, 1.2, 2.4};
  config.loads = {0.0, 50.0, 100.0};
  config.without_cushion = false;
  config.repeats = 2;
  config.rate_hz = 100.0;
  config.noise_position = 0.3e-3;
  config.noise_pitch = 0.5e-3;
  config.seed = seed;
  return config;
}

double RelativeError(double value, double truth) { return std::abs(value - truth) / truth; }

TEST(AssignRolesTest, SlowestIsGmFastestIsLmMiddleIsValidation) {
  const TrialSet set = GenerateTrialSet(SmallProtocol(3));
  const std::vector<MeasuredTrial> trials = set.Measured();
  const std::vector<TrialRole> roles = AssignRoles(trials);
  ASSERT_EQ(roles.size(), trials.size());
  for (std::size_t k = 0; k < trials.size(); ++k) {
    const double speed = *trials[k].profile.speed;
    const TrialRole expected = speed < 1.0   ? TrialRole::kGeometric
                               : speed > 2.0 ? TrialRole::kLumped
                                             : TrialRole::kValidation;
    EXPECT_EQ(roles[k], expected) << trials[k].name;
  }
  EXPECT_STREQ(RoleName(TrialRole::kGeometric), "gm");
  EXPECT_STREQ(RoleName(TrialRole::kLumped), "lm");
  EXPECT_STREQ(RoleName(TrialRole::kValidation), "validation");
}

TEST(IdentifyChairTest, RecoversTableOneFromGeneratedTrials) {
  const TrialSet set = GenerateTrialSet(SmallProtocol(11));
  const std::vector<MeasuredTrial> trials = set.Measured();
  const IdentifyResult result = IdentifyChair(trials, AssignRoles(trials));
  ASSERT_TRUE(result.chair.gm && result.chair.lm);
  const LumpedParams& truth = *set.truth.lm;
  const LumpedParams& got = *result.chair.lm;
  EXPECT_LT(RelativeError(got.k_z, truth.k_z), 0.02) << got.k_z;
  EXPECT_LT(RelativeError(got.k_theta, truth.k_theta), 0.02) << got.k_theta;
  EXPECT_LT(RelativeError(got.c_z, truth.c_z), 0.05) << got.c_z;
  EXPECT_LT(RelativeError(got.c_theta, truth.c_theta), 0.05) << got.c_theta;
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(result.chair.gm->alpha[i], set.truth.gm->alpha[i], 0.01) << "alpha " << i;
  }
  // Adjacent pairs are fitted, 1-3 is written as 0 (Table I: β13 = 0).
  ASSERT_EQ(result.chair.gm->beta.size(), 3u);
  EXPECT_NEAR(result.chair.gm->beta[0].weight, 0.5, 0.02);
  EXPECT_EQ(result.chair.gm->beta[1].weight, 0.0);
  EXPECT_NEAR(result.chair.gm->beta[2].weight, 0.6, 0.02);
  // Held-out trials are reproduced: the residual is mocap noise only.
  EXPECT_GT(result.validation_fit_z, 95.0);
  EXPECT_GT(result.validation_fit_pitch, 90.0);
  for (const TrialFit& fit : result.trials) {
    if (fit.role != TrialRole::kValidation) continue;
    EXPECT_GT(fit.fit_z, 93.0) << fit.trial;
    EXPECT_GT(fit.fit_pitch, 85.0) << fit.trial;
  }
}

// A terrain file 25 % taller than the ground the chair drove (as a cushion yielding a fifth of
// its height under the chair reads): free α scale down to sum 0.8 and fit the trials; rigid heave
// keeps Σα = 1, so the obstacle's missing height stays in the residual.
TEST(IdentifyGeometricTest, RigidHeaveKeepsTheWeightsSummingToOne) {
  const TrialSet set = GenerateTrialSet(SmallProtocol(12));
  std::vector<MeasuredTrial> trials = set.Measured();
  std::vector<const MeasuredTrial*> slow;
  for (MeasuredTrial& m : trials) {
    for (double& z : m.terrain.z) z *= 1.25;
    if (*m.profile.speed < 1.0) slow.push_back(&m);
  }
  auto sum = [](const GeometricParams& gm) {
    double s = 0.0;
    for (double a : gm.alpha) s += a;
    return s;
  };
  const GeometricParams free_gm = IdentifyGeometric(slow, set.truth);
  EXPECT_NEAR(sum(free_gm), 0.8, 0.01);
  IdentifyOptions rigid;
  rigid.rigid_heave = true;
  const GeometricParams rigid_gm = IdentifyGeometric(slow, set.truth, rigid);
  ASSERT_EQ(rigid_gm.alpha.size(), 3u);
  EXPECT_NEAR(sum(rigid_gm), 1.0, 1e-12);
  // The heights the wheels met, given as a scale of the file's (a cushion's yield, as a
  // diagnosis knows it): the weights are the truth's again, without the constraint too.
  for (MeasuredTrial& m : trials) m.contact_height_scale.assign(3, 0.8);
  const GeometricParams scaled = IdentifyGeometric(slow, set.truth);
  EXPECT_NEAR(sum(scaled), 1.0, 0.01);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(scaled.alpha[i], set.truth.gm->alpha[i], 0.02) << i;
  for (MeasuredTrial& m : trials) m.contact_height_scale.clear();
  // On the terrain as driven, both give the truth's weights (Table I, summing to 1; the slow
  // trials' dynamics, not filtered out in this single step, bias them by about 0.01).
  for (MeasuredTrial& m : trials)
    for (double& z : m.terrain.z) z /= 1.25;
  const GeometricParams truth_free = IdentifyGeometric(slow, set.truth);
  const GeometricParams truth_rigid = IdentifyGeometric(slow, set.truth, rigid);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(truth_free.alpha[i], set.truth.gm->alpha[i], 0.02) << i;
    EXPECT_NEAR(truth_rigid.alpha[i], set.truth.gm->alpha[i], 0.02) << i;
  }
}

TEST(IdentifyChairTest, SharedModeUsesOneFrequencyAndDampingRatio) {
  const TrialSet set = GenerateTrialSet(SmallProtocol(5));
  const std::vector<MeasuredTrial> trials = set.Measured();
  IdentifyOptions options;
  options.shared_mode = true;
  options.reference_load_kg = 100.0;
  const IdentifyResult result = IdentifyChair(trials, AssignRoles(trials), options);
  const Chair& chair = result.chair;
  const Mode heave = HeaveMode(chair, 100.0);
  const Mode pitch = PitchMode(chair, 100.0);
  EXPECT_NEAR(heave.omega_n, pitch.omega_n, 1e-9 * heave.omega_n);
  EXPECT_NEAR(heave.zeta, pitch.zeta, 1e-9);
  // Table I is (nearly) such a chair: 2.63 Hz, ζ 0.44 at 100 kg.
  EXPECT_NEAR(heave.omega_n / (2.0 * 3.141592653589793), 2.63, 0.05);
  EXPECT_NEAR(heave.zeta, 0.44, 0.02);
}

TEST(IdentifyChairTest, LinearEstimateIsAUsableStart) {
  const TrialSet set = GenerateTrialSet(SmallProtocol(7));
  const std::vector<MeasuredTrial> trials = set.Measured();
  const IdentifyResult result = IdentifyChair(trials, AssignRoles(trials));
  EXPECT_FALSE(result.start.fallback_z);
  EXPECT_FALSE(result.start.fallback_pitch);
  EXPECT_LT(RelativeError(result.start.lm.k_z, set.truth.lm->k_z), 0.3);
  EXPECT_LT(RelativeError(result.start.lm.k_theta, set.truth.lm->k_theta), 0.3);
}

TEST(IdentifyChairTest, NeedsTwoSpeeds) {
  GenerateConfig config = SmallProtocol(1);
  config.speeds = {1.2};
  config.loads = {100.0};
  const std::vector<MeasuredTrial> trials = GenerateTrialSet(config).Measured();
  EXPECT_THROW(IdentifyChair(trials, AssignRoles(trials)), InputError);
}

TEST(CompareTrialTest, TruthChairReproducesItsOwnTrialUpToNoise) {
  GenerateConfig config = SmallProtocol(2);
  config.speeds = {1.2};
  config.loads = {100.0};
  config.repeats = 1;
  config.noise_position = 0.0;
  config.noise_pitch = 0.0;
  config.z_offset = 0.35;  // the tracked origin above the floor: removed by centring
  const TrialSet set = GenerateTrialSet(config);
  const TrialComparison comparison = CompareTrial(set.trials[0].measured, set.truth);
  EXPECT_GT(comparison.fit_z, 99.9);
  EXPECT_GT(comparison.fit_pitch, 99.9);
}

}  // namespace
}  // namespace pwsim
