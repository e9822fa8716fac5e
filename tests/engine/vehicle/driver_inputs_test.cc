#include "engine/vehicle/driver_inputs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "engine/input_error.h"

namespace pwsim::vehicle {
namespace {

InputTables Tables(const std::string& text) {
  const YamlDocument doc = LoadYamlString(text, "scene.yaml");
  YamlMap root(doc.root, doc.file, "");
  YamlMap inputs = root.Map("inputs");
  return ParseInputTables(inputs, 5);
}

TEST(InputTables, InterpolateAndHoldGears) {
  const InputTables t = Tables(
      "inputs:\n  throttle: [[0, 0], [2, 1]]\n  gear: [[0, 1], [3, 2]]\n  steer_deg: [[0, 0], [1, 90]]\n");
  EXPECT_DOUBLE_EQ(t.At(1.0).throttle, 0.5);
  EXPECT_DOUBLE_EQ(t.At(5.0).throttle, 1.0);
  EXPECT_EQ(t.At(2.999).gear, 1);
  EXPECT_EQ(t.At(3.0).gear, 2);
  EXPECT_NEAR(t.At(0.5).steer, 0.25 * kPi, 1e-12);
  EXPECT_EQ(t.At(1.0).brake, 0.0);
  EXPECT_EQ(t.EndTime(), 3.0);
}

TEST(InputTables, BadTablesAreRejected) {
  EXPECT_THROW(Tables("inputs:\n  throttle: [[0, 0], [0, 1]]\n"), InputError);   // time not rising
  EXPECT_THROW(Tables("inputs:\n  throttle: [[0, 1.5]]\n"), InputError);         // out of [0, 1]
  EXPECT_THROW(Tables("inputs:\n  gear: [[0, 2.5]]\n"), InputError);             // not an integer
  EXPECT_THROW(Tables("inputs:\n  gear: [[0, 6]]\n"), InputError);               // no 6th gear
  EXPECT_THROW(Tables("inputs:\n  throtle: [[0, 1]]\n"), InputError);            // typo
  try {
    Tables("inputs:\n  brake: [[0, 0], [1, 0.5], [0.5, 1]]\n");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("inputs.brake[2][0]"), std::string::npos) << e.what();
  }
}

TEST(RecordedDrive, ReadsColumnsInAnyOrderAndRejectsBadCells) {
  const std::filesystem::path dir = std::filesystem::path(PWSIM_BINARY_DIR) / "vehicle_test_drive";
  std::filesystem::create_directories(dir);
  const std::filesystem::path good = dir / "good.csv";
  std::ofstream(good) << "gear,t_s,throttle,brake,clutch,steer_rad\n1,0,0,0,1,0\n1,1,0.5,0,0,0.1\n2,2,0.2,0.3,0,-0.1\n";
  const InputTables t = ReadRecordedDrive(good, 5);
  EXPECT_DOUBLE_EQ(t.At(0.5).throttle, 0.25);
  EXPECT_DOUBLE_EQ(t.At(0.5).clutch, 0.5);
  EXPECT_EQ(t.At(1.5).gear, 1);
  EXPECT_EQ(t.At(2.0).gear, 2);
  EXPECT_DOUBLE_EQ(t.At(1.5).steer, 0.0);

  const std::filesystem::path bad = dir / "bad.csv";
  std::ofstream(bad) << "t_s,throttle,brake,clutch,gear,steer_rad\n0,0,0,0,1,0\n1,2,0,0,1,0\n";
  try {
    ReadRecordedDrive(bad, 5);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "throttle");
  }
  std::ofstream(bad) << "t_s,throttle,brake,clutch,gear\n0,0,0,0,1\n";
  EXPECT_THROW(ReadRecordedDrive(bad, 5), InputError);  // steer_rad missing
}

/// A closed-loop drive recorded to CSV and replayed gives the same trajectory, bit for bit.
TEST(RecordedDrive, ReplayOfARecordedDriveIsExact) {
  const Vehicle car = ReadVehicleFile(PWSIM_SOURCE_DIR "/assets/cars/midsize.yaml");
  PathDriver driver(PathDriverParams{}, {{0.0, 0.0}, {50.0, 0.0}, {150.0, 30.0}}, {{0.0, 40.0}, {300.0, 40.0}});
  VehicleState s = InitialState(car);
  std::vector<double> t;
  std::vector<DriverInput> inputs;
  std::vector<VehicleState> states;
  for (int k = 0; k < 15000; ++k) {
    const DriverInput in = driver.Step(car, s, 1e-3);
    t.push_back(k * 1e-3);
    inputs.push_back(in);
    s = StepVehicle(car, s, in, 1e-3);
    states.push_back(s);
  }
  const std::filesystem::path file = std::filesystem::path(PWSIM_BINARY_DIR) / "vehicle_test_drive" / "recorded.csv";
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file) << RecordedDriveCsv(t, inputs);
  const InputTables replay = ReadRecordedDrive(file, car.gear_count());
  VehicleState r = InitialState(car);
  for (int k = 0; k < 15000; ++k) {
    r = StepVehicle(car, r, replay.At(k * 1e-3), 1e-3);
    ASSERT_EQ(r, states[static_cast<std::size_t>(k)]) << "tick " << k;
  }
  EXPECT_GT(r.y, 5.0);  // it did turn
}

