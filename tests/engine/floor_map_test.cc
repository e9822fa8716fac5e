#include "engine/floor_map.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/input_error.h"

namespace pwsim {
namespace {

FloorMap Parse(const std::string& text) {
  const YamlDocument doc = LoadYamlString(text, "floor.yaml");
  YamlMap map(doc.root, doc.file, "floor");
  FloorMap floor = ParseFloorMap(map);
  map.Finish();
  return floor;
}

// Tests that a floor of the sagittal terrain alone returns its heights bit for bit at any y.
TEST(FloorMapTest, ProfileAloneIsTheTerrainBitForBit) {
  const Terrain cushion = MakeSpeedCushion();
  const FloorMap floor = FloorFromTerrain(cushion);
  for (double x = -1.0; x < 13.0; x += 0.0137) {
    ASSERT_EQ(floor.HeightAt(x, 0.3 * x - 1.0), cushion.HeightAt(x));
  }
}

// Tests that the hinted lookup of a wheel (HeightAtNear: the profile's segment, the interval
// clear of every feature and the grid, and the level interval, with or without one feature on
// it, carried from call to call)
// returns HeightAt's bits on a path that enters and leaves level and sloped profile segments,
// sharp and tapered features (one on another), the grid and the profile's ends, and jumps back
// and forth (the hint then misses and is rebuilt).
TEST(FloorMapTest, HintedLookupIsHeightAtBitForBit) {
  FloorMap floor = Parse(
      "profile_m: [[0, 0], [1.8, 0], [2.1, 0.065], [3.6, 0.065], [3.9, 0], [12, 0]]\n"
      "features:\n"
      "  - {bump: {name: step, x_m: [2, 6], y_m: [0, 1], height_m: 0.05}}\n"
      "  - {bump: {name: kerb, x_m: [7, 7.5], y_m: [-1, 0.2], height_m: -0.03, ramp_m: 0.1}}\n"
      "  - {plane: {name: cross, x_m: [10, 20], y_m: [-2, 2], grade_y: 0.05, ramp_m: 0.5}}\n"
      "  - {bump: {name: patch on the plane, x_m: [12, 13], y_m: [-1.1, 1.1], height_m: 0.02, ramp_m: 0.05}}\n"
      "grid: {origin_m: [8, -1], cell_m: 0.5, rows: [[0, 0.01, 0.02], [0.01, 0.03, -0.01], [0, 0, 0.02]]}\n");
  floor.profile.z[0] = -0.0;  // a -0 start: the clear interval's z + 0 must turn it into +0 as HeightAt does
  FloorHint hint;
  int clear_hits = 0;
  int level_feature_hits = 0;  // on a level piece of the profile with one feature active
  for (int k = 0; k < 40000; ++k) {
    const double x = -1.0 + 25.0 * (0.5 - 0.5 * std::cos(k * 1.7e-4)) + (k % 997 == 0 ? 3.0 : 0.0);
    const double y = 1.2 * std::sin(k * 3.1e-4);
    const bool clear = x > hint.clear_lo && x < hint.clear_hi;
    level_feature_hits += x > hint.level_lo && x < hint.level_hi && hint.level_feature >= 0;
    const double z = floor.HeightAtNear(x, y, hint);
    ASSERT_EQ(std::signbit(z), std::signbit(floor.HeightAt(x, y))) << x << " " << y;
    ASSERT_EQ(z, floor.HeightAt(x, y)) << x << " " << y;
    clear_hits += clear;
  }
  EXPECT_GT(clear_hits, 10000);  // the clear interval was really used
  EXPECT_GT(level_feature_hits, 5000);  // and the level interval under the plane and the kerb
  for (double x = 7.6; x < 9.9; x += 0.01) {  // into and out of the grid between two features
    ASSERT_EQ(floor.HeightAtNear(x, -0.5, hint), floor.HeightAt(x, -0.5)) << x;
  }
  for (const double x : {1.0, 0.0, 2.0, 6.0, 7.0, 7.5, 10.0, 20.0, 8.0, 9.0, 12.0, 0.0}) {  // span ends
    const double z = floor.HeightAtNear(x, 0.5, hint);
    EXPECT_EQ(std::signbit(z), std::signbit(floor.HeightAt(x, 0.5))) << x;
    EXPECT_EQ(z, floor.HeightAt(x, 0.5)) << x;
  }
}

// Tests bumps and planes against their closed forms: a bump is h inside its tapered edges and
// h·u/ramp on them; a plane is g_x (x - x_c) + g_y (y - y_c); both 0 outside.
TEST(FloorMapTest, FeaturesFollowTheirClosedForms) {
  const FloorMap floor = Parse(
      "features:\n"
      "  - {bump: {name: kerb, x_m: [2, 6], y_m: [0, 1], height_m: 0.05, ramp_m: 0.02}}\n"
      "  - {plane: {name: cross, x_m: [10, 20], y_m: [-2, 2], grade_y: 0.05}}\n");
  EXPECT_DOUBLE_EQ(floor.HeightAt(3.0, 0.5), 0.05);
  EXPECT_NEAR(floor.HeightAt(2.01, 0.5), 0.05 * 0.01 / 0.02, 1e-15);
  EXPECT_DOUBLE_EQ(floor.HeightAt(3.0, -0.5), 0.0);
  EXPECT_DOUBLE_EQ(floor.HeightAt(12.0, 1.5), 0.05 * 1.5);
  EXPECT_DOUBLE_EQ(floor.HeightAt(12.0, -1.5), -0.05 * 1.5);
  EXPECT_DOUBLE_EQ(floor.HeightAt(21.0, 1.5), 0.0);
}

// Tests the grid's bilinear interpolation against the closed form of a bilinear surface
// z = a + b x + c y + d x y (which bilinear interpolation reproduces exactly).
TEST(FloorMapTest, GridIsBilinear) {
  const auto surface = [](double x, double y) { return 0.01 + 0.02 * x - 0.01 * y + 0.005 * x * y; };
  std::string rows = "grid: {origin_m: [1, -1], cell_m: 0.5, rows: [";
  for (int j = 0; j < 4; ++j) {
    rows += j ? ", [" : "[";
    for (int i = 0; i < 5; ++i) rows += (i ? ", " : "") + std::to_string(surface(1.0 + 0.5 * i, -1.0 + 0.5 * j));
    rows += "]";
  }
  rows += "]}\n";
  const FloorMap floor = Parse(rows);
  for (double x = 1.0; x <= 3.0; x += 0.13) {
    for (double y = -1.0; y <= 0.5; y += 0.11) ASSERT_NEAR(floor.HeightAt(x, y), surface(x, y), 1e-6) << x << " " << y;
  }
  EXPECT_EQ(floor.HeightAt(0.9, 0.0), 0.0);
}

void ExpectError(const std::string& text, const std::string& field, int line) {
  try {
    Parse(text);
    FAIL() << "accepted: " << text;
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), field) << error.what();
    EXPECT_EQ(error.line(), line) << error.what();
  }
}

