// `pwsim run --mca mpc|offline` end to end on the shipped scenes: the chair's speed cushion and
// the car's launch and lane change run inside every limit and say which algorithm and preview.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

const std::filesystem::path kBinary = std::filesystem::path(PWSIM_BINARY_DIR) / "pwsim";
const std::filesystem::path kSource(PWSIM_SOURCE_DIR);

nlohmann::json RunMca(const std::string& scene, const std::string& args, const std::string& name) {
  const std::filesystem::path out = std::filesystem::path(PWSIM_BINARY_DIR) / "test-out" / name;
  std::filesystem::remove_all(out);
  const std::string command = "cd '" + kSource.string() + "' && '" + kBinary.string() + "' run " + scene +
                              " --no-video --decimate 10 " + args + " --out '" + out.string() + "' > /dev/null";
  if (std::system(command.c_str()) != 0) return {};
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in)["mca"];
}

void ExpectInsideLimits(const nlohmann::json& mca) {
  ASSERT_TRUE(mca.is_object());
  for (const auto& usage : mca["platform"]["usage"]) {
    EXPECT_LE(usage["pose_fraction_of_limit"].get<double>(), 1.0 + 1e-9) << usage["dof"];
    EXPECT_LE(usage["rate_fraction_of_limit"].get<double>(), 1.0 + 1e-9) << usage["dof"];
    EXPECT_LE(usage["accel_fraction_of_limit"].get<double>(), 1.0 + 1e-6) << usage["dof"];
  }
}

// Tests the speed cushion with the MPC, held input and previewed: inside the limits, no
// fallback, and summary.json names the algorithm and the kind of preview.
TEST(MpcCliTest, SpeedCushionWithMpc) {
  const nlohmann::json held = RunMca("scenes/speed_cushion.yaml", "--mca mpc", "mpc_cushion");
  ExpectInsideLimits(held);
  EXPECT_EQ(held["algorithm"]["name"], "mpc");
  EXPECT_EQ(held["algorithm"]["preview"], "none: the current input is held");
  EXPECT_EQ(held["algorithm"]["fallbacks_to_washout"].get<int>(), 0);
  const nlohmann::json preview = RunMca("scenes/speed_cushion.yaml", "--mca mpc --mca-preview", "mpc_cushion_preview");
  ExpectInsideLimits(preview);
  EXPECT_NE(preview["algorithm"]["preview"].get<std::string>().find("whole trial"), std::string::npos);
  const nlohmann::json washout = RunMca("scenes/speed_cushion.yaml", "--mca washout", "mpc_cushion_washout");
  EXPECT_EQ(washout["algorithm"]["name"], "washout");
}

// Tests the car's launch and lane change with the MPC and the offline ceiling on the rail + yaw,
// the other shipped car scenes with the MPC, and that an unknown --mca value is refused.
TEST(MpcCliTest, CarScenesWithMpcAndOffline) {
  for (const char* scene : {"car_launch", "car_lane_change"}) {
    const nlohmann::json mpc = RunMca(std::string("scenes/") + scene + ".yaml", "--mca mpc", std::string("mpc_") + scene);
    ExpectInsideLimits(mpc);
    EXPECT_TRUE(mpc["platform"]["within_limits"].get<bool>()) << scene;
    EXPECT_EQ(mpc["algorithm"]["fallbacks_to_washout"].get<int>(), 0) << scene;
    const nlohmann::json offline =
        RunMca(std::string("scenes/") + scene + ".yaml", "--mca offline", std::string("offline_") + scene);
    ExpectInsideLimits(offline);
    EXPECT_EQ(offline["algorithm"]["name"], "offline") << scene;
  }
  for (const char* scene : {"car_recorded_drive", "car_seed_drive"}) {  // the other shipped car scenes
    const nlohmann::json mpc = RunMca(std::string("scenes/") + scene + ".yaml", "--mca mpc", std::string("mpc_") + scene);
    ExpectInsideLimits(mpc);
    EXPECT_EQ(mpc["algorithm"]["fallbacks_to_washout"].get<int>(), 0) << scene;
  }
  EXPECT_NE(std::system(("'" + kBinary.string() + "' run --mca fuzzy --no-video --out /tmp/pwsim_mpc_bad > /dev/null 2>&1").c_str()), 0);
}

}  // namespace
