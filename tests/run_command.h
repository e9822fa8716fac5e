#pragma once
// For tests that run the built pwsim (or another program) through the shell: a temporary folder
// of the test's own, and a run whose exit status and output are kept, so that a test that
// expects a refusal can check that it was one — the exit code of a handled error and the message
// naming what was wrong — and not a crash (a signal) or a refusal of something else.
//
//   pwsim::testing::TempDir dir("omct_refusals");             // /tmp/pwsim-omct_refusals-XXXXXX
//   const auto r = pwsim::testing::RunCommand("pwsim omct --mca fuzzy --out " + dir.Quoted("out"), dir);
//   EXPECT_TRUE(pwsim::testing::Refused(r, 2, {"--mca", "fuzzy"}));

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace pwsim::testing {

/// A fresh folder under the system's temporary folder (mkdtemp: unique, so that two runs of a
/// test, or two build trees, never share it), removed with everything in it at the end of scope.
class TempDir {
 public:
  explicit TempDir(const std::string& name) {
    std::string pattern = (std::filesystem::temp_directory_path() / ("pwsim-" + name + "-XXXXXX")).string();
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (mkdtemp(buffer.data()) == nullptr) throw std::runtime_error("mkdtemp " + pattern + " failed");
    path_ = buffer.data();
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  /// path()/name in single quotes, for a shell command line.
  std::string Quoted(const std::string& name) const { return "'" + (path_ / name).string() + "'"; }

 private:
  std::filesystem::path path_;
};

struct CommandResult {
  std::string command;
  int exit_code{-1};  ///< the program's exit status; -1 when it did not exit normally
  int signal{0};      ///< the signal that ended it (the shell reports 128 + n), 0 if none
  std::string output; ///< stdout and stderr together
};

/// Runs `command` with sh, its stdout and stderr going to a log file in `dir`.
inline CommandResult RunCommand(const std::string& command, const TempDir& dir) {
  static int runs = 0;
  const std::filesystem::path log = dir / ("command-" + std::to_string(++runs) + ".log");
  const std::string line = "( " + command + " ) > '" + log.string() + "' 2>&1";
  const int status = std::system(line.c_str());
  CommandResult result;
  result.command = command;
  if (status != -1 && WIFEXITED(status)) {
    result.exit_code = WEXITSTATUS(status);
    if (result.exit_code > 128) {  // sh's report of a child ended by a signal
      result.signal = result.exit_code - 128;
      result.exit_code = -1;
    }
  } else if (status != -1 && WIFSIGNALED(status)) {
    result.signal = WTERMSIG(status);
  }
  std::ifstream in(log);
  std::ostringstream text;
  text << in.rdbuf();
  result.output = text.str();
  return result;
}

/// True when the run ended by exiting with `exit_code` (a handled refusal, not a crash) and its
/// output names every one of `words`.
inline ::testing::AssertionResult Refused(const CommandResult& r, int exit_code,
                                          std::initializer_list<std::string> words) {
  if (r.signal != 0)
    return ::testing::AssertionFailure() << r.command << ": killed by signal " << r.signal << "\n" << r.output;
  if (r.exit_code != exit_code)
    return ::testing::AssertionFailure() << r.command << ": exit code " << r.exit_code << ", expected "
                                         << exit_code << "\n" << r.output;
  for (const std::string& word : words)
    if (r.output.find(word) == std::string::npos)
      return ::testing::AssertionFailure() << r.command << ": the message does not name '" << word
                                           << "':\n" << r.output;
  return ::testing::AssertionSuccess();
}

}  // namespace pwsim::testing
