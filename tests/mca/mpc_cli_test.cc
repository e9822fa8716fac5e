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
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "tests/run_command.h"

namespace {

const std::filesystem::path kBinary = std::filesystem::path(PWSIM_BINARY_DIR) / "pwsim";
const std::filesystem::path kSource(PWSIM_SOURCE_DIR);

nlohmann::json RunMca(const std::string& scene, const std::string& args, const std::string& name) {
  const std::filesystem::path out = std::filesystem::path(PWSIM_BINARY_DIR) / "test-out" / name;
  std::filesystem::remove_all(out);
  const std::string command = "cd '" + kSource.string() + "' && '" + kBinary.string() + "' run " + scene +
                              " --no-video --decimate 10 " +
                              (args.find("--mca-compare") != std::string::npos ? args.substr(0, args.find(" --mca-compare"))
                                                                                : args + " --no-mca-compare") +
                              " --out '" + out.string() + "' > /dev/null";
  if (std::system(command.c_str()) != 0) return {};
  std::ifstream in(out / "summary.json");
  return nlohmann::json::parse(in)["mca"];
}

/// summary.json says every actuator stayed within its stroke, speed and acceleration (from the
/// actuator positions, checked by FK), and its figures agree.
void ExpectInsideLimits(const nlohmann::json& mca) {
  ASSERT_TRUE(mca.is_object());
  EXPECT_TRUE(mca["limits"]["within_limits"].get<bool>()) << mca["limits"];
  EXPECT_TRUE(mca["platform"]["within_limits"].get<bool>());
  EXPECT_LE(mca["limits"]["forward_residual"].get<double>(), 1e-9);
  ASSERT_FALSE(mca["actuators"].empty());
  for (const auto& a : mca["actuators"]) {  // at or below 1 itself (the limiter's headroom)
    EXPECT_LE(a["stroke_use"].get<double>(), 1.0) << a["name"];
    EXPECT_LE(a["speed_fraction"].get<double>(), 1.0) << a["name"];
    EXPECT_LE(a["accel_fraction"].get<double>(), 1.0) << a["name"];
  }
}

// Tests the speed cushion with the MPC, held input and previewed: inside the limits, no
// fallback, and summary.json names the algorithm and the kind of preview.
TEST(MpcCliTest, SpeedCushionWithMpc) {
  const nlohmann::json held = RunMca("scenes/speed_cushion.yaml", "--mca mpc", "mpc_cushion");
  ExpectInsideLimits(held);
  EXPECT_EQ(held["algorithm"]["name"], "mpc");
  EXPECT_EQ(held["algorithm"]["preview"], "none: the vehicle model run ahead with the driver's present input held");
  EXPECT_EQ(held["algorithm"]["fallbacks_to_washout"].get<int>(), 0);
  const nlohmann::json preview = RunMca("scenes/speed_cushion.yaml", "--mca mpc --mca-preview", "mpc_cushion_preview");
  ExpectInsideLimits(preview);
  EXPECT_NE(preview["algorithm"]["preview"].get<std::string>().find("whole trial"), std::string::npos);
  const nlohmann::json washout = RunMca("scenes/speed_cushion.yaml", "--mca washout", "mpc_cushion_washout");
  EXPECT_EQ(washout["algorithm"]["name"], "washout");
  // the run's comparison: the same trial through the washout, the MPC without preview and the
  // offline ceiling, each figure equal to that algorithm's own run
  const nlohmann::json compared = RunMca("scenes/speed_cushion.yaml", "--mca mpc --mca-compare", "mpc_cushion_compare");
  const nlohmann::json& c = compared["comparison"];
  ASSERT_TRUE(c.is_object());
  EXPECT_EQ(c["mpc"]["rms_error"].get<double>(), held["perceived"]["rms_error"].get<double>());
  EXPECT_EQ(c["washout"]["rms_error"].get<double>(), washout["perceived"]["rms_error"].get<double>());
  EXPECT_LE(c["mpc"]["rms_error"].get<double>(), c["washout"]["rms_error"].get<double>());
  EXPECT_LE(c["offline"]["rms_error"].get<double>(), c["mpc"]["rms_error"].get<double>());
  EXPECT_EQ(c["mpc"]["fallbacks_to_washout"].get<int>(), 0);
  for (const char* who : {"washout", "mpc", "offline"}) {
    EXPECT_GT(c[who]["xcorr_peak"].get<double>(), 0.5) << who;
    EXPECT_LT(std::abs(c[who]["lag_s"].get<double>()), 0.5) << who;
  }
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
  const pwsim::testing::TempDir dir("mpc_cli_bad_mca");
  EXPECT_TRUE(pwsim::testing::Refused(
      pwsim::testing::RunCommand("'" + kBinary.string() + "' run --mca fuzzy --no-video --out " + dir.Quoted("out"), dir),
      2, {"option --mca", "washout, mpc or offline", "'fuzzy'"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
}


/// The columns of a trial.csv by name.
std::map<std::string, std::vector<double>> ReadColumns(const std::filesystem::path& csv_file) {
  std::ifstream csv(csv_file);
  std::string line;
  std::getline(csv, line);
  std::vector<std::string> header;
  std::stringstream names(line);
  for (std::string cell; std::getline(names, cell, ',');) header.push_back(cell);
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(csv, line)) {
    std::stringstream row(line);
    std::string cell;
    for (std::size_t i = 0; i < header.size() && std::getline(row, cell, ','); ++i) {
      char* end = nullptr;
      const double value = std::strtod(cell.c_str(), &end);  // a text cell (a car's gear name ...) is NaN
      columns[header[i]].push_back(end != cell.c_str() ? value : std::numeric_limits<double>::quiet_NaN());
    }
  }
  return columns;
}

// Tests every shipped scene with both algorithms (the washout, the MPC without preview as a
// live session runs it, and the MPC previewing the trial), from the files pwsim run writes:
//  - the tilt-rate guarantee (mca/mpc.h, mca/actuator_limiter.h), from trial.csv alone: the
//    platform's pitch (roll) rate r, the pose difference per tick, stays within
//    [min(0, ω_f) − τ, max(0, ω_f) + τ], τ = 3 deg/s, where ω_f is the vehicle's own nose-up
//    pitch rate −head_w_y (roll rate head_w_x) changing by at most the axis's acceleration limit
//    per tick (recomputed here from the definition); only floating-point slack is allowed. The
//    car platform has no pitch or roll (no columns): nothing to tilt;
//  - every actuator within its stroke, speed and acceleration (summary.json, from the actuator
//    positions by FK; MpcTest and WashoutTest recompute them from the poses);
//  - the MPC without preview never loses to the washout on this trial: its perceived-motion
//    error (RMS over otolith [m/s²] and canal [rad/s × 10] channels, summary's mca.comparison) is
//    at most the washout's, and no QP fell back.
/// The shipped scenes' file names (scenes/*.yaml), one parameter each so that ctest runs them apart.
std::vector<std::string> ShippedScenes() {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(kSource / "scenes")) {
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

class MpcCliSceneTest : public ::testing::TestWithParam<std::string> {};

TEST_P(MpcCliSceneTest, TiltCoordinationRateNeverAboveThresholdOnEveryShippedScene) {
  const double deg = std::numbers::pi / 180.0;
  const double threshold = 3.0 * deg;
  int tilt_runs = 0;
  double worst = 0.0;
  const std::string scene = "scenes/" + GetParam() + ".yaml";
  double held_error = -1.0, washout_error = -1.0;
  for (const std::string mode : {"--mca mpc", "--mca mpc --mca-preview", "--mca washout"}) {
    const std::string name = "mpc_tilt_" + GetParam() + "_" +
                             (mode.find("preview") != std::string::npos ? "preview"
                              : mode.find("washout") != std::string::npos ? "washout" : "held");
    const std::filesystem::path out = std::filesystem::path(PWSIM_BINARY_DIR) / "test-out" / name;
    std::filesystem::remove_all(out);
    const std::string command = "cd '" + kSource.string() + "' && '" + kBinary.string() + "' run " + scene +
                                " --no-video --no-mca-compare " + mode + " --out '" + out.string() + "' > /dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(out / "summary.json");
    const nlohmann::json mca = nlohmann::json::parse(in)["mca"];
    ExpectInsideLimits(mca);
    if (mca["false_cues"].contains("tilt_rate_count")) {  // platforms with a tilt axis
      EXPECT_EQ(mca["false_cues"]["tilt_rate_count"].get<int>(), 0) << name;
    }
    if (mca["algorithm"]["name"] == "mpc") {
      EXPECT_EQ(mca["algorithm"]["fallbacks_to_washout"].get<int>(), 0) << name;
    }
    if (name.ends_with("_held")) held_error = mca["perceived"]["rms_error"].get<double>();
    if (name.ends_with("_washout")) washout_error = mca["perceived"]["rms_error"].get<double>();
    const std::map<std::string, std::vector<double>> c = ReadColumns(out / "trial.csv");
    const std::vector<double>& t = c.at("t_s");
    ASSERT_GT(t.size(), 100u) << name;
    const double dt = t[1] - t[0];
    for (const char* axis : {"pitch", "roll"}) {
      const auto pose = c.find(std::string("plat_") + axis + "_rad");
      if (pose == c.end()) continue;
      // pw4dof's roll and pitch: 300 deg/s², no sustained limit (scenes/platforms/pw4dof.yaml)
      ASSERT_EQ(mca["platform"]["name"], "pw4dof") << name;
      const double accel_limit = 300.0 * deg;
      const bool pitch = std::string(axis) == "pitch";
      const std::vector<double>& w = c.at(pitch ? "head_w_y_radps" : "head_w_x_radps");
      double follow = 0.0, previous = 0.0;
      for (std::size_t k = 0; k < t.size(); ++k) {
        const double vehicle = pitch ? -w[k] : w[k];
        follow = std::clamp(vehicle, follow - accel_limit * dt, follow + accel_limit * dt);
        const double rate = (pose->second[k] - previous) / dt;
        previous = pose->second[k];
        const double beyond = std::max({0.0, rate - std::max(0.0, follow), std::min(0.0, follow) - rate});
        worst = std::max(worst, beyond);
        ASSERT_LE(beyond, threshold * (1.0 + 1e-9) + 1e-9) << name << " " << axis << " tick " << k;
      }
      ++tilt_runs;
    }
  }
  ASSERT_GT(washout_error, 0.0) << scene;
  EXPECT_LE(held_error, washout_error) << scene << ": the MPC without preview loses to the washout";
  if (tilt_runs > 0) {  // a chair scene on pw4dof: every run, both algorithms, binds the band
    EXPECT_GT(worst, 0.9 * threshold) << "the band binds (the check is not vacuous)";
  }
}

INSTANTIATE_TEST_SUITE_P(Shipped, MpcCliSceneTest, ::testing::ValuesIn(ShippedScenes()),
                         [](const ::testing::TestParamInfo<std::string>& scene) { return scene.param; });

// Tests that the shipped scenes are all there: the chair's straight run and three circuits
// (pitch and roll on pw4dof), four car scenes.
TEST(MpcCliTest, ShippedScenesAreTheEight) {
  const std::vector<std::string> names = ShippedScenes();
  EXPECT_GE(names.size(), 8u);
  for (const char* scene : {"speed_cushion", "circuit_course", "circuit_recorded", "circuit_room", "car_launch",
                            "car_lane_change", "car_recorded_drive", "car_seed_drive"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), scene), names.end()) << scene;
  }
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
  const pwsim::testing::TempDir dir("mpc_cli_drive_refused");
  EXPECT_TRUE(pwsim::testing::Refused(
      pwsim::testing::RunCommand("cd '" + kSource.string() + "' && '" + kBinary.string() +
                                     "' drive scenes/car_launch.yaml --no-realtime --duration 3 --mca lqr --out " +
                                     dir.Quoted("out"),
                                 dir),
      2, {"option --mca", "'lqr'"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "drive.csv"));
}

// Tests `pwsim omct --mca mpc` refusals: a tick rate that does not divide the MPC's control
// period, and an unknown algorithm.
TEST(MpcCliTest, OmctMpcRefusals) {
  const pwsim::testing::TempDir dir("mpc_cli_omct_refused");
  const std::string base = "'" + kBinary.string() + "' omct --out " + dir.Quoted("out") + " ";
  EXPECT_TRUE(pwsim::testing::Refused(pwsim::testing::RunCommand(base + "--mca mpc --rate-hz 250", dir), 2,
                                      {"option --rate-hz", "control period", "whole number of ticks"}));
  EXPECT_TRUE(pwsim::testing::Refused(pwsim::testing::RunCommand(base + "--mca fuzzy", dir), 2,
                                      {"option --mca", "'fuzzy'"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "omct.csv"));
}

}  // namespace
