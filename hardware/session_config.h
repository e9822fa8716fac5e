#pragma once
// Session configuration: rates, timeouts, safety and master settings, and its log-header form
// ("key=value ...") so that a replay rebuilds the same core.

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "hardware/cia402_master.h"
#include "hardware/safety_supervisor.h"

namespace pwsim::hw {

/// A platform setpoint from the MCA: q1 yaw [rad], q2 rail [m] at an engine tick.
struct PlatformSetpoint {
  std::int64_t tick{0};
  std::array<double, kPlatformAxes> position{};
  bool operator==(const PlatformSetpoint&) const = default;
};

struct SessionConfig {
  int clock_rate_hz{1000};
  int drive_cycle_ticks{4};     ///< 4 ms SYNC at 1 kHz
  int frame_ticks{10};          ///< 100 Hz visual frames
  int ping_every_frames{10};
  std::int64_t run_ticks{5000}; ///< stop request (soft stop to neutral) at this tick
  std::int64_t max_stop_ticks{15000};  ///< give up waiting for park after this many more
  std::int64_t hmd_timeout_ns{250'000'000};  ///< a frame unanswered by a head pose this long: HMD stale
  bool hmd_required{true};
  std::uint32_t session_id{1};
  SafetyConfig safety;
  MasterConfig master;

  std::string Validate() const;
  /// "key=value ..." for the log header, and back.
  std::string ToHeader() const;
  static std::optional<SessionConfig> FromHeader(const std::string& header, std::string* error);
};

}  // namespace pwsim::hw
