#pragma once
// What a session measured: cycle lateness and jitter, visual/platform skew, clock offset,
// receive and safety counters, how it stopped, and the peak commands (JSON report).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hardware/hmd_protocol.h"
#include "hardware/safety_supervisor.h"

namespace pwsim::hw {

struct Percentiles {
  std::size_t n{0};
  double p50{0}, p99{0}, max{0}, mean{0}, stddev{0};
};
Percentiles ComputePercentiles(std::vector<double> values);

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
  std::string final_state;
  std::string stop_reason;
  std::int64_t stop_tick{-1};
  std::int64_t parked_tick{-1};
  std::array<double, 2> peak_abs_command{};
  std::array<double, 2> peak_abs_measured{};
  std::array<double, 2> peak_abs_command_velocity{};
  std::array<double, 2> peak_abs_command_accel{};
  bool limits_ok{true};
  std::string ToJson() const;
};

}  // namespace pwsim::hw
