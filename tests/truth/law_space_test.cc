// The law space of the independent truth: the draw is a function of the seed alone, it reaches
// every law of every effect and every noise kind, forcing the noise kind leaves the laws as
// drawn, and each law the draw can pick changes the chair's motion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "tests/truth/independent_truth.h"
#include "tests/truth/law_space.h"

namespace pwsim::truth {
namespace {

TruthSetConfig OneTrial(std::uint64_t seed, std::vector<std::string> effects) {
  TruthSetConfig c;
  c.seed = seed;
  c.effects = std::move(effects);
  c.draw_laws = true;
  c.speeds = {1.2};
  c.loads = {80.0};
  return c;
}

TEST(LawSpace, TheDrawIsAFunctionOfTheSeed) {
  const TruthSet a = SimulateTruthSet(OneTrial(1000, {"cushion_compliance"}));
  const TruthSet b = SimulateTruthSet(OneTrial(1000, {"cushion_compliance"}));
  const TruthSet c = SimulateTruthSet(OneTrial(1001, {"cushion_compliance"}));
  EXPECT_EQ(a.trials[0].z, b.trials[0].z);
  EXPECT_EQ(a.trials[0].pitch, b.trials[0].pitch);
  EXPECT_EQ(a.laws, b.laws);
  EXPECT_NE(a.laws, c.laws);
  EXPECT_NE(a.trials[0].z, c.trials[0].z);
  ASSERT_EQ(a.laws.size(), 2u);  // the effect and the noise
  EXPECT_EQ(a.laws[0].rfind("cushion_compliance: ", 0), 0u);
  EXPECT_EQ(a.laws[1].rfind("noise ", 0), 0u);
}

/// "effect: law, parameters" -> the law's name (up to the first ',' or ':').
std::string LawName(const std::string& line) {
  const std::size_t start = line.find(": ") + 2;
  const std::size_t end = line.find_first_of(",:", start);
  return line.substr(start, end - start);
}

TEST(LawSpace, EveryLawAndNoiseKindIsDrawn) {
  std::map<std::string, std::set<std::string>> laws;
  std::set<std::string> kinds;
  std::mt19937_64 rng(5);
  const TruthChair chair = RandomTruthChair(rng);
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    for (const std::string& name : TruthEffectNames()) {
      const LawDraw d = DrawLaws(seed, {name}, chair);
      laws[name].insert(LawName(d.laws[0]));
      kinds.insert(d.noise.kind);
      // Strengths within the documented ranges.
      const TruthEffects& fx = d.effects;
      if (name == "wheel_radius") {
        EXPECT_GE(fx.contact_radius_scale, 0.6);
        EXPECT_LE(fx.contact_radius_scale, 1.4);
      } else if (name == "suspension_friction") {
        EXPECT_GE(fx.dahl_force_n, 20.0);
        EXPECT_LE(fx.dahl_force_n, 60.0);
      } else if (name == "heave_pitch_coupling") {
        EXPECT_GE(std::abs(fx.stiffness_asymmetry), 0.15);
        EXPECT_LE(std::abs(fx.stiffness_asymmetry), 0.4);
      }
    }
  }
  EXPECT_EQ(laws["tyre_compliance"].size(), 2u);
  EXPECT_EQ(laws["cushion_compliance"].size(), 3u);
  EXPECT_EQ(laws["nonlinear_stiffness"].size(), 3u);
  EXPECT_EQ(laws["suspension_friction"].size(), 4u) << *laws["suspension_friction"].begin();
  EXPECT_EQ(kinds.size(), NoiseKinds().size());
}

TEST(LawSpace, ForcingTheNoiseKindKeepsTheLaws) {
  std::mt19937_64 rng(9);
  const TruthChair chair = RandomTruthChair(rng);
  const LawDraw drawn = DrawLaws(1234, {"suspension_friction", "inertial_pitch"}, chair);
  std::vector<std::string> kinds = NoiseKinds();
  for (const std::string& extra : ExtraNoiseKinds()) kinds.push_back(extra);  // forced only
  for (const std::string& kind : kinds) {
    const LawDraw forced = DrawLaws(1234, {"suspension_friction", "inertial_pitch"}, chair, kind);
    EXPECT_EQ(forced.noise.kind, kind);
    EXPECT_FALSE(forced.noise.white_only);
    EXPECT_EQ(std::vector<std::string>(forced.laws.begin(), forced.laws.end() - 1),
              std::vector<std::string>(drawn.laws.begin(), drawn.laws.end() - 1));
  }
  EXPECT_THROW(DrawLaws(1, {}, chair, "brown"), std::invalid_argument);
  EXPECT_THROW(DrawLaws(1, {"warp_drive"}, chair), std::invalid_argument);
}

double MotionDifference(const TruthEffects& fx) {
  TruthSetConfig base;
  base.speeds = {1.2};
  base.loads = {80.0};
  const TruthSet plain = SimulateTruthSet(base);
  TruthTrialConfig c = plain.configs[0];
  c.effects = fx;
  const TruthTrial a = plain.trials[0], b = SimulateTruthTrial(c);
  double diff = 0.0;
  for (std::size_t k = 0; k < std::min(a.true_z.size(), b.true_z.size()); ++k)
    diff = std::max({diff, std::abs(a.true_z[k] - b.true_z[k]), 0.1 * std::abs(a.true_pitch[k] - b.true_pitch[k])});
  return diff;
}

TEST(LawSpace, EveryNewLawChangesTheMotion) {
  using Law = TruthEffects::FrictionLaw;
  std::vector<std::pair<std::string, TruthEffects>> cases;
  TruthEffects fx;
  fx.dahl_force_n = 40.0;
  fx.friction_law = Law::kSmoothCoulomb;
  cases.push_back({"smooth Coulomb per wheel", fx});
  fx.friction_chair_level = true;
  cases.push_back({"smooth Coulomb at chair level", fx});
  fx.friction_chair_level = false;
  fx.friction_law = Law::kStribeck;
  fx.friction_breakaway_ratio = 1.8;
  cases.push_back({"Stribeck", fx});
  fx = {};
  fx.tyre_massless = true;
  fx.caster_tyre_ratio = 0.8;
  cases.push_back({"massless series tyres", fx});
  fx = {};
  fx.cushion_yield = 0.15;
  fx.cushion_proportional = true;
  cases.push_back({"cushion yielding a fixed share", fx});
  fx = {};
  fx.bump_gain = 0.8;
  fx.bump_rebound_only = true;
  cases.push_back({"rebound stops", fx});
  for (const auto& [name, effects] : cases) EXPECT_GT(MotionDifference(effects), 5e-4) << name;
}

TEST(LawSpace, MasslessTyresRefuseRateDependentFriction) {
  TruthEffects fx;
  fx.tyre_massless = true;
  fx.caster_tyre_ratio = 1.0;
  fx.dahl_force_n = 30.0;
  fx.friction_law = TruthEffects::FrictionLaw::kSmoothCoulomb;
  EXPECT_THROW(MotionDifference(fx), std::invalid_argument);
  // The draw never pairs them: beside friction the tyres are unsprung masses.
  std::mt19937_64 rng(2);
  const TruthChair chair = RandomTruthChair(rng);
  for (std::uint64_t seed = 1000; seed < 1040; ++seed)
    EXPECT_FALSE(DrawLaws(seed, {"tyre_compliance", "suspension_friction"}, chair).effects.tyre_massless) << seed;
}

}  // namespace
}  // namespace pwsim::truth
