// The marker lever's height from the measured x (sysid/diagnose/lever_from_track.h), on tracks
// written here in closed form: a chair driving at a steady speed with a slow surge, pitching
// over an obstacle, the marker at a known lever, deterministic noise.
#include "sysid/diagnose/lever_from_track.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace pwsim::diagnose {
namespace {

TEST(MinusMovingAverageTest, RemovesAConstantAndALineInside) {
  const std::vector<double> constant(20, 3.5);
  for (double v : MinusMovingAverage(constant, 5)) EXPECT_NEAR(v, 0.0, 1e-15);
  std::vector<double> line(20);
  for (std::size_t k = 0; k < line.size(); ++k) line[k] = 0.1 * static_cast<double>(k) - 2.0;
  const std::vector<double> h = MinusMovingAverage(line, 5);
  for (std::size_t k = 2; k + 2 < h.size(); ++k) EXPECT_NEAR(h[k], 0.0, 1e-12) << k;
  // At the ends the window shrinks: sample 0 less the mean of samples 0-2.
  EXPECT_NEAR(h[0], -0.1, 1e-12);
}

TEST(MinusMovingAverageTest, AnImpulseByHand) {
  // [0 0 3 0 0], window 3: each sample less the mean of itself and its neighbours (two at the ends).
  const std::vector<double> h = MinusMovingAverage({0.0, 0.0, 3.0, 0.0, 0.0}, 3);
  const std::vector<double> expected{0.0, -1.0, 2.0, -1.0, 0.0};
  for (std::size_t k = 0; k < h.size(); ++k) EXPECT_NEAR(h[k], expected[k], 1e-15) << k;
}

/// Trials of 6 s at 100 Hz: 1 s at rest, then a drive at `speed` m/s with a slow surge; the pitch
/// a decaying 2.5 Hz swing after an obstacle at 2 s (amplitude growing with the speed) plus a
/// slow nose-up while accelerating; the marker at (r_x, r_z); white noise of 0.3 mm and 0.5 mrad.
std::vector<effects::TrialRecord> Trials(double r_x, double r_z, double pitch_amplitude = 0.04) {
  std::mt19937_64 rng(17);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<effects::TrialRecord> out;
  for (double speed : {0.5, 0.9, 1.3, 1.7}) {
    effects::TrialRecord r;
    r.name = "v" + std::to_string(speed);
    for (int k = 0; k < 600; ++k) {
      const double t = 0.01 * k, moving = std::max(0.0, t - 1.0);
      const double x_o = speed * moving + 0.02 * std::sin(2.0 * std::numbers::pi * 0.2 * moving);
      const double after = std::max(0.0, t - 2.0);
      const double theta = 0.01 + pitch_amplitude * speed * std::exp(-1.5 * after) *
                                      std::sin(2.0 * std::numbers::pi * 2.5 * after) +
                           0.005 * (1.0 - std::exp(-moving));
      r.t.push_back(t);
      r.x.push_back(x_o + r_x * std::cos(theta) - r_z * std::sin(theta) + 3e-4 * gauss(rng));
      r.z.push_back(0.5);
      r.pitch.push_back(theta + 5e-4 * gauss(rng));
    }
    out.push_back(std::move(r));
  }
  return out;
}

TEST(LeverHeightFromTrackTest, RecoversTheLeverTheXCarries) {
  for (double r_z : {0.45, -0.3, 0.2}) {
    const std::optional<LeverHeight> h = LeverHeightFromTrack(Trials(0.1, r_z));
    ASSERT_TRUE(h.has_value());
    EXPECT_NEAR(h->estimate_m, r_z, 0.02 * std::abs(r_z)) << r_z;
    EXPECT_LE(h->lower_m, r_z);
    EXPECT_GE(h->upper_m, r_z);
    EXPECT_GT(h->lower_m * h->upper_m, 0.0) << "the range refutes a marker at O_V: " << h->lower_m << ", " << h->upper_m;
  }
}

TEST(LeverHeightFromTrackTest, AMarkerAtTheOriginRefutesALever) {
  const std::optional<LeverHeight> h = LeverHeightFromTrack(Trials(0.0, 0.0));
  ASSERT_TRUE(h.has_value());
  EXPECT_LE(h->lower_m, 0.0);
  EXPECT_GE(h->upper_m, 0.0);
  EXPECT_NEAR(h->estimate_m, 0.0, 0.01);
  // The slow nose-up while accelerating moves with the start of the drive: the estimate over
  // twice the window sees it (bias_m), and the range is the wider for it, but still refutes
  // the levers the model would otherwise use to mimic another effect.
  EXPECT_GT(h->bias_m, 0.01);
  EXPECT_GT(h->lower_m, -0.15);
  EXPECT_LT(h->upper_m, 0.15);
}

TEST(LeverHeightFromTrackTest, NothingWhereThePitchDoesNotSwing) {
  std::vector<effects::TrialRecord> flat = Trials(0.1, 0.4, 0.0);
  for (effects::TrialRecord& r : flat) r.pitch.assign(r.t.size(), 0.01);
  EXPECT_FALSE(LeverHeightFromTrack(flat).has_value());
  EXPECT_FALSE(LeverHeightFromTrack({Trials(0.1, 0.4).front()}).has_value()) << "one trial is no spread";
}

}  // namespace
}  // namespace pwsim::diagnose
