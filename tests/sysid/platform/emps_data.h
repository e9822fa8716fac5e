#pragma once
// Where the real EMPS measurements are: $PWSIM_EMPS_DIR, else ../shared/data/emps beside the
// source tree (or one level further up for a git worktree). Tests that need them skip with
// a message naming where they looked.

#include <cstdlib>
#include <filesystem>
#include <string>

namespace pwsim::test {

inline std::filesystem::path EmpsDir() {
  if (const char* env = std::getenv("PWSIM_EMPS_DIR")) return env;
  const std::filesystem::path src(PWSIM_SOURCE_DIR);
  for (const auto& candidate :
       {src / ".." / "shared" / "data" / "emps", src / ".." / ".." / "shared" / "data" / "emps"})
    if (std::filesystem::exists(candidate / "DATA_EMPS.mat")) return candidate;
  return src / ".." / "shared" / "data" / "emps";
}

inline std::string EmpsMissingMessage() {
  return "EMPS data absent: no DATA_EMPS.mat in " + EmpsDir().string() +
         " (set PWSIM_EMPS_DIR or put the shared data beside the source tree)";
}

#define PWSIM_REQUIRE_EMPS()                                                  \
  do {                                                                        \
    if (!std::filesystem::exists(::pwsim::test::EmpsDir() / "DATA_EMPS.mat")) \
      GTEST_SKIP() << ::pwsim::test::EmpsMissingMessage();                    \
  } while (0)

}  // namespace pwsim::test
