#pragma once
// Car scene: one trial of the car simulator of seed 001 as a file (`pwsim-scene/1` with
// `kind: car`, YAML under scenes/): the car, where its controls come from (time tables, a
// recorded drive, or the closed-loop driver on a route or the ISO 3888-1 track), the road, the
// driver's head, the clock. Sections owned by other libraries (mca, platform, render, session)
// are kept as YAML, as in the wheelchair scene (engine/scene.h).
//
//   if (SceneKind(path) == "car") { CarScene scene = LoadCarScene(path); auto run = SimulateCarScene(scene); }
//
// Head motion (MCA input) at the driver's head p_VH (from the CoG, in V), body with yaw rate r,
// roll φ (left up) and pitch θ (nose up), small roll/pitch angles:
//   a_H = (a_x - ṙ y_h - r² x_h - θ̈ z_h,  a_y + ṙ x_h - r² y_h - φ̈ z_h,  0)
//   fs_H = (a_H,x + g sin θ,  a_H,y + g sin φ,  g cos φ cos θ),   w_H = (φ̇, -θ̇, r)

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/yaml_reader.h"
#include "engine/clock.h"
#include "engine/scene.h"
#include "engine/vehicle/driver_inputs.h"
#include "engine/vehicle/vehicle_model.h"

namespace pwsim::vehicle {

/// The road drawn around the car (render) and used for the lane metrics.
struct Road {
  std::vector<PathPoint> centre;   ///< centreline of the right-hand lane pair, along the route
  double lane_width{3.5};          ///< [m]
  int lanes{2};                    ///< lanes side by side; the car starts in the rightmost
  std::vector<PathPoint> cones;    ///< cone positions in W
};

struct CarScene {
  std::filesystem::path file;
  std::string name{"car"};
  std::string description;
  Clock clock;
  std::filesystem::path vehicle_file;
  Vehicle car;
  double duration{10.0};           ///< [s]
  VehicleState start;
  int start_gear{0};               ///< gear engaged at t = 0 (rolling start when > 0)
  enum class Source { kTables, kRecordedDrive, kDriver };
  Source source{Source::kTables};
  InputTables tables;              ///< kTables and kRecordedDrive
  std::filesystem::path recorded_drive_file;
  PathDriverParams driver;         ///< kDriver
  std::vector<PathPoint> path;     ///< kDriver: the line to follow
  std::vector<SpeedPoint> speed;   ///< kDriver: target speed along the path
  Road road;
  std::array<double, 3> head_offset{0.3, 0.37, 0.65};  ///< p_VH [m] driver's head from the CoG
  std::map<std::string, SceneSection> sections;          ///< mca, platform, render, session

  std::int64_t tick_count() const { return clock.TicksFor(duration) + 1; }
  const SceneSection* section(const std::string& key) const;
};

/// "car" for a scene file with `kind: car`, "wheelchair" otherwise (also when `kind` is absent).
/// @throws InputError if the file cannot be read or `kind` is neither.
std::string SceneKind(const std::filesystem::path& file);
/// The same for a document already read (a scene is read once: it may come from a pipe).
std::string SceneKind(const YamlDocument& document);

/// Loads and validates a car scene. @throws InputError (file, line, field, expected).
CarScene LoadCarScene(const std::filesystem::path& file);
CarScene ParseCarScene(const std::string& yaml_text, const std::filesystem::path& label);
CarScene ParseCarScene(const YamlDocument& document);

/// One tick of a car run: the state after the tick's step and the inputs that led to it.
struct CarSample {
  std::int64_t tick{0};
  VehicleState state;
  DriverInput input;
  double road_wheel_angle{0.0};   ///< [rad]
  double throttle_effective{0.0}; ///< after idle control
  double engine_torque{0.0};      ///< [N m]
  double clutch_torque{0.0};      ///< [N m]
  double roll_accel{0.0};         ///< φ̈ [rad/s^2]
  double pitch_accel{0.0};        ///< θ̈ [rad/s^2]
};

/// Sample 0 of a run: the scene's start state (clutch released in its start gear, else pressed).
CarSample FirstCarSample(const CarScene& scene);

/// The sample after `previous` with `input` applied for one tick of `dt` (what
/// SimulateCarScene does per tick; a live loop calls it with the wheel's controls).
CarSample NextCarSample(const Vehicle& car, const CarSample& previous, const DriverInput& input, double dt);

/// Runs the scene on its clock: sample 0 is the start state, then one sample per tick.
std::vector<CarSample> SimulateCarScene(const CarScene& scene);

/// Specific force [m/s^2] and angular velocity [rad/s] at the head, in H (see above).
struct CarHeadMotion {
  std::array<double, 3> fs{0.0, 0.0, kGravity};
  std::array<double, 3> w{};
};
CarHeadMotion HeadMotionOfCar(const CarSample& sample, const std::array<double, 3>& head_offset);

/// A polyline along a route of straights and arcs from (x0, y0, heading0), one point per
/// `spacing` metres. A route item is {straight_m} or {turn_deg (left +), radius_m}.
struct RouteItem {
  double straight{0.0};  ///< [m]
  double turn{0.0};      ///< [rad], left positive (0 for a straight)
  double radius{0.0};    ///< [m]
};
std::vector<PathPoint> RoutePolyline(const std::vector<RouteItem>& route, double x0, double y0,
                                     double heading0, double spacing);

}  // namespace pwsim::vehicle
