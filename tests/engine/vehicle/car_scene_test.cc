#include "engine/vehicle/car_scene.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/input_error.h"
#include "engine/scene.h"

namespace pwsim::vehicle {
namespace {

std::filesystem::path Scene(const char* name) { return std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes" / name; }

TEST(CarScene, KindTellsCarFromWheelchair) {
  EXPECT_EQ(SceneKind(Scene("car_launch.yaml")), "car");
  EXPECT_EQ(SceneKind(Scene("speed_cushion.yaml")), "wheelchair");
}

TEST(CarScene, TheWheelchairLoaderPointsToTheCarLoader) {
  try {
    LoadScene(Scene("car_launch.yaml"));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "kind");
    EXPECT_NE(std::string(e.what()).find("LoadCarScene"), std::string::npos) << e.what();
  }
}

TEST(CarScene, LaunchReachesThirdGearAndStops) {
  const CarScene scene = LoadCarScene(Scene("car_launch.yaml"));
  EXPECT_EQ(scene.source, CarScene::Source::kTables);
  const std::vector<CarSample> run = SimulateCarScene(scene);
  ASSERT_EQ(static_cast<std::int64_t>(run.size()), scene.tick_count());
  int top_gear_locked = 0;
  double top_speed = 0.0;
  bool stalled = false;
  for (const CarSample& s : run) {
    if (s.state.clutch_locked) top_gear_locked = std::max(top_gear_locked, s.input.gear);
    top_speed = std::max(top_speed, s.state.u);
    stalled = stalled || !s.state.engine_running;
  }
  EXPECT_GE(top_gear_locked, 3);
  EXPECT_GT(top_speed, 10.0);
  EXPECT_FALSE(stalled);
  EXPECT_LT(std::abs(run.back().state.u), 0.01);
  EXPECT_NEAR(run.back().state.y, 0.0, 1e-9);  // straight, no steering
}

TEST(CarScene, LaneChangeMovesOneLaneAndBack) {
  const CarScene scene = LoadCarScene(Scene("car_lane_change.yaml"));
  ASSERT_EQ(scene.source, CarScene::Source::kDriver);
  EXPECT_EQ(scene.road.cones.size(), 18u);
  const std::vector<CarSample> run = SimulateCarScene(scene);
  double y_max = 0.0;
  for (const CarSample& s : run) y_max = std::max(y_max, s.state.y);
  EXPECT_GT(y_max, 0.8 * scene.road.lane_width);
  EXPECT_LT(y_max, 1.3 * scene.road.lane_width);
  EXPECT_LT(std::abs(run.back().state.y), 0.5);
}

TEST(CarScene, RecordedDriveReplaysOpenLoop) {
  const CarScene scene = LoadCarScene(Scene("car_recorded_drive.yaml"));
  EXPECT_EQ(scene.source, CarScene::Source::kRecordedDrive);
  EXPECT_GT(scene.tables.EndTime(), 70.0);
  EXPECT_GT(scene.road.centre.size(), 1000u);  // the road follows its route
  const std::vector<CarSample> run = SimulateCarScene(scene);
  double max_r = 0.0;
  int max_gear = 0;
  for (const CarSample& s : run) {
    max_r = std::max(max_r, std::abs(s.state.r));
    max_gear = std::max(max_gear, s.input.gear);
  }
  EXPECT_GT(max_r, 0.2);
  EXPECT_GE(max_gear, 3);
  EXPECT_TRUE(run.back().state.engine_running);
}

TEST(CarScene, SeedDriveTurnsAndStops) {
  const CarScene scene = LoadCarScene(Scene("car_seed_drive.yaml"));
  const std::vector<CarSample> run = SimulateCarScene(scene);
  double min_ax = 0.0, max_ax = 0.0, max_r = 0.0;
  int max_gear = 0;
  for (const CarSample& s : run) {
    min_ax = std::min(min_ax, s.state.ax);
    max_ax = std::max(max_ax, s.state.ax);
    max_r = std::max(max_r, std::abs(s.state.r));
    max_gear = std::max(max_gear, s.input.gear);
  }
  EXPECT_LT(min_ax, -2.0);   // braking
  EXPECT_GT(max_ax, 1.0);    // accelerating
  EXPECT_GT(max_r, 0.2);     // turns
  EXPECT_GE(max_gear, 3);
  EXPECT_NEAR(run.back().state.yaw, 45.0 * kPi / 180.0, 0.05);  // route: +90 - 90 + 45 deg
  EXPECT_LT(run.back().state.u, 0.5);
}

/// In a steady turn the head feels the centripetal acceleration of its own point:
/// fs_y = a_y,CoG + ṙ x_h - r² y_h + g sin φ with ṙ = 0 (closed form), fs_x = a_x - r² x_h + g sin θ.
TEST(CarScene, HeadMotionInASteadyTurn) {
  CarSample s;
  s.state.u = 20.0;
  s.state.r = 0.2;
  s.state.ax = 0.0;
  s.state.ay = 4.0;
  s.state.roll = 0.02;
  s.state.pitch = 0.0;
  const std::array<double, 3> head{0.3, 0.37, 0.65};
  const CarHeadMotion m = HeadMotionOfCar(s, head);
  EXPECT_NEAR(m.fs[0], -0.04 * 0.3, 1e-12);
  EXPECT_NEAR(m.fs[1], 4.0 - 0.04 * 0.37 + kGravity * std::sin(0.02), 1e-12);
  EXPECT_NEAR(m.fs[2], kGravity * std::cos(0.02), 1e-12);
  EXPECT_EQ(m.w[2], 0.2);
}

TEST(CarScene, RouteArcsHaveTheirRadius) {
  const std::vector<PathPoint> path = RoutePolyline({{10.0, 0.0, 0.0}, {0.0, kPi / 2.0, 20.0}}, 0.0, 0.0, 0.0, 0.5);
  EXPECT_NEAR(path.back().x, 30.0, 1e-9);
  EXPECT_NEAR(path.back().y, 20.0, 1e-9);
  const std::vector<PathPoint> right = RoutePolyline({{0.0, -kPi / 2.0, 20.0}}, 0.0, 0.0, 0.0, 0.5);
  EXPECT_NEAR(right.back().x, 20.0, 1e-9);
  EXPECT_NEAR(right.back().y, -20.0, 1e-9);
}

TEST(CarScene, BadScenesNameTheField) {
  const std::string head = "format: pwsim-scene/1\nkind: car\nname: x\nvehicle: ../assets/cars/midsize.yaml\nduration_s: 5\n";
  const std::filesystem::path label = Scene("inline.yaml");
  auto expect = [&](const std::string& body, const std::string& part) {
    try {
      ParseCarScene(head + body, label);
      ADD_FAILURE() << "no error: " << part;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expect("", "exactly one of inputs, recorded_drive or driver");
  expect("inputs: {throttle: [[0, 0]]}\ndriver: {path_m: [[0, 0], [1, 0]], speed_kmh: [[0, 10]]}\n", "exactly one");
  expect("driver: {path_m: [[0, 0], [1, 0]]}\n", "driver.speed_kmh");
  expect("driver: {route: [{turn_deg: 90, radius_m: 2}], speed_kmh: [[0, 10]]}\n", "driver.route[0].radius_m");
  expect("inputs: {throttle: [[0, 0]]}\nroad: {lanes: 9}\n", "road.lanes");
  expect("inputs: {throttle: [[0, 0]]}\nwheather: sunny\n", "wheather");
  EXPECT_NO_THROW(ParseCarScene(head + "inputs: {throttle: [[0, 0]]}\nmca: {}\nplatform: platforms/car2dof.yaml\n", label));
}

}  // namespace
}  // namespace pwsim::vehicle
