#include "engine/circuit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "engine/input_error.h"
#include "engine/scene.h"

namespace pwsim {
namespace {

const std::filesystem::path kLabel = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes" / "circuit_test.yaml";

std::string SceneText(const std::string& circuit) {
  return "format: pwsim-scene/1\nname: circuit_test\nchair: ../assets/chairs/table1_pw6.yaml\nload_kg: 100\n"
         "circuit:\n" + circuit;
}

Scene Parse(const std::string& circuit) { return ParseScene(SceneText(circuit), kLabel); }

/// Expects an InputError whose field is `field`, on `line` (1-based in the whole scene text).
void ExpectError(const std::string& circuit, const std::string& field, int line, const std::string& words) {
  try {
    Parse(circuit);
    FAIL() << "accepted:\n" << circuit;
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), field) << error.what();
    if (line > 0) {
      EXPECT_EQ(error.line(), line) << error.what();
    }
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
  }
}

// Tests that a chair driven straight at a wall stops at it: one contact, counted with its speed,
// the footprint never overlaps the wall, and the chair stays stopped while the joystick pushes.
TEST(CircuitTest, ChairStopsAtAWallAndTheContactIsCounted) {
  const Scene scene = Parse(
      "  duration_s: 8\n"
      "  walls: [{name: end, from_m: [4, -2], to_m: [4, 2], thickness_m: 0.1}]\n"
      "  joystick: {table: [[0, 0.6, 0], [8, 0.6, 0]]}\n");
  const std::vector<FullChairSample> run = SimulateCircuitScene(scene);
  const double front = scene.circuit->layout.footprint_front;
  int entered = 0;
  for (std::size_t k = 1; k < run.size(); ++k) {
    ASSERT_LE(run[k].planar.x + front, 4.0 - 0.05 + 1e-12) << k;
    entered += run[k].in_contact && !run[k - 1].in_contact;
  }
  EXPECT_EQ(run.back().contact_events, 1);
  EXPECT_EQ(entered, 1);
  EXPECT_NEAR(run.back().planar.x + front, 3.95, 0.003);
  EXPECT_GT(run.back().last_contact_speed, 0.8);  // at cruise speed, 0.6 deflection ≈ 0.93 m/s
  EXPECT_LT(run.back().last_contact_speed, 1.0);
}

// Tests the closed-loop driver through a slalom of gates between obstacles: every gate passed
// in order, no contact, and the run is the same bits twice.
TEST(CircuitTest, DriverPassesTheSlalomGatesWithoutContact) {
  const std::string circuit =
      "  duration_s: 25\n"
      "  obstacles:\n"
      "    - {name: c1, shape: circle, centre_m: [2.5, 0.0], radius_m: 0.15}\n"
      "    - {name: c2, shape: circle, centre_m: [5.0, 0.0], radius_m: 0.15}\n"
      "    - {name: c3, shape: box, centre_m: [7.5, 0.0], size_m: [0.3, 0.3]}\n"
      "  gates:\n"
      "    - {left_m: [2.5, 1.8], right_m: [2.5, 0.3]}\n"
      "    - {left_m: [5.0, -0.3], right_m: [5.0, -1.8]}\n"
      "    - {left_m: [7.5, 1.8], right_m: [7.5, 0.3]}\n"
      "  joystick: {driver: {speed_mps: 0.6, lookahead_m: 0.8}}\n";
  const Scene scene = Parse(circuit);
  const std::vector<FullChairSample> run = SimulateCircuitScene(scene);
  EXPECT_EQ(run.back().gates_passed, 3);
  EXPECT_EQ(run.back().contact_events, 0);
  const std::vector<FullChairSample> again = SimulateCircuitScene(Parse(circuit));
  ASSERT_EQ(run.size(), again.size());
  for (std::size_t k = 0; k < run.size(); k += 97) {
    ASSERT_EQ(run[k].planar, again[k].planar);
    ASSERT_EQ(run[k].lm, again[k].lm);
  }
}

// Tests a recorded joystick CSV: values are replayed (linear between rows), and NaN or
// out-of-range deflections name the file, the line and the column.
TEST(CircuitTest, RecordedJoystickIsReadAndCheckedPerCell) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "circuit_joystick";
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  const JoystickSource ok = ReadRecordedJoystick(write("ok.csv", "t_s,turn,forward\n0,0,0\n1,0.5,1\n"));
  EXPECT_DOUBLE_EQ(ok.At(0.5).forward, 0.5);
  EXPECT_DOUBLE_EQ(ok.At(0.5).turn, 0.25);
  const auto expect = [&](const std::string& name, const std::string& text, int line, const std::string& field) {
    try {
      ReadRecordedJoystick(write(name, text));
      FAIL() << name;
    } catch (const InputError& error) {
      EXPECT_EQ(error.line(), line) << error.what();
      EXPECT_EQ(error.field(), field) << error.what();
      EXPECT_NE(error.file().find(name), std::string::npos);
    }
  };
  expect("nan.csv", "t_s,forward,turn\n0,0,0\n0.5,nan,0\n", 3, "forward");
  expect("range.csv", "t_s,forward,turn\n0,0,0\n0.5,0.2,-1.3\n", 3, "turn");
  expect("time.csv", "t_s,forward,turn\n0,0,0\n0,0.2,0\n", 3, "t_s");
  expect("column.csv", "t_s,forward,steer\n0,0,0\n", 1, "steer");
}

