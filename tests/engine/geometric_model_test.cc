#include "engine/geometric_model.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace pwsim {
namespace {

// Tests eq. (1)-(2) with Table I weights against a hand computation.
TEST(GeometricModelTest, TableOneWeightsByHand) {
  const GeometricModel dut(MakeTableOneChair());
  const std::array<double, 3> z_O{0.065, 0.02, 0.0};
  const GeometricOutput out = dut.Evaluate(z_O);
  EXPECT_NEAR(out.z, 0.17 * 0.065 + 0.66 * 0.02 + 0.17 * 0.0, 1e-15);
  const double expected_pitch =
      0.5 * std::asin((0.065 - 0.02) / 0.38) + 0.6 * std::asin((0.02 - 0.0) / 0.38);
  EXPECT_NEAR(out.pitch, expected_pitch, 1e-15);
}

// Tests that a front wheel higher than the rear gives positive (nose-up) pitch.
TEST(GeometricModelTest, FrontHigherIsNoseUp) {
  const GeometricModel dut(MakeTableOneChair());
  const std::array<double, 3> z_O{0.05, 0.0, 0.0};
  EXPECT_GT(dut.Evaluate(z_O).pitch, 0.0);
}

// Tests that on flat ground at any height the pitch is zero and the altitude is Σα·h.
TEST(GeometricModelTest, LevelGround) {
  const GeometricModel dut(MakeTableOneChair());
  const std::array<double, 3> z_O{0.065, 0.065, 0.065};
  const GeometricOutput out = dut.Evaluate(z_O);
  EXPECT_NEAR(out.z, 0.065, 1e-15);
  EXPECT_EQ(out.pitch, 0.0);
}

// Tests that contact heights sample the terrain under each wheel.
TEST(GeometricModelTest, ContactHeightsFollowTerrain) {
  const GeometricModel dut(MakeTableOneChair());
  const Terrain terrain = MakeSpeedCushion();
  std::array<double, 3> z_O{};
  dut.ContactHeights(terrain, 1.72, z_O);  // front caster at 2.10 (top of the ramp)
  EXPECT_NEAR(z_O[0], 0.065, 1e-12);
  EXPECT_NEAR(z_O[1], 0.0, 1e-12);
  EXPECT_NEAR(z_O[2], 0.0, 1e-12);
}

}  // namespace
}  // namespace pwsim
