#include "mca/config.h"

#include <gtest/gtest.h>

#include "engine/input_error.h"

namespace pwsim::mca {
namespace {

const std::filesystem::path kSource(PWSIM_SOURCE_DIR);

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
  const std::string base =
      "format: pwsim-scene/1\nname: t\nterrain: ../assets/terrains/speed_cushion.yaml\n"
      "chair: ../assets/chairs/table1_pw6.yaml\nload_kg: 100\n"
      "drive: {speed_mps: 1.2, accel_mps2: 0.8, stop_x_m: 7.0}\n";
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

}  // namespace
}  // namespace pwsim::mca
