// The seed's ramp friction experiment through IDIM, and the `pwsim platform` command's
// handling of bad input (an error naming the file, no output left behind).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "sysid/platform/idim.h"
#include "tests/sysid/platform/emps_data.h"
#include "tests/sysid/platform/truth_axis.h"

namespace pwsim::sysid::platform {
namespace {

namespace fs = std::filesystem;

TEST(FrictionExperiment, RampRecordingGivesViscousAndCoulomb) {
  test::TruthAxisParams p;
  p.delay_samples = 0;
  p.duration = 30.0;
  AxisRecording r = test::SimulateTruthAxis(p);
  r.experiment = "ramp";  // constant-velocity segments of the trapezoidal moves
  const PlatformFit fit = IdentifyPlatform({r}, {}, "");
  ASSERT_EQ(fit.model.name, "friction");
  EXPECT_NEAR(fit.ls.theta(0), p.fv_pos, 0.05 * p.fv_pos);
  EXPECT_NEAR(fit.ls.theta(1), p.fc_pos, 0.05 * p.fc_pos);
  EXPECT_NEAR(fit.ls.theta(2), p.offset, 1.0);
}

int RunPwsim(const std::string& args, const fs::path& log) {
  const std::string cmd = std::string(PWSIM_BINARY_DIR) + "/pwsim " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(PlatformCommand, BadRecordingLeavesNoReport) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test-platform-cli";
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  std::ofstream(dir / "out" / "platform-fit.json") << "{\"stale\": true}\n";  // an old report
  std::ofstream(dir / "run.csv") << "t,x,u\n0,0,0\n0.001,nan,0\n";
  std::ofstream(dir / "run.yaml")
      << "format: pwsim-axis-trial/1\ndata: {file: run.csv, format: csv}\ntime: t\njoints:\n"
         "  - {name: a, kind: prismatic, position: x, command: u, command_to_effort: {value: 1}}\n";
  const int rc = RunPwsim("platform identify " + (dir / "run.yaml").string() + " --out " +
                              (dir / "out").string(),
                          dir / "log.txt");
  EXPECT_EQ(rc, 1);
  EXPECT_FALSE(fs::exists(dir / "out" / "platform-fit.json"));
  std::ifstream in(dir / "log.txt");
  const std::string log((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(log.find("run.csv"), std::string::npos) << log;
  EXPECT_NE(log.find("time ('t')"), std::string::npos) << log;
}

TEST(PlatformCommand, IdentifiesEmpsFromTheCommandLine) {
  PWSIM_REQUIRE_EMPS();
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test-platform-cli-emps";
  fs::remove_all(dir);
  const fs::path emps = test::EmpsDir() / "DATA_EMPS.mat";
  // The same recording as its own cross-test: the validation error equals the fit's.
  const int rc = RunPwsim("platform identify " + emps.string() + " --validate " + emps.string() +
                              " --out " + dir.string(),
                          dir.string() + ".log");
  ASSERT_EQ(rc, 0);
  std::ifstream in(dir / "platform-fit.json");
  const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"format\": \"pwsim-platform-fit/1\""), std::string::npos);
  EXPECT_NE(json.find("\"relative_error_pct\": 4.0833"), std::string::npos) << json;
  EXPECT_NE(json.find("\"rows\": 2480"), std::string::npos);
  EXPECT_NE(json.find("\"recording\": \"DATA_EMPS.mat\""), std::string::npos);
}

// Bad option values of `platform diagnose` are usage errors (exit 2) that name the option and
// the expected form, checked before any recording is read.
TEST(PlatformCommand, BadDiagnoseOptionsNameTheExpectedForm) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test-platform-cli-options";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string base = "platform diagnose " + (dir / "absent.yaml").string() + " --out " +
                           (dir / "out").string() + " ";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"--block-s abc", "option --block-s: expected a number, got \"abc\""},
      {"--holdout 1.5", "option --holdout: expected 0.05..0.95"},
      {"--selection 0", "option --selection: expected 0.05..0.95"},
      {"--decimation 0", "option --decimation: expected an integer in 1..100, got 0"},
      {"--cutoff-hz -3", "option --cutoff-hz: expected a frequency > 0 Hz, got -3"},
  };
  for (const auto& [option, expected] : cases) {
    const fs::path log = dir / "log.txt";
    EXPECT_EQ(RunPwsim(base + option, log), 2) << option;
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find(expected), std::string::npos) << option << ": " << text;
  }
}

TEST(PlatformCommand, UnknownModelIsAUsageError) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test-platform-cli-model";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path log = dir / "log.txt";
  EXPECT_EQ(RunPwsim("platform identify " + (dir / "absent.yaml").string() + " --out " +
                         (dir / "out").string() + " --model foo",
                     log),
            2);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("option --model: expected axis-base | axis-asymmetric | friction | rail-yaw, got foo"),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace pwsim::sysid::platform