TEST(Iso3888Track, ConesFollowTheStandard) {
  const double w = 1.8;
  const LaneChangeTrack track = MakeIso3888Track(w, 50.0, 50.0, 50.0);
  ASSERT_EQ(track.left_cones.size(), 9u);
  ASSERT_EQ(track.right_cones.size(), 9u);
  // section lengths 15, (30), 25, (25), 15 + 15
  EXPECT_DOUBLE_EQ(track.right_cones[2].x - track.right_cones[0].x, 15.0);
  EXPECT_DOUBLE_EQ(track.right_cones[3].x - track.right_cones[2].x, 30.0);
  EXPECT_DOUBLE_EQ(track.right_cones[5].x - track.right_cones[3].x, 25.0);
  EXPECT_DOUBLE_EQ(track.right_cones[6].x - track.right_cones[5].x, 25.0);
  EXPECT_DOUBLE_EQ(track.right_cones[8].x - track.right_cones[6].x, 30.0);
  // lane widths
  EXPECT_NEAR(track.left_cones[0].y - track.right_cones[0].y, 1.1 * w + 0.25, 1e-12);
  EXPECT_NEAR(track.left_cones[3].y - track.right_cones[3].y, 1.2 * w + 0.25, 1e-12);
  EXPECT_NEAR(track.left_cones[6].y - track.right_cones[6].y, 1.3 * w + 0.25, 1e-12);
  // 3.5 m offset of the right rows; sections 1 and 5 share theirs
  EXPECT_NEAR(track.right_cones[3].y - track.right_cones[0].y, 3.5, 1e-12);
  EXPECT_NEAR(track.right_cones[6].y, track.right_cones[0].y, 1e-12);
}

/// The closed-loop driver takes the car through the ISO 3888-1 gates at 60 km/h: about one lane
/// sideways and back, every wheel inside every gate.
TEST(PathDriver, DrivesTheIso3888LaneChange) {
  const Vehicle car = ReadVehicleFile(PWSIM_SOURCE_DIR "/assets/cars/midsize.yaml");
  const LaneChangeTrack track = MakeIso3888Track(car.chassis.width, 150.0, 150.0, 60.0);
  const double v = 60.0 / 3.6;
  PathDriverParams p;
  p.top_gear = 3;
  p.upshift_rpm = 4000.0;
  PathDriver driver(p, track.centre, {{0.0, v}, {400.0, v}});
  VehicleState s = InitialState(car);
  s.x = track.centre.front().x;
  double y_max = -1.0, y_after = 0.0, speed_in = 0.0;
  int outside = 0;
  const auto wheels = WheelPositions(car);
  for (long k = 0; k < 40000 && s.x < track.x_end + 40.0; ++k) {
    s = StepVehicle(car, s, driver.Step(car, s, 1e-3), 1e-3);
    if (s.x < track.x_start) speed_in = s.u;
    y_max = std::max(y_max, s.y);
    if (s.x > track.x_end + 30.0) y_after = s.y;
    for (const auto& wp : wheels) {
      const double wx = s.x + std::cos(s.yaw) * wp[0] - std::sin(s.yaw) * wp[1];
      const double wy = s.y + std::sin(s.yaw) * wp[0] + std::cos(s.yaw) * wp[1];
      for (int g = 0; g < 3; ++g) {
        const auto& r0 = track.right_cones[static_cast<std::size_t>(3 * g)];
        const auto& r1 = track.right_cones[static_cast<std::size_t>(3 * g + 2)];
        const auto& l0 = track.left_cones[static_cast<std::size_t>(3 * g)];
        if (wx >= r0.x && wx <= r1.x && (wy < r0.y || wy > l0.y)) ++outside;
      }
    }
  }
  EXPECT_NEAR(speed_in, v, 1.0);
  EXPECT_NEAR(y_max, track.lane_offset, 0.5);
  EXPECT_NEAR(y_after, 0.0, 0.3);
  EXPECT_EQ(outside, 0);
}

}  // namespace
}  // namespace pwsim::vehicle
