#include "mca/config.h"

#include <gtest/gtest.h>

#include <fstream>

#include "engine/input_error.h"

namespace pwsim::mca {
namespace {

const std::filesystem::path kSource(PWSIM_SOURCE_DIR);
/// A chair scene up to its mca/platform sections, for a file next to scenes/.
const std::string kSceneHead =
    "format: pwsim-scene/1\nname: t\nterrain: ../assets/terrains/speed_cushion.yaml\n"
    "chair: ../assets/chairs/table1_pw6.yaml\nload_kg: 100\n"
    "drive: {speed_mps: 1.2, accel_mps2: 0.8, stop_x_m: 7.0}\n";

// Tests that a scene without mca/platform sections gets the documented defaults, and that the
// repository's speed-cushion scene loads.
TEST(ConfigTest, DefaultsAndRepositoryScene) {
  const Scene scene = LoadScene(kSource / "scenes/speed_cushion.yaml");
  const McaConfig config = LoadMcaConfig(scene);
  EXPECT_EQ(config.platform.name, "pw4dof");
  EXPECT_TRUE(config.washout.Validate().empty());
}

// Tests a platform path relative to the scene, inline mca values, and strict errors.
TEST(ConfigTest, SectionsFromScene) {
  const std::string base = kSceneHead;
  const std::filesystem::path label = kSource / "scenes/inline.yaml";
  const Scene scene = ParseScene(base +
                                     "platform: platforms/car2dof.yaml\n"
                                     "mca:\n  surge: {scale: 0.6}\n  vestibular: {thresholds: {pitch_degps: 3}}\n",
                                 label);
  const McaConfig config = LoadMcaConfig(scene);
  EXPECT_EQ(config.platform.name, "car2dof");
  EXPECT_DOUBLE_EQ(config.washout.translation(Dof::kSurge).scale, 0.6);
  EXPECT_NEAR(config.vestibular.thresholds.w[1], 3.0 * kDegToRad, 1e-15);

  const Scene typo = ParseScene(base + "mca:\n  surge: {scael: 0.6}\n", label);
  try {
    LoadMcaConfig(typo);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("scael"), std::string::npos) << error.what();
    EXPECT_EQ(error.line(), 8) << error.what();
  }
  const Scene missing = ParseScene(base + "platform: platforms/none.yaml\n", label);
  EXPECT_THROW(LoadMcaConfig(missing), InputError);
  const Scene inline_platform = ParseScene(
      base + "platform:\n  name: rig\n  dofs: {heave: {travel_m: 0.05, speed_mps: 0.2, accel_mps2: 2}}\n",
      label);
  EXPECT_EQ(LoadMcaConfig(inline_platform).platform.name, "rig");
}


// Tests that a platform (inline or file) may name its algorithm and MPC settings, and that the
// scene's mca: overrides them key by key.
TEST(ConfigTest, AlgorithmFromPlatform) {
  const std::string base = kSceneHead;
  const std::filesystem::path label = kSource / "scenes/inline.yaml";
  const std::string platform =
      "platform:\n  name: rig\n  algorithm: mpc\n  mpc: {horizon_s: 1.5, block_s: 0.1}\n"
      "  dofs: {pitch: {travel_deg: 15, speed_degps: 40, accel_degps2: 300}}\n";
  const McaConfig from_platform = LoadMcaConfig(ParseScene(base + platform, label));
  EXPECT_EQ(from_platform.algorithm, McaAlgorithm::kMpc);
  EXPECT_DOUBLE_EQ(from_platform.mpc.horizon, 1.5);
  EXPECT_EQ(from_platform.platform.name, "rig");

  // the scene's mca: wins: its algorithm, and its mpc fields over the platform's
  const McaConfig washout = LoadMcaConfig(ParseScene(base + platform + "mca: {algorithm: washout}\n", label));
  EXPECT_EQ(washout.algorithm, McaAlgorithm::kWashout);
  const McaConfig merged =
      LoadMcaConfig(ParseScene(base + platform + "mca: {mpc: {control_period_s: 0.02}}\n", label));
  EXPECT_EQ(merged.algorithm, McaAlgorithm::kMpc);
  EXPECT_DOUBLE_EQ(merged.mpc.horizon, 1.5);
  EXPECT_DOUBLE_EQ(merged.mpc.control_period, 0.02);

  // a platform file with algorithm: written next to a scene that names it
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "pwsim_config_algorithm";
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "rig.yaml");
    out << "format: pwsim-platform/1\nname: filerig\nalgorithm: mpc\nmpc: {horizon_s: 2.0}\n"
           "dofs: {pitch: {travel_deg: 15, speed_degps: 40, accel_degps2: 300}}\n";
  }
  const McaConfig from_file = LoadMcaConfig(ParseScene(
      "format: pwsim-scene/1\nname: t\nterrain: " + (kSource / "assets/terrains/speed_cushion.yaml").string() +
          "\nchair: " + (kSource / "assets/chairs/table1_pw6.yaml").string() +
          "\nload_kg: 100\ndrive: {speed_mps: 1.2, accel_mps2: 0.8, stop_x_m: 7.0}\nplatform: rig.yaml\n",
      dir / "scene.yaml"));
  EXPECT_EQ(from_file.platform.name, "filerig");
  EXPECT_EQ(from_file.algorithm, McaAlgorithm::kMpc);
  EXPECT_DOUBLE_EQ(from_file.mpc.horizon, 2.0);

  // a wrong algorithm in the platform names the platform's key
  try {
    LoadMcaConfig(ParseScene(base + "platform:\n  name: rig\n  algorithm: lqr\n"
                                    "  dofs: {pitch: {travel_deg: 15, speed_degps: 40, accel_degps2: 300}}\n",
                             label));
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("algorithm"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("lqr"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace pwsim::mca
