#pragma once
// Helpers of the study tests: temporary folders, reading CSV outputs of reference scripts, and
// running a command to its exit.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace pwsim::study::test_util {

inline std::filesystem::path TempDir(const std::string& name) {
  std::filesystem::path dir = std::filesystem::path(PWSIM_BINARY_DIR) / "test_out" / "study" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string Slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Rows of a CSV with a header, as column -> text.
inline std::vector<std::map<std::string, std::string>> ReadCsv(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream ls(line);
    std::string f;
    while (std::getline(ls, f, ',')) fields.push_back(f);
    if (header.empty()) {
      header = fields;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

/// Runs `command` through the shell and waits for it to exit; returns its exit status.
inline int RunShell(const std::string& command) {
  const int status = std::system(command.c_str());
  if (status == -1) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline bool HaveExecutable(const std::string& name) {
  return RunShell("command -v " + name + " > /dev/null 2>&1") == 0;
}

/// A python3 that imports scipy (Debian's /usr/bin/python3 first), or "".
inline std::string PythonWithScipy() {
  for (const char* py : {"/usr/bin/python3", "python3"})
    if (RunShell(std::string(py) + " -c 'import scipy' > /dev/null 2>&1") == 0) return py;
  return "";
}

}  // namespace pwsim::study::test_util
