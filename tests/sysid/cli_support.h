#pragma once
// What the end-to-end tests of `pwsim identify` and `pwsim diagnose` share: running the built
// binary with its output in a log, reading a file whole, and a set's trial folders in order.

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pwsim::test {

inline const std::filesystem::path& PwsimBinary() {
  static const std::filesystem::path binary = std::filesystem::path(PWSIM_BINARY_DIR) / "pwsim";
  return binary;
}

/// Runs `pwsim ARGS` with stdout and stderr in `log`; returns the exit status (-1 if killed).
inline int RunPwsim(const std::string& args, const std::filesystem::path& log) {
  const std::string command = PwsimBinary().string() + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline std::string Read(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// " DIR1 DIR2 ..." for the trial folders of `set`, sorted (arguments for the CLI).
inline std::string TrialDirs(const std::filesystem::path& set) {
  std::vector<std::string> dirs;
  for (const auto& entry : std::filesystem::directory_iterator(set)) {
    if (entry.is_directory()) dirs.push_back(entry.path().string());
  }
  std::sort(dirs.begin(), dirs.end());
  std::string out;
  for (const auto& d : dirs) out += " " + d;
  return out;
}

}  // namespace pwsim::test
