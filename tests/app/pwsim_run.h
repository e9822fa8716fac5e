#pragma once
// Running the built pwsim from a test: its exit status and everything it printed (stdout and
// stderr together, through a log file in the test's own folder), and that folder, fresh, under
// the build tree. One copy for the command-line tests of tests/app.

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace pwsim::test {

struct PwsimResult {
  int status{0};       ///< exit status; -1 when pwsim did not exit normally (a crash)
  std::string output;  ///< stdout and stderr together
};

/// A fresh, empty folder `name` of test area `area` under the build tree.
inline std::filesystem::path FreshTestFolder(const std::string& area, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(PWSIM_BINARY_DIR) / "test_out" / area / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string ReadWholeFile(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Runs `pwsim ARGS` with its log in `dir`; from inside `dir` when `in_dir`, else from the
/// test's own working folder (relative paths in ARGS are then read from there).
inline PwsimResult RunPwsim(const std::string& args, const std::filesystem::path& dir, bool in_dir) {
  const std::filesystem::path log = dir / "pwsim.log";
  const std::string command = (in_dir ? "cd '" + dir.string() + "' && " : std::string()) +
                              std::string(PWSIM_BINARY_DIR) + "/pwsim " + args + " > '" + log.string() + "' 2>&1";
  const int raw = std::system(command.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, ReadWholeFile(log)};
}

}  // namespace pwsim::test
