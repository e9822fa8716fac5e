#pragma once
// Scratch files for the measured-trial tests, under the build folder.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pwsim::testing {

/// A fresh folder per test: build/test-scratch/<suite>.<test>/.
inline std::filesystem::path ScratchDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = std::filesystem::path(PWSIM_BINARY_DIR) / "test-scratch" /
                                    (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::filesystem::path WriteText(const std::filesystem::path& file, const std::string& text) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

}  // namespace pwsim::testing
