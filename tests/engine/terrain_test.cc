#include "engine/terrain.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>

#include "engine/input_error.h"
#include "tests/run_command.h"

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
  const pwsim::testing::TempDir dir("terrain_roundtrip");  // its own, removed after
  const auto file = dir / "terrain.yaml";
  WriteTerrainFile(original, file);
  const Terrain read = ReadTerrainFile(file);
  EXPECT_EQ(read.x, original.x);
  EXPECT_EQ(read.z, original.z);
}

}  // namespace
}  // namespace pwsim

namespace pwsim {
namespace {

// Tests that the hinted lookup of the per-tick paths (ChairSimulator, the full chair) returns
// HeightAt's bits exactly, for queries that creep forward, jump, go back, sit on breakpoints and
// leave the profile at both ends.
TEST(TerrainTest, HintedLookupIsHeightAtBitForBit) {
  const Terrain cushion = MakeSpeedCushion();
  std::size_t hint = 0;
  double x = -0.5;
  std::uint64_t state = 12345;
  for (int k = 0; k < 200000; ++k) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;  // a local LCG: determinism
    const double u = static_cast<double>(state >> 11) / 9007199254740992.0;
    x = k % 1000 == 0 ? -1.0 + 14.0 * u : x + 0.002 * (u - 0.1);
    const double query = k % 777 == 0 ? cushion.x[static_cast<std::size_t>(k) % cushion.x.size()] : x;
    ASSERT_EQ(cushion.HeightAtNear(query, hint), cushion.HeightAt(query)) << query;
  }
}

}  // namespace
}  // namespace pwsim