// Tests that holes and NaN in a height map name the file, the line, the cell and what was expected.
TEST(FloorMapTest, HolesAndNanAreErrorsNamingTheCell) {
  ExpectError("grid:\n  origin_m: [0, 0]\n  cell_m: 0.5\n  rows:\n    - [0, 0, 0]\n    - [0, .nan, 0]\n",
              "floor.grid.rows[1][1]", 6);
  ExpectError("grid:\n  origin_m: [0, 0]\n  cell_m: 0.5\n  rows:\n    - [0, 0, 0]\n    - [0, ~, 0]\n",
              "floor.grid.rows[1][1]", 6);
  ExpectError("grid:\n  origin_m: [0, 0]\n  cell_m: 0.5\n  rows:\n    - [0, 0, 0]\n    - [0, 0]\n",
              "floor.grid.rows[1]", 6);
  ExpectError("features:\n  - {bump: {x_m: [2, 1], y_m: [0, 1], height_m: 0.1}}\n", "floor.features[0].bump.x_m", 2);
}

// Tests friction patches: read with their rectangle and μ, the lowest μ where they overlap and
// the wheel's own outside them; μ <= 0 and a reversed interval are errors naming the field.
TEST(FloorMapTest, FrictionPatchesLowerTheGrip) {
  const FloorMap floor = Parse(
      "patches:\n  - {name: wet, x_m: [1, 3], y_m: [-1, 1], friction: 0.3}\n"
      "  - {name: ice, x_m: [2, 4], y_m: [0, 2], friction: 0.05}\n");
  ASSERT_EQ(floor.patches.size(), 2u);
  EXPECT_EQ(floor.patches[0].name, "wet");
  EXPECT_EQ(floor.FrictionAt(0.5, 0.0, 0.8), 0.8);
  EXPECT_EQ(floor.FrictionAt(1.5, 0.0, 0.8), 0.3);
  EXPECT_EQ(floor.FrictionAt(2.5, 0.5, 0.8), 0.05);
  EXPECT_EQ(floor.FrictionAt(1.5, 0.0, 0.2), 0.2);
  ExpectError("patches:\n  - {x_m: [1, 3], y_m: [-1, 1], friction: 0}\n", "floor.patches[0].friction", 2);
  ExpectError("patches:\n  - {x_m: [3, 1], y_m: [-1, 1], friction: 0.3}\n", "floor.patches[0].x_m", 2);
}

}  // namespace
}  // namespace pwsim
