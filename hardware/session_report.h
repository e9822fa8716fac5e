#pragma once
// What a session measured: cycle lateness and jitter, visual/platform skew, clock offset,
// receive and safety counters, how it stopped, and the peak commands (JSON report).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hardware/drive_axes.h"

#include "hardware/hmd_protocol.h"
#include "hardware/safety_supervisor.h"

namespace pwsim::hw {

struct Percentiles {
  std::size_t n{0};
  double p50{0}, p99{0}, max{0}, mean{0}, stddev{0};
};
Percentiles ComputePercentiles(std::vector<double> values);

/// One drive axis: what was commanded and measured over the session, and what the drive last
/// said at the end.
struct AxisReport {
  std::string actuator;          ///< the mechanism's name for it ("yaw", "leg_front_left", ...)
  std::string unit;              ///< "m" or "rad"
  int node{0};
  double stroke_min{0.0}, stroke_max{0.0};  ///< the mechanical ends (hard limits)
  double speed{0.0};             ///< the actuator's speed limit
  double command_min{0.0}, command_max{0.0};
  double peak_command_velocity{0.0};  ///< |finite differences| of the streamed positions
  double peak_command_accel{0.0};
  double measured_min{0.0}, measured_max{0.0};  ///< measured positions (TPDO1)
  double peak_measured_velocity{0.0};           ///< |measured velocity| (TPDO2)
  bool measured{false};          ///< the drive answered at least once
  // the end:
  std::string state;             ///< CiA 402 state of the last statusword
  std::string nmt;               ///< NMT state as last heard
  std::uint16_t statusword{0};
  double position{0.0};          ///< last measured
  double velocity{0.0};
  double feedback_age_ms{-1.0};  ///< from its last TPDO1 to the session's last step (-1: never)
  std::uint16_t last_emcy_code{0};
  std::uint64_t restarts{0};     ///< boot-ups after the start-up
  std::uint64_t returns{0};      ///< heartbeats back after a loss (reset and started again)
  std::uint64_t readmissions{0}; ///< operation enabled again after a restart or return
};

/// Drive trouble over the session (each counted when it began).
struct DriveEvents {
  std::uint64_t feedback_lost{0};   ///< the drives' feedback went stale while streaming
  std::uint64_t heartbeat_lost{0};
  std::uint64_t restarts{0};
  std::uint64_t returns{0};
  std::uint64_t readmissions{0};
  std::uint64_t quick_stops{0};
  std::uint64_t faults{0};
  std::uint64_t total() const { return feedback_lost + heartbeat_lost + restarts + returns + quick_stops + faults; }
};

struct SessionReport {
  std::int64_t ticks{0};
  std::int64_t steps{0};
  Percentiles cycle_lateness_us;   ///< wake time minus scheduled time of each step
  Percentiles cycle_period_jitter_us;  ///< |period - nominal| between drive-cycle steps
  /// Steps that woke more than half a drive cycle late, after which the runner's schedule
  /// slipped rather than catching up (session_runner.h), and the total slip. Filled in by
  /// the runner; 0 in a replay.
  std::int64_t schedule_slips{0};
  double schedule_slip_ms{0.0};
  /// Datagrams read and dropped because they came from a sender other than the link's peer
  /// (udp_socket.h), per link. Filled in by the runner (they never reach the log); 0 in a replay.
  std::uint64_t can_rx_refused{0};
  std::uint64_t hmd_rx_refused{0};
  /// A live input (joystick) drove the session: latency from each new reading reaching the
  /// process to the first platform command / HMD frame computed from it leaving (ms;
  /// input_latency.h). Filled in by the runner; in the JSON only when has_live_input.
  bool has_live_input{false};
  Percentiles input_to_platform_ms;
  Percentiles input_to_hmd_ms;
  Percentiles skew_ms;             ///< visual frame shown minus platform moved (signed)
  Percentiles abs_skew_ms;
  std::int64_t clock_offset_ns{0};
  std::int64_t clock_rtt_ns{0};
  HmdRxCounters hmd_rx;
  SafetyCounters safety;
  std::string platform;            ///< the platform's name (SessionConfig::platform)
  /// From the drives' measured feedback (session_core.h): parked, fault, quick-stop,
  /// feedback-lost, not-parked, not-started.
  std::string final_state;
  std::string supervisor_state;    ///< the supervisor's own state at the end
  std::string stop_reason;
  std::int64_t stop_tick{-1};
  std::int64_t parked_tick{-1};    ///< when the drives' feedback showed the platform parked
  std::vector<AxisReport> axes;
  DriveEvents drive_events;
  /// Largest |pose| per axis measured by forward kinematics of the measured actuator positions
  /// (surge, sway, heave [m], roll, pitch, yaw [rad]).
  std::array<double, 6> peak_abs_measured_pose{};
  /// Worst inconsistency of the measured lengths while the drives were enabled (forward
  /// kinematics' residual) [m | rad].
  double fk_residual_max{0.0};
  double fk_residual_tracking_max{0.0};  ///< the same while the supervisor ran (tracking the MCA)
  std::uint64_t ik_failures{0};    ///< pose commands the inverse kinematics refused
  /// Every streamed position inside [min, max] and within the velocity, acceleration limits
  /// (finite differences).
  bool limits_ok{true};
  /// Every measured actuator position inside its stroke (no tolerance) and every measured
  /// speed within speed x (1 + velocity_tolerance).
  bool within_limits{true};
  double velocity_tolerance{0.0};
  /// 0: parked at neutral by the drives' feedback, no drive trouble, limits kept;
  /// 3: not parked (timed out), never started, or a limit exceeded;
  /// 4: a fault (a drive's, or bus-off) at the end;
  /// 5: the drives' feedback lost at the end, or a drive in quick stop;
  /// 6: parked, but after drive trouble (feedback lost, restart, quick stop, fault).
  int ExitStatus() const;
  std::string ToJson() const;
};

}  // namespace pwsim::hw
