#pragma once
// Where the car's controls come from: time tables (scene files), a recorded drive (CSV), or a
// closed-loop driver that follows a path and a speed profile, shifting gears like a driving
// instructor (clutch in, change, clutch out) and launching from standstill without stalling.
//
//   InputTables tables = ParseInputTables(scene.Map("inputs"));   DriverInput in = tables.At(t);
//   InputTables drive = ReadRecordedDrive("drive.csv");
//   PathDriver driver(params, path, speed_profile);   DriverInput in = driver.Step(car, state, dt);

#include <filesystem>
#include <string>
#include <vector>

#include "engine/vehicle/vehicle_model.h"
#include "engine/yaml_reader.h"

namespace pwsim::vehicle {

/// One channel: (t, value) knots, rising t; linear between knots (`hold` = stepwise: the value
/// of the last knot at or before t), held before the first and after the last.
struct Channel {
  std::vector<double> t;
  std::vector<double> value;
  bool hold{false};
  double At(double time) const;
};

/// Time tables of all five controls; absent channels stay 0 (gear: neutral).
struct InputTables {
  Channel throttle, brake, clutch, gear, steer;
  DriverInput At(double time) const;
  /// Last knot time over all channels [s].
  double EndTime() const;
};

/// Reads `{throttle: [[t_s, value], ...], brake: ..., clutch: ..., gear: [[t_s, gear], ...],
/// steer_rad: [[t_s, rad], ...]}` (or `steer_deg`). Values are range-checked.
InputTables ParseInputTables(YamlMap& map, int gear_count);

/// Reads a recorded drive: CSV with header `t_s,throttle,brake,clutch,gear,steer_rad` (any
/// order, all six), rising t_s. @throws InputError naming file, line and column.
InputTables ReadRecordedDrive(const std::filesystem::path& file, int gear_count);

/// CSV text of a recorded drive (the format ReadRecordedDrive reads; shortest round-trip
/// numbers, so a replay reproduces the controls exactly). @pre t.size() == inputs.size().
std::string RecordedDriveCsv(const std::vector<double>& t, const std::vector<DriverInput>& inputs);

/// Closed-loop driver.
struct PathPoint {
  double x{0.0}, y{0.0};  ///< [m] in W
};
/// Target speed at a distance along the path (linear between points, held beyond).
struct SpeedPoint {
  double s{0.0};  ///< [m] along the path
  double v{0.0};  ///< [m/s]
};

struct PathDriverParams {
  double preview_time{0.9};      ///< [s] look-ahead = max(min_preview, v·preview_time)
  double min_preview{5.0};       ///< [m]
  double speed_gain{0.35};       ///< [1/(m/s)] throttle per m/s of speed error
  double speed_integral{0.08};   ///< [1/m] throttle per m of integrated speed error
  double brake_gain{0.25};       ///< [1/(m/s)] brake per m/s of overspeed beyond the band
  double brake_band{0.5};        ///< [m/s] overspeed left to engine braking (no brake)
  double max_brake{0.5};         ///< [-] most brake pedal used (short of locking the wheels)
  double brake_rate{1.5};        ///< [1/s] fastest brake pedal application (release is instant)
  double clutch_rate{8.0};       ///< [1/s] fastest clutch pedal travel, either way
  double upshift_rpm{3000.0};
  double downshift_rpm{1300.0};
  double shift_time{0.7};        ///< [s] clutch in, change, clutch out
  double launch_rpm{1800.0};     ///< engine speed held while the clutch comes up
  double launch_time{1.5};       ///< [s] clutch pedal travel from free to engaged
  double stop_speed{3.0};        ///< [m/s] below this, when slowing to 0, the clutch goes in
  int top_gear{0};               ///< highest gear used (0 = all)
};

class PathDriver {
 public:
  PathDriver(PathDriverParams params, std::vector<PathPoint> path, std::vector<SpeedPoint> speed);

  /// Starts already rolling in `gear` (clutch engaged), as a test that begins at speed.
  void StartRolling(int gear);
  /// The controls for this tick from the current state; advances the driver's own state.
  DriverInput Step(const Vehicle& car, const VehicleState& state, double dt);
  /// The same before the brake-pedal rate limit.
  DriverInput Decide(const Vehicle& car, const VehicleState& state, double dt);

  double progress() const { return progress_; }   ///< [m] along the path (nearest point)
  double lateral_error() const { return lateral_error_; }  ///< [m] left of the path positive
  double TargetSpeed(double s) const;
  double path_length() const { return cumulative_.back(); }

 private:
  enum class Mode { kStopped, kLaunch, kDrive, kShift };
  PathPoint PointAt(double s) const;

  PathDriverParams params_;
  std::vector<PathPoint> path_;
  std::vector<double> cumulative_;
  std::vector<SpeedPoint> speed_;
  Mode mode_{Mode::kStopped};
  int gear_{0};
  int next_gear_{0};
  double timer_{0.0};
  double brake_{0.0};  ///< brake pedal of the last tick
  double clutch_{1.0}; ///< clutch pedal of the last tick
  double integral_{0.0};
  std::size_t segment_{0};
  double progress_{0.0};
  double lateral_error_{0.0};
};

/// ISO 3888-1 double lane change track for a car `width` wide, starting at x0 along +x:
/// sections of 15, 30, 25, 25, 15, 15 m; lane widths 1.1 w + 0.25, 1.2 w + 0.25 and
/// 1.3 w + 0.25 m; section 3's right cone row 3.5 m left of section 1's; sections 1, 5 and 6
/// share their right cone row.
struct LaneChangeTrack {
  std::vector<PathPoint> left_cones, right_cones;
  std::vector<PathPoint> centre;   ///< a smooth centre path through the gates (driver's line)
  double lane_offset{0.0};         ///< [m] centre of section 3 left of section 1's centre
  double x_start{0.0}, x_end{0.0}; ///< [m] first and last cone rows
};
LaneChangeTrack MakeIso3888Track(double width, double x0, double run_in, double run_out);

}  // namespace pwsim::vehicle
