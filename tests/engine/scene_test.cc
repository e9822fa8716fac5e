#include "engine/scene.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "engine/input_error.h"

namespace pwsim {
namespace {

const char* kValidScene = R"(format: pwsim-scene/1
name: inline_test
clock: {rate_hz: 500}
terrain:
  profile_m: [[0.0, 0.0], [1.8, 0.0], [2.1, 0.065], [3.6, 0.065], [3.9, 0.0], [12.0, 0.0]]
chair:
  name: pw6
  mass_kg: 53
  inertia_kgm2: 9.9
  cm_height_m: 0.43
  wheels:
    - {name: front_caster, x_m: 0.38, radius_m: 0.10}
    - {name: drive, x_m: 0.0, radius_m: 0.17}
    - {name: rear_caster, x_m: -0.38, radius_m: 0.10}
  gm: {alpha: [0.17, 0.66, 0.17], beta: {"1-2": 0.5, "1-3": 0.0, "2-3": 0.6}}
  lm: {k_z: 4.18e4, c_z: 2.24e3, k_theta: 1.04e4, c_theta: 560}
load_kg: 50
drive:
  speed_mps: 2.4
  accel_mps2: 1.0
  stop_x_m: 9.0
mca: {anything: here}
)";

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Tests that the shipped default scene loads and describes the paper's trial.
TEST(SceneTest, DefaultSceneLoads) {
  const Scene scene = LoadScene(DefaultScenePath(PWSIM_SOURCE_DIR));
  EXPECT_EQ(scene.name, "speed_cushion");
  EXPECT_EQ(scene.chair.wheel_count(), 3);
  EXPECT_EQ(scene.load_kg, 100.0);
  EXPECT_NEAR(scene.terrain.MaxHeight(), 0.065, 1e-12);
  EXPECT_EQ(scene.clock.rate_hz, 1000);
  // The front caster meets the cushion (x = 1.80 m) while cruising at the programmed speed.
  const double x_meet = 1.80 - scene.chair.wheels[0].x;
  const double x_cruise = scene.drive.start_x +
                          scene.drive.speed * scene.drive.speed / (2 * scene.drive.accel);
  EXPECT_LT(x_cruise, x_meet);
}

// Tests inline chair/terrain, defaults and that owned-elsewhere sections are kept raw.
TEST(SceneTest, InlineSceneParses) {
  const Scene scene = ParseScene(kValidScene, "inline.yaml");
  EXPECT_EQ(scene.clock.rate_hz, 500);
  EXPECT_EQ(scene.drive.decel, 1.0);  // defaults to accel
  ASSERT_NE(scene.section("mca"), nullptr);
  EXPECT_EQ(scene.section("render"), nullptr);
  EXPECT_GT(scene.tick_count(), 500 * 4);
}

struct BadCase {
  const char* name;
  std::string text;
  int line;                  // expected line (0 = do not check)
  const char* field;         // expected field path
  const char* expected_part; // a fragment of the "expected ..." text
};

class SceneBadInputTest : public ::testing::TestWithParam<BadCase> {};

// Tests that each kind of bad scene input fails with file, line, field and expectation.
TEST_P(SceneBadInputTest, NamesFileLineFieldAndExpectation) {
  const BadCase& c = GetParam();
  try {
    ParseScene(c.text, "bad.yaml");
    FAIL() << c.name << ": no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(error.file(), "bad.yaml") << message;
    if (c.line > 0) {
      EXPECT_EQ(error.line(), c.line) << message;
    }
    EXPECT_EQ(error.field(), c.field) << message;
    EXPECT_NE(message.find(c.expected_part), std::string::npos) << message;
    EXPECT_EQ(message.rfind("bad.yaml", 0), 0u) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, SceneBadInputTest,
    ::testing::Values(
        BadCase{"syntax", Replace(kValidScene, "load_kg: 50", "load_kg: [50"), 0, "(syntax)",
                "valid YAML"},
        BadCase{"unknown_key", Replace(kValidScene, "load_kg: 50", "load_kg: 50\nloda_kg: 5"), 18,
                "loda_kg", "a known key"},
        BadCase{"wrong_type", Replace(kValidScene, "speed_mps: 2.4", "speed_mps: fast"), 19,
                "drive.speed_mps", "a number in (0, 4] m/s"},
        BadCase{"missing_field", Replace(kValidScene, "load_kg: 50\n", ""), 0, "load_kg",
                "this required field"},
        BadCase{"out_of_range", Replace(kValidScene, "load_kg: 50", "load_kg: 500"), 17, "load_kg",
                "[0, 300] kg"},
        BadCase{"wrong_format", Replace(kValidScene, "pwsim-scene/1", "pwsim-scene/9"), 1,
                "format", "pwsim-scene/1"},
        BadCase{"terrain_not_increasing", Replace(kValidScene, "[2.1, 0.065]", "[1.7, 0.065]"), 0,
                "terrain.profile_m[2][0]", "strictly increasing"},
        BadCase{"missing_chair_file",
                Replace(Replace(kValidScene, "chair:\n  name: pw6", "chair: nowhere.yaml\nxchair:\n  name: pw6"),
                        "", ""),
                0, "chair", "existing file"},
        BadCase{"wheels_out_of_order", Replace(kValidScene, "x_m: -0.38", "x_m: 0.5"), 0,
                "chair.wheels[2].x_m", "front to rear"},
        BadCase{"beta_bad_pair", Replace(kValidScene, "\"1-3\": 0.0", "\"1-4\": 0.0"), 0,
                "chair.gm.beta.1-4", "a known key"},
        BadCase{"drive_too_short", Replace(kValidScene, "stop_x_m: 9.0", "stop_x_m: 3.0"), 0,
                "drive.stop_x_m", "reach its speed and stop"},
        BadCase{"chair_without_lm",
                Replace(kValidScene, "  lm: {k_z: 4.18e4, c_z: 2.24e3, k_theta: 1.04e4, c_theta: 560}\n", ""),
                0, "chair", "identified gm and lm"},
        BadCase{"nested_typo", Replace(kValidScene, "accel_mps2: 1.0", "accel_mps2: 1.0\n  acel: 2"),
                0, "drive.acel", "a known key"},
        BadCase{"alpha_count", Replace(kValidScene, "[0.17, 0.66, 0.17]", "[0.17, 0.66]"), 0,
                "chair.gm.alpha", "3..3 numbers"},
        BadCase{"clock_not_integer", Replace(kValidScene, "rate_hz: 500", "rate_hz: 500.5"), 3,
                "clock.rate_hz", "an integer"},
        BadCase{"not_a_mapping", Replace(kValidScene, "drive:\n  speed_mps", "drive: 3\nxdrive:\n  speed_mps"),
                0, "drive", "a mapping"}),
    [](const auto& test_info) { return std::string(test_info.param.name); });

// Tests that a scene referencing missing files names the resolved path.
TEST(SceneTest, MissingSceneFile) {
  try {
    LoadScene("/nonexistent/scene.yaml");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), "/nonexistent/scene.yaml");
    EXPECT_NE(std::string(error.what()).find("no such file"), std::string::npos);
  }
}

}  // namespace
}  // namespace pwsim
