#include "engine/terrain.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "engine/input_error.h"

namespace pwsim {
namespace {

// Tests piecewise-linear interpolation and z = 0 outside the listed span.
TEST(TerrainTest, InterpolatesAndIsZeroOutside) {
  const Terrain dut{{1.0, 2.0, 3.0}, {0.5, 1.5, 0.5}};
  EXPECT_DOUBLE_EQ(dut.HeightAt(1.5), 1.0);
  EXPECT_DOUBLE_EQ(dut.HeightAt(2.0), 1.5);
  EXPECT_DOUBLE_EQ(dut.HeightAt(2.75), 0.75);
  EXPECT_EQ(dut.HeightAt(0.5), 0.0);
  EXPECT_EQ(dut.HeightAt(3.5), 0.0);
  EXPECT_DOUBLE_EQ(dut.SlopeAt(1.5), 1.0);
  EXPECT_DOUBLE_EQ(dut.SlopeAt(2.5), -1.0);
  EXPECT_EQ(dut.SlopeAt(4.0), 0.0);
}

// Tests the paper's cushion: 6.5 cm plateau, ramps of 0.30 m from x = 1.80 m.
TEST(TerrainTest, SpeedCushionShape) {
  const Terrain dut = MakeSpeedCushion();
  EXPECT_EQ(dut.HeightAt(1.79), 0.0);
  EXPECT_NEAR(dut.HeightAt(1.95), 0.0325, 1e-12);
  EXPECT_NEAR(dut.HeightAt(3.0), 0.065, 1e-12);
  EXPECT_NEAR(dut.HeightAt(3.75), 0.0325, 1e-12);
  EXPECT_DOUBLE_EQ(dut.MaxHeight(), 0.065);
}

// Tests that a written terrain file reads back identically.
TEST(TerrainTest, FileRoundTrip) {
  const Terrain original = MakeSpeedCushion(2.0, 0.05, 0.25, 1.0, 10.0);
  const auto file = std::filesystem::temp_directory_path() / "pwsim_terrain_roundtrip.yaml";
  WriteTerrainFile(original, file);
  const Terrain read = ReadTerrainFile(file);
  EXPECT_EQ(read.x, original.x);
  EXPECT_EQ(read.z, original.z);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace pwsim
