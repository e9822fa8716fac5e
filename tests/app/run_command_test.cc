// End-to-end tests of `pwsim run` through the built binary (build/pwsim).

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Result {
  int status{0};
  std::string output;
};

Result Pwsim(const std::string& args) {
  const fs::path log = fs::temp_directory_path() / ("pwsim_cli_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                                                    ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".log");
  const std::string command = std::string("cd ") + PWSIM_SOURCE_DIR + " && " + PWSIM_BINARY_DIR +
                              "/pwsim " + args + " > " + log.string() + " 2>&1";
  const int raw = std::system(command.c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  return {WEXITSTATUS(raw), text.str()};
}

std::string ReadFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

fs::path Scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("pwsim_run_test_" + name);
  fs::remove_all(dir);
  return dir;
}

// Tests that the default run writes trial.csv with the foundation's columns and a summary.
TEST(RunCommandTest, DefaultSceneWritesTrialAndSummary) {
  const fs::path out = Scratch("default");
  const Result result = Pwsim("run --no-video --out " + out.string());
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("trial.csv"), std::string::npos);
  const std::string csv = ReadFile(out / "trial.csv");
  const std::string header = csv.substr(0, csv.find('\n'));
  for (const char* column : {"t_s", "x_m", "z_o1_m", "z_o2_m", "z_o3_m", "z_gm_m", "pitch_gm_rad",
                             "z_m", "pitch_rad", "z_rate_mps", "pitch_rate_radps"}) {
    EXPECT_NE(header.find(column), std::string::npos) << column << " in " << header;
  }
  const std::string summary = ReadFile(out / "summary.json");
  EXPECT_NE(summary.find("\"peak_heave\""), std::string::npos);
  EXPECT_NE(summary.find("speed_cushion"), std::string::npos);
  EXPECT_FALSE(fs::exists(out / "trial.csv.partial"));
}

// Tests that the same scene gives a bit-identical trial.csv twice.
TEST(RunCommandTest, BitIdenticalRepeat) {
  const fs::path a = Scratch("repeat_a");
  const fs::path b = Scratch("repeat_b");
  ASSERT_EQ(Pwsim("run --no-video --out " + a.string()).status, 0);
  ASSERT_EQ(Pwsim("run --no-video --out " + b.string()).status, 0);
  const std::string first = ReadFile(a / "trial.csv");
  EXPECT_GT(first.size(), 100000u);
  EXPECT_EQ(first, ReadFile(b / "trial.csv"));
}

// Tests that --help lists every option with unit and default, for the tool and for run.
TEST(RunCommandTest, HelpListsOptionsWithUnitsAndDefaults) {
  const Result top = Pwsim("--help");
  EXPECT_EQ(top.status, 0);
  EXPECT_NE(top.output.find("run"), std::string::npos);
  const Result run = Pwsim("run --help");
  EXPECT_EQ(run.status, 0);
  EXPECT_NE(run.output.find("--out DIR"), std::string::npos);
  EXPECT_NE(run.output.find("default: out/run"), std::string::npos);
  EXPECT_NE(run.output.find("unit:"), std::string::npos);
}

// Tests that a bad scene fails with a non-zero status, names the problem, and writes nothing.
TEST(RunCommandTest, BadSceneFailsCleanly) {
  const fs::path dir = Scratch("bad_scene");
  fs::create_directories(dir);
  std::ofstream(dir / "bad.yaml") << "format: pwsim-scene/1\nname: x\nterrain: nope.yaml\n";
  const fs::path out = dir / "out";
  const Result result = Pwsim("run " + (dir / "bad.yaml").string() + " --out " + out.string());
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find("bad.yaml:3: field 'terrain'"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(out / "trial.csv"));
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

// Tests that unknown options are usage errors.
TEST(RunCommandTest, UnknownOptionIsUsageError) {
  const Result result = Pwsim("run --speed 3");
  EXPECT_EQ(result.status, 2);
  EXPECT_NE(result.output.find("unknown option --speed"), std::string::npos);
}


// A car scene (kind: car) through the CLI: the car's columns and the rail + yaw platform.
TEST(RunCommandTest, CarSceneWritesTheCarOutputs) {
  const fs::path out = Scratch("car_launch");
  const Result result = Pwsim("run scenes/car_launch.yaml --no-video --decimate 20 --out " + out.string());
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("car scene 'car_launch'"), std::string::npos) << result.output;
  const std::string csv = ReadFile(out / "trial.csv");
  const std::string header = csv.substr(0, csv.find('\n'));
  for (const char* column : {"t_s", "x_m", "y_m", "yaw_rad", "v_mps", "yaw_rate_radps", "ax_mps2", "ay_mps2",
                             "engine_rpm", "gear", "throttle", "brake", "clutch", "steer_rad", "plat_surge_m",
                             "plat_yaw_rad"}) {
    EXPECT_NE(header.find(column), std::string::npos) << column << " in " << header;
  }
  const std::string summary = ReadFile(out / "summary.json");
  EXPECT_NE(summary.find("\"within_limits\": true"), std::string::npos);
  EXPECT_NE(summary.find("\"rail_yaw_false_cue\""), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "mca.png"));
}

// Tests that every number from the command line is range-checked, with the option's name,
// its range and unit in the message, as a usage error (status 2), before anything starts.
TEST(RunCommandTest, OutOfRangeOrNonFiniteNumbersAreUsageErrorsNamingTheOption) {
  struct Case {
    const char* args;
    const char* expected;
  };
  const Case cases[] = {
      {"hmd-peer --head-yaw-deg 200", "option --head-yaw-deg: expected 0..90 deg, got 200"},
      {"platform-sim --fault-at -1", "option --fault-at: expected 0..86400 s, got -1"},
      {"platform-sim --cycle-ms inf", "option --cycle-ms: expected a number, got \"inf\""},
      {"session --rt-priority 120", "option --rt-priority: expected an integer in 0..99, got 120"},
  };
  for (const Case& c : cases) {
    const Result result = Pwsim(c.args);
    EXPECT_EQ(result.status, 2) << c.args << "\n" << result.output;
    EXPECT_NE(result.output.find(c.expected), std::string::npos) << c.args << "\n" << result.output;
  }
}

}  // namespace
