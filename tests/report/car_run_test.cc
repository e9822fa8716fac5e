// `pwsim run` for car scenes at the library level: the outputs, their units, and what the
// issue asks of the two standard scenes (third gear; one lane sideways and back; the platform
// inside its limits), plus the rail-yaw false cue in the summary.
#include "report/car_run.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "report/car_checks.h"

namespace pwsim::report {
namespace {

namespace fs = std::filesystem;

fs::path Scratch(const std::string& name) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "car_run_test" / name;
  fs::remove_all(dir);
  return dir;
}

std::string Header(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  return line;
}

nlohmann::json Summary(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  return nlohmann::json::parse(in);
}

const fs::path kScenes = fs::path(PWSIM_SOURCE_DIR) / "scenes";

TEST(CarRun, LaunchWritesTheOutputsAndReachesThirdGear) {
  const fs::path out = Scratch("launch");
  CarRunOptions options;
  options.video = false;
  options.decimate = 10;
  const auto scene = vehicle::LoadCarScene(kScenes / "car_launch.yaml");
  const auto written = RunCarScene(scene, kScenes / "car_launch.yaml", options, out);
  EXPECT_GE(written.size(), 3u);
  const std::string header = Header(out / "trial.csv");
  for (const char* column : {"t_s", "x_m", "y_m", "yaw_rad", "v_mps", "yaw_rate_radps", "ax_mps2", "ay_mps2",
                             "engine_rpm", "gear", "throttle", "brake", "clutch", "steer_rad", "plat_surge_m",
                             "plat_yaw_rad", "false_cue_surge_mps2", "false_cue_sway_mps2", "vest_plat_oto_x_mps2"}) {
    EXPECT_NE(header.find(column), std::string::npos) << column;
  }
  EXPECT_TRUE(fs::exists(out / "mca.png"));
  const nlohmann::json s = Summary(out);
  EXPECT_EQ(s["scene"]["kind"], "car");
  EXPECT_GE(s["drive"]["highest_gear_engaged"].get<int>(), 3);
  EXPECT_FALSE(s["drive"]["stalled"].get<bool>());
  EXPECT_LT(s["drive"]["final_speed_mps"].get<double>(), 0.05);
  EXPECT_TRUE(s["mca"]["platform"]["within_limits"].get<bool>());
  EXPECT_EQ(s["mca"]["platform"]["name"], "car2dof");
  EXPECT_TRUE(s["mca"]["rail_yaw_false_cue"].contains("peak_sway_mps2"));
}

TEST(CarRun, LaneChangeMovesOneLaneAndBackWithVideo) {
  const fs::path out = Scratch("lane_change");
  CarRunOptions options;
  options.width = 320;
  options.height = 180;
  options.fps = 10;
  const auto scene = vehicle::LoadCarScene(kScenes / "car_lane_change.yaml");
  RunCarScene(scene, kScenes / "car_lane_change.yaml", options, out);
  const nlohmann::json s = Summary(out);
  const double y_max = s["drive"]["y_range_m"][1].get<double>();
  EXPECT_GT(y_max, 0.8 * scene.road.lane_width);
  EXPECT_LT(y_max, 1.3 * scene.road.lane_width);
  EXPECT_TRUE(s["mca"]["platform"]["within_limits"].get<bool>());
  EXPECT_GT(s["mca"]["consistency"]["canals"]["z"]["correlation"].get<double>(), 0.5);  // yaw cue follows
  EXPECT_TRUE(fs::exists(out / "video.mp4"));
  EXPECT_GT(fs::file_size(out / "video.mp4"), 1000u);
  EXPECT_EQ(s["render"]["frames"].get<int>(), 141);  // 14 s at 10 frames/s, frame 0 included
}

TEST(CarChecks, NumbersMatchTheClosedForms) {
  const fs::path out = Scratch("checks");
  const auto car = vehicle::ReadVehicleFile(fs::path(PWSIM_SOURCE_DIR) / "assets/cars/midsize.yaml");
  const nlohmann::ordered_json r = RunCarChecks(car, "midsize.yaml", out);
  EXPECT_LT(std::abs(r["understeer"]["relative_difference"].get<double>()), 0.1);
  EXPECT_LT(std::abs(r["energy"]["residual_fraction"].get<double>()), 0.01);
  EXPECT_TRUE(r["stall"]["dropped_in_fifth_stalls"].get<bool>());
  EXPECT_FALSE(r["stall"]["slow_release_in_first_stalls"].get<bool>());
  for (const auto& row : r["locked_clutch_ratios"]) {
    EXPECT_NEAR(row["engine_rpm"].get<double>(), row["wheel_times_ratios_rpm"].get<double>(), 1e-6);
  }
  for (const char* stem : {"car_understeer", "car_launch", "car_energy", "car_stall"}) {
    EXPECT_TRUE(fs::exists(out / (std::string(stem) + ".png"))) << stem;
  }
}

}  // namespace
}  // namespace pwsim::report
