// `pwsim run --mca mpc|offline` end to end on the shipped scenes: the chair's speed cushion and
// the car's launch and lane change run inside every limit and say which algorithm and preview;
// `pwsim drive --mca` and `pwsim omct --mca mpc` through the built binary.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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


/// `pwsim drive SCENE --no-realtime` (the scene's own controls) with `args`; the plat_surge_m
/// column of drive.csv and stdout.
std::vector<double> DriveSurge(const std::string& args, const std::string& name, std::string* stdout_text) {
  const std::filesystem::path out = std::filesystem::path(PWSIM_BINARY_DIR) / "test-out" / name;
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  const std::string command = "cd '" + kSource.string() + "' && '" + kBinary.string() +
                              "' drive scenes/car_launch.yaml --no-realtime --duration 3 " + args + " --out '" +
                              out.string() + "' > '" + (out / "stdout.txt").string() + "' 2>&1";
  if (std::system(command.c_str()) != 0) return {};
  std::ifstream text(out / "stdout.txt");
  *stdout_text = std::string(std::istreambuf_iterator<char>(text), {});
  std::ifstream csv(out / "drive.csv");
  std::string line;
  std::getline(csv, line);
  std::vector<std::string> header;
  std::stringstream names(line);
  for (std::string cell; std::getline(names, cell, ',');) header.push_back(cell);
  const auto column = static_cast<std::size_t>(std::find(header.begin(), header.end(), "plat_surge_m") - header.begin());
  std::vector<double> surge;
  while (std::getline(csv, line)) {
    std::stringstream row(line);
    std::string cell;
    for (std::size_t i = 0; i <= column && std::getline(row, cell, ','); ++i) {
    }
    surge.push_back(std::stod(cell));
  }
  return surge;
}

// Tests that `pwsim drive --mca` reaches the live loop: the scene (washout) and --mca washout
// give the same rail, --mca mpc another one, and the run says which.
TEST(MpcCliTest, DriveOptionReachesTheLoop) {
  std::string scene_text, washout_text, mpc_text;
  const std::vector<double> scene = DriveSurge("", "drive_scene", &scene_text);
  const std::vector<double> washout = DriveSurge("--mca washout", "drive_washout", &washout_text);
  const std::vector<double> mpc = DriveSurge("--mca mpc", "drive_mpc", &mpc_text);
  ASSERT_GT(scene.size(), 1000u) << scene_text;
  ASSERT_EQ(washout.size(), scene.size()) << washout_text;
  ASSERT_EQ(mpc.size(), scene.size()) << mpc_text;
  EXPECT_EQ(washout, scene);
  double difference = 0.0;
  for (std::size_t k = 0; k < mpc.size(); ++k) difference = std::max(difference, std::abs(mpc[k] - washout[k]));
  EXPECT_GT(difference, 1e-3);  // [m] of rail
  EXPECT_NE(scene_text.find("mca washout"), std::string::npos) << scene_text;
  EXPECT_NE(mpc_text.find("mca mpc"), std::string::npos) << mpc_text;
  std::string refused;
  EXPECT_TRUE(DriveSurge("--mca lqr", "drive_refused", &refused).empty());
}

// Tests `pwsim omct --mca mpc` refusals: a tick rate that does not divide the MPC's control
// period, and an unknown algorithm.
TEST(MpcCliTest, OmctMpcRefusals) {
  const std::string base = "'" + kBinary.string() + "' omct --out /tmp/pwsim_omct_mpc_bad ";
  EXPECT_NE(std::system((base + "--mca mpc --rate-hz 250 > /dev/null 2>&1").c_str()), 0);
  EXPECT_NE(std::system((base + "--mca fuzzy > /dev/null 2>&1").c_str()), 0);
}

}  // namespace
