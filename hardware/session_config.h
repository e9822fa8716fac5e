#pragma once
// Session configuration: rates, timeouts, safety and master settings, and its log-header form
// ("key=value ...") so that a replay rebuilds the same core.

#include <cstdint>
#include <optional>
#include <string>

#include "hardware/cia402_master.h"
#include "hardware/drive_axes.h"
#include "hardware/safety_supervisor.h"
#include "mca/mechanism.h"

namespace pwsim::hw {

/// The first line of a session log: this magic, a space, then SessionConfig::ToHeader().
inline constexpr const char* kSessionLogMagic = "# pwsim-session-log/2";

/// The supervisor's limits for a mechanism's actuators, one axis each (node = 1 + index):
///   hard range [hard_min, hard_max] = the actuator's stroke; an unlimited rotary stage gets the
///     session's own range, neutral ± 30° (the car's yaw: seed 001's is "theoretically infinite");
///   [min, max] = the hard range less a margin of 1/24 of it at each end (the car's rail:
///     ±0.6 m -> ±0.55 m), 1° for an unlimited rotary stage (±29°);
///   velocity, accel = the actuator's speed and acceleration; jerk = 2 accel / dt: the
///     acceleration may swing across its whole range in one drive cycle, as the MCA's own actuator
///     limiter does (bang-bang at the limits: a tighter jerk makes the supervisor rate-limit
///     feasible cues and trail them, by 22 mm on pw4dof's legs with accel / (2 dt));
///   soft stop: 1/4 of the speed, 1/10 of the acceleration, jerk = the acceleration per second
///     (the soft stop's acceleration swings in 0.1 s);
///   neutral = the actuator's position at the neutral pose (inverse kinematics).
SafetyConfig SafetyConfigFor(const mca::Mechanism& mechanism, double dt);
/// One axis per actuator: node 1 + index, 10^6 counts per m or rad.
MasterConfig MasterConfigFor(const mca::Mechanism& mechanism);

struct SessionConfig {
  int clock_rate_hz{1000};
  int drive_cycle_ticks{4};     ///< 4 ms SYNC at 1 kHz
  int frame_ticks{10};          ///< 100 Hz visual frames
  int ping_every_frames{10};
  std::int64_t run_ticks{5000}; ///< stop request (soft stop to neutral) at this tick
  std::int64_t max_stop_ticks{15000};  ///< give up waiting for park after this many more
  /// A drive whose feedback is lost is waited for this long (engine ticks) to come back and be
  /// re-admitted before the session gives up on it; counted from the loss.
  std::int64_t drive_return_ticks{5000};
  std::int64_t hmd_timeout_ns{250'000'000};  ///< a frame unanswered by a head pose this long: HMD stale
  bool hmd_required{true};
  std::uint32_t session_id{1};
  /// The platform: its name (for the record) and its mechanism (the drives, the kinematics).
  /// Default: seed 001's car, node 1 = yaw, node 2 = rail.
  std::string platform{"car2dof"};
  mca::Mechanism mechanism{DefaultMechanism()};
  SafetyConfig safety{SafetyConfigFor(mechanism, static_cast<double>(drive_cycle_ticks) / clock_rate_hz)};
  MasterConfig master{MasterConfigFor(mechanism)};
  /// The drives' measured feedback: parked when every drive is within this of neutral [m | rad]
  /// and at rest within rest_velocity_tolerance [m/s | rad/s].
  double park_measured_tolerance{1e-3};
  double rest_velocity_tolerance{2e-3};
  /// within_limits: a measured speed may exceed the actuator's speed limit by this fraction
  /// (the servo's overshoot when the command runs at the limit).
  double velocity_tolerance{0.05};

  /// The car 2-DoF platform's mechanism (mca::MakeCar2DofPlatform).
  static mca::Mechanism DefaultMechanism();
  /// Drives `mechanism` (named `name`): its safety limits and master configuration for the
  /// current drive cycle (SafetyConfigFor, MasterConfigFor); the master's timing is kept.
  void SetPlatform(const std::string& name, const mca::Mechanism& mechanism);
  int axis_count() const { return master.axis_count; }
  std::string Validate() const;
  /// "key=value ..." for the log header, and back.
  std::string ToHeader() const;
  static std::optional<SessionConfig> FromHeader(const std::string& header, std::string* error);
};

}  // namespace pwsim::hw