// Tests the bad scene inputs of the issue: each names file, line, field and what was expected.
TEST(CircuitTest, BadCircuitsAreErrorsNamingFieldAndExpectation) {
  // scene header is 5 lines; the circuit's own lines follow from line 6
  ExpectError("  duration_s: 5\n"
              "  walls:\n"
              "    - {name: a, from_m: [0, 2], to_m: [6, 2]}\n"
              "    - {name: b, from_m: [3, 0.5], to_m: [3, 4]}\n"
              "  joystick: {table: [[0, 0, 0]]}\n",
              "circuit.walls[1]", 9, "overlaps");
  ExpectError("  duration_s: 5\n"
              "  walls:\n"
              "    - {name: a, from_m: [0, 2], to_m: [6, 2]}\n"
              "    - {name: b, from_m: [4, 2], to_m: [8, 2]}\n"
              "  joystick: {table: [[0, 0, 0]]}\n",
              "circuit.walls[1]", 9, "overlaps");
  ExpectError("  duration_s: 5\n"
              "  walls: [{name: w, from_m: [3, -2], to_m: [3, 2]}]\n"
              "  gates: [{left_m: [5, 1], right_m: [5, -1]}]\n"
              "  joystick: {table: [[0, 0, 0]]}\n",
              "circuit.gates[0]", 8, "goes through 'w'");
  ExpectError("  duration_s: 5\n"
              "  walls: [{name: w, from_m: [3, -2], to_m: [3, 2]}]\n"
              "  joystick:\n"
              "    driver: {speed_mps: 0.5, path_m: [[0, 0], [5, 0]]}\n",
              "circuit.joystick.driver.path_m", 9, "goes through 'w'");
  ExpectError("  duration_s: 5\n"
              "  joystick: {table: [[0, 0, 0], [1, 1.5, 0]]}\n",
              "circuit.joystick.table[1][1]", 7, "[-1, 1]");
  ExpectError("  duration_s: 5\n"
              "  joystick: {table: [[0, 0, 0], [1, .nan, 0]]}\n",
              "circuit.joystick.table[1][1]", 7, "[-1, 1]");
  ExpectError("  duration_s: 5\n"
              "  controller: {turn_accel_degps2: -30}\n"
              "  joystick: {table: [[0, 0, 0]]}\n",
              "circuit.controller.turn_accel_degps2", 7, "positive");
  ExpectError("  duration_s: 5\n"
              "  floor: {grid: {origin_m: [0, 0], cell_m: 0.5, rows: [[0, 0], [0, .nan]]}}\n"
              "  joystick: {table: [[0, 0, 0]]}\n",
              "circuit.floor.grid.rows[1][1]", 7, "hole or NaN");
  ExpectError("  duration_s: 5\n"
              "  obstacles: [{name: pillar, shape: circle, centre_m: [0.3, 0], radius_m: 0.2}]\n"
              "  joystick: {table: [[0, 0, 0]]}\n",
              "circuit.start", 0, "pillar");
}

}  // namespace
}  // namespace pwsim

namespace pwsim {
namespace {

// Tests the shipped circuits: each loads, validates and runs; the course's driver passes the
// doorway, the slalom, the cross-slope and the kerb gates in order without touching anything,
// the kerb is climbed by the left wheels only (roll left side up, right contacts on the floor),
// the cross-slope rolls the chair; the room's drive ends with one counted wall contact.
TEST(ShippedCircuitsTest, CourseRoomAndRecordedDriveRun) {
  const std::filesystem::path scenes = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes";
  const Scene course = LoadScene(scenes / "circuit_course.yaml");
  ASSERT_TRUE(course.is_circuit());
  const std::vector<FullChairSample> run = SimulateCircuitScene(course);
  EXPECT_EQ(run.back().gates_passed, static_cast<int>(course.circuit->gates.size()));
  EXPECT_EQ(run.back().contact_events, 0);
  double kerb_roll = 0.0, slope_roll = 0.0, right_kerb_z = 0.0;
  for (const FullChairSample& s : run) {
    if (s.planar.x > 19.7 && s.planar.x < 20.3) {
      kerb_roll = std::max(kerb_roll, s.roll_gm);
      for (int i = 0; i < 3; ++i) right_kerb_z = std::max(right_kerb_z, s.contacts[2 * i + 1].z);
    }
    if (s.planar.x > 14.0 && s.planar.x < 16.0) slope_roll = std::max(slope_roll, s.roll_gm);
    ASSERT_FALSE(s.tip_over);
  }
  EXPECT_GT(kerb_roll, 0.8 * std::asin(0.05 / 0.56));  // left wheels 5 cm up
  EXPECT_EQ(right_kerb_z, 0.0);
  EXPECT_GT(slope_roll, 0.8 * std::asin(0.05));

  const std::vector<FullChairSample> room = SimulateCircuitScene(LoadScene(scenes / "circuit_room.yaml"));
  EXPECT_EQ(room.back().contact_events, 1);
  EXPECT_TRUE(room.back().in_contact);
  EXPECT_LT(room.back().last_contact_speed, 0.6);

  const Scene recorded = LoadScene(scenes / "circuit_recorded.yaml");
  EXPECT_EQ(recorded.circuit->joystick.kind, JoystickSource::Kind::kRecorded);
  const std::vector<FullChairSample> replay = SimulateCircuitScene(recorded);
  EXPECT_EQ(replay.back().contact_events, 0);
  EXPECT_GT(replay.back().distance, 10.0);
}

// Tests that the default scene of `pwsim run` is still the sagittal speed-cushion trial.
TEST(ShippedCircuitsTest, DefaultSceneStaysTheSpeedCushion) {
  const Scene scene = LoadScene(DefaultScenePath(PWSIM_SOURCE_DIR));
  EXPECT_FALSE(scene.is_circuit());
  EXPECT_EQ(scene.name, "speed_cushion");
}

}  // namespace
}  // namespace pwsim
