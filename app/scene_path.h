#pragma once
// Where the default scene is: ./scenes/speed_cushion.yaml when run from a checkout, else the
// copy in the source tree this binary was built from.

#include <filesystem>

namespace pwsim::app {

inline std::filesystem::path DefaultScene() {
  const std::filesystem::path local = "scenes/speed_cushion.yaml";
  if (std::filesystem::exists(local)) return local;
  return std::filesystem::path(PWSIM_SOURCE_DIR) / local;
}

}  // namespace pwsim::app
