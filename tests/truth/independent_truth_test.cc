// The independent truth against closed forms: at rest with one wheel on a plateau the chair
// settles where the suspension forces balance, z = Σk h / Σk, sin θ = Σ k x h / Σ k x²
// (Σ k x = 0); the mocap lever arm maps the true pose as the rigid-body formula says; effects
// change the motion.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/truth/independent_truth.h"

namespace pwsim::truth {
namespace {

TruthTrialConfig StopOnPlateau(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  TruthTrialConfig c;
  c.chair = RandomTruthChair(rng);
  c.terrain.x_m = {0.0, 2.0, 2.0001, 20.0};
  c.terrain.z_m = {0.0, 0.0, 0.04, 0.04};
  c.drive.speed_mps = 0.3;
  c.drive.accel_mps2 = 0.5;
  c.drive.still_s = 4.0;  // settle after stopping
  // Front wheel stops 0.1 m past the step; the others stay on the floor.
  const double stop_dist = 0.5 * c.drive.speed_mps * (c.drive.speed_mps / c.drive.accel_mps2 + c.drive.jerk_time_s);
  c.drive.cruise_until_m = 2.1 - c.chair.wheels.front().x_m - stop_dist;
  c.noise_x_m = c.noise_z_m = c.noise_pitch_rad = 0.0;
  c.z_offset_m = 0.0;
  return c;
}

TEST(IndependentTruth, SettlesAtTheStaticBalanceOfTheSuspension) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const TruthTrialConfig c = StopOnPlateau(seed);
    const TruthTrial t = SimulateTruthTrial(c);
    double ks = 0, kh = 0, kxh = 0, kxx = 0;
    for (const TruthWheel& w : c.chair.wheels) {
      const double h = c.terrain.HeightAt(t.true_x.back() + w.x_m);
      ks += w.k_npm;
      kh += w.k_npm * h;
      kxh += w.k_npm * w.x_m * h;
      kxx += w.k_npm * w.x_m * w.x_m;
    }
    ASSERT_GT(kxh, 0.0);  // the front wheel is up
    EXPECT_NEAR(t.true_z.back(), kh / ks, 2e-5) << seed;
    EXPECT_NEAR(std::sin(t.true_pitch.back()), kxh / kxx, 5e-5) << seed;
  }
}

TEST(IndependentTruth, MarkerLeverArmTurnsWithTheChair) {
  TruthTrialConfig c = StopOnPlateau(4);
  c.effects.marker_x_m = 0.2;
  c.effects.marker_z_m = 0.5;
  const TruthTrial t = SimulateTruthTrial(c);
  const std::size_t k = t.t.size() - 1;
  const double th = t.true_pitch[k];
  EXPECT_GT(std::abs(th), 0.01);
  EXPECT_NEAR(t.x[k], t.true_x[k] + 0.2 * std::cos(th) - 0.5 * std::sin(th), 1e-12);
  EXPECT_NEAR(t.z[k], t.true_z[k] + 0.2 * std::sin(th) + 0.5 * std::cos(th), 1e-12);
}

TEST(IndependentTruth, EveryEffectChangesTheMotion) {
  TruthSetConfig base;
  base.speeds = {1.2};
  base.loads = {80.0};
  const TruthSet plain = SimulateTruthSet(base);
  for (const std::string& name : TruthEffectNames()) {
    TruthSetConfig c = base;
    c.effects = {name};
    const TruthSet set = SimulateTruthSet(c);
    double diff = 0.0;
    const TruthTrial& a = plain.trials[0];
    const TruthTrial& b = set.trials[0];
    for (std::size_t k = 0; k < std::min(a.z.size(), b.z.size()); ++k)
      diff = std::max({diff, std::abs((a.z[k] - a.z[0]) - (b.z[k] - b.z[0])),
                       0.1 * std::abs(a.pitch[k] - b.pitch[k])});
    EXPECT_GT(diff, 5e-4) << name;
  }
}

}  // namespace
}  // namespace pwsim::truth
