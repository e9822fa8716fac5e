// End-to-end checks of the MCA's command-line surface: `pwsim run` columns and summary,
// `pwsim omct` files, `pwsim mca-validate` on a generated trial. Runs the built binary.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/run_command.h"

namespace {

const std::filesystem::path kBinary = std::filesystem::path(PWSIM_BINARY_DIR) / "pwsim";
const std::filesystem::path kSource(PWSIM_SOURCE_DIR);

std::filesystem::path FreshDir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(PWSIM_BINARY_DIR) / "test-out" / name;
  std::filesystem::remove_all(dir);
  return dir;
}

int RunPwsim(const std::string& args) {
  const std::string command = "cd '" + kSource.string() + "' && '" + kBinary.string() + "' " + args + " > /dev/null";
  return std::system(command.c_str());
}

std::string FirstLine(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

// Tests that `pwsim run` writes every contract column, the summary's "mca" object and mca.png.
TEST(McaCliTest, RunAddsMotionCueing) {
  const std::filesystem::path out = FreshDir("mca_run");
  ASSERT_EQ(RunPwsim("run --no-video --decimate 10 --out '" + out.string() + "'"), 0);
  const std::string header = "," + FirstLine(out / "trial.csv") + ",";
  for (const char* column :
       {"head_fs_x_mps2", "head_fs_z_mps2", "head_w_y_radps", "plat_heave_m", "plat_pitch_rad",
        "plat_roll_rad", "plat_yaw_rad", "vis_x_m", "vis_z_m", "vis_pitch_rad", "vis_tilt_pitch_rad",
        "vis_tilt_roll_rad", "vest_true_oto_x_mps2", "vest_plat_oto_z_mps2", "vest_true_scc_y_radps",
        "vest_plat_scc_y_radps", "head_plat_fs_x_mps2", "mca_fault"}) {
    EXPECT_NE(header.find(std::string(",") + column + ","), std::string::npos) << column;
  }
  std::ifstream in(out / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_TRUE(summary.contains("mca"));
  EXPECT_EQ(summary["mca"]["platform"]["name"], "pw4dof");
  EXPECT_GT(summary["mca"]["consistency"]["canals"]["y"]["correlation"].get<double>(), 0.8);
  EXPECT_EQ(summary["mca"]["false_cues"]["tilt_rate_count"].get<int>(), 0);
  EXPECT_TRUE(std::filesystem::exists(out / "mca.png"));
}

// Tests the OMCT files for the car platform: 2 applicable tests × 12 frequencies.
TEST(McaCliTest, OmctWritesCsvAndPlot) {
  const std::filesystem::path out = FreshDir("mca_omct");
  ASSERT_EQ(RunPwsim("omct --platform scenes/platforms/car2dof.yaml --rate-hz 250 --out '" + out.string() + "'"), 0);
  std::ifstream in(out / "omct.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "test,frequency,gain,phase");
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 24);
  EXPECT_TRUE(std::filesystem::exists(out / "omct.png"));
  const pwsim::testing::TempDir dir("mca_cli_omct_no_platform");
  EXPECT_TRUE(pwsim::testing::Refused(
      pwsim::testing::RunCommand("cd '" + kSource.string() + "' && '" + kBinary.string() +
                                     "' omct --platform scenes/platforms/none.yaml --out " + dir.Quoted("out"),
                                 dir),
      1, {"scenes/platforms/none.yaml", "expected a readable YAML file", "no such file"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "omct.csv"));
}

// Tests the paper's validation on a generated trial: cross-correlations above 0.98.
TEST(McaCliTest, ValidationOnGeneratedTrial) {
  const std::filesystem::path out = FreshDir("mca_validate");
  ASSERT_EQ(RunPwsim("mca-validate --out '" + out.string() + "'"), 0);
  std::ifstream in(out / "mca_validation.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_TRUE(report["pass"].get<bool>());
  EXPECT_GT(report["trials"][0]["heave_xcorr"].get<double>(), 0.98);
  EXPECT_GT(report["trials"][0]["pitch_xcorr"].get<double>(), 0.98);
}

// Tests the refusal check the CLI tests use (tests/run_command.h): a crash that printed the right
// words, a refusal of something else and a different exit code all fail it.
TEST(RefusalCheck, TellsARefusalFromACrashOrAnotherError) {
  const pwsim::testing::TempDir dir("refusal_check");
  const auto refusal = pwsim::testing::RunCommand("echo 'option --mca: expected washout' >&2; exit 2", dir);
  EXPECT_TRUE(pwsim::testing::Refused(refusal, 2, {"option --mca"}));
  const auto crash = pwsim::testing::RunCommand("echo 'option --mca'; kill -SEGV $$", dir);
  EXPECT_EQ(crash.signal, 11);
  EXPECT_FALSE(pwsim::testing::Refused(crash, 2, {"option --mca"}));
  EXPECT_FALSE(pwsim::testing::Refused(pwsim::testing::RunCommand("echo 'option --out'; exit 2", dir), 2, {"option --mca"}));
  EXPECT_FALSE(pwsim::testing::Refused(pwsim::testing::RunCommand("echo 'option --mca'; exit 1", dir), 2, {"option --mca"}));
  EXPECT_TRUE(std::filesystem::is_directory(dir.path()));
  const std::filesystem::path kept = dir.path();
  { const pwsim::testing::TempDir other("refusal_check"); EXPECT_NE(other.path(), kept); }
}

}  // namespace
