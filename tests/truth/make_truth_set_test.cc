// independent_truth_set as a user runs it: `--draw --seed N` regenerates an evaluation set bit
// for bit (every mocap.csv and the truth file), writes the drawn laws beside the set, and a
// malformed number names the option and the expected form (exit 2).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

const std::string kTool = std::string(PWSIM_BINARY_DIR) + "/tests/truth/independent_truth_set";

int RunTool(const std::string& args, const fs::path& log) {
  const int raw = std::system((kTool + " " + args + " > " + log.string() + " 2>&1").c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

std::string Slurp(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(MakeTruthSet, DrawBySeedRegeneratesTheSetBitForBit) {
  const fs::path dir = fs::temp_directory_path() / ("pwsim_truth_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string common = " --draw --seed 1003 --effects cushion_compliance --speeds 0.9,1.3 --loads 50";
  ASSERT_EQ(RunTool("--out " + (dir / "a").string() + common, dir / "a.log"), 0) << Slurp(dir / "a.log");
  ASSERT_EQ(RunTool("--out " + (dir / "b").string() + common, dir / "b.log"), 0) << Slurp(dir / "b.log");
  int trials = 0;
  for (const auto& entry : fs::directory_iterator(dir / "a")) {
    const fs::path name = entry.path().filename();
    EXPECT_EQ(Slurp(dir / "a" / name / "mocap.csv"), Slurp(dir / "b" / name / "mocap.csv")) << name;
    ++trials;
  }
  EXPECT_EQ(trials, 2);
  const std::string truth = Slurp(dir / "a.truth.yaml");
  EXPECT_NE(truth.find("laws:\n  - \"cushion_compliance: "), std::string::npos) << truth;
  EXPECT_NE(truth.find("  - \"noise "), std::string::npos) << truth;
  // Replacing the noise kind keeps the set's laws line.
  ASSERT_EQ(RunTool("--out " + (dir / "c").string() + common + " --noise mix", dir / "c.log"), 0);
  const std::string mixed = Slurp(dir / "c.truth.yaml");
  EXPECT_NE(mixed.find("  - \"noise mix:"), std::string::npos) << mixed;
  const auto law_line = [](const std::string& text) {
    const std::size_t at = text.find("  - \"cushion_compliance");
    return text.substr(at, text.find('\n', at) - at);
  };
  EXPECT_EQ(law_line(truth), law_line(mixed));
  fs::remove_all(dir);
}

TEST(MakeTruthSet, BadOptionsNameTheOptionAndTheExpectedForm) {
  // Everything in this test's own folder; the refused runs must not create their --out.
  const fs::path dir = fs::temp_directory_path() / ("pwsim_truth_cli_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path log = dir / "log.txt";
  const std::string out = "--out " + (dir / "never").string();
  EXPECT_EQ(RunTool(out + " --seed 12x", log), 2);
  EXPECT_NE(Slurp(log).find("--seed: expected a number, got '12x'"), std::string::npos) << Slurp(log);
  EXPECT_EQ(RunTool(out + " --speeds 0.5,fast", log), 2);
  EXPECT_NE(Slurp(log).find("--speeds: expected a number, got 'fast'"), std::string::npos) << Slurp(log);
  EXPECT_EQ(RunTool(out + " --draw --noise purple", log), 2);
  EXPECT_NE(Slurp(log).find("unknown noise kind 'purple'"), std::string::npos) << Slurp(log);
  EXPECT_EQ(RunTool(out + " --noise white", log), 2);
  EXPECT_NE(Slurp(log).find("--noise needs --draw"), std::string::npos) << Slurp(log);
  EXPECT_FALSE(fs::exists(dir / "never"));
  fs::remove_all(dir);
}

}  // namespace
