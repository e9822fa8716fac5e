#pragma once
// The immersive session as a deterministic core plus a real-time runner.
//
// SessionCore::Step(tick, inputs) is a pure function of its inputs and state: the wall clock,
// every received CAN frame and HMD datagram (with its receive time), the MCA setpoint and the
// camera pose all come in as inputs. The runner (session_runner.h) logs every input and every
// output line; `pwsim replay LOG` feeds the logged inputs back through a fresh core and checks
// that every output line comes out identical, bit for bit.
//
// Per engine tick: platform work on ticks that are multiples of drive_cycle_ticks (safety
// supervisor -> CiA 402 master -> RPDOs + SYNC), visual work on multiples of frame_ticks
// (CAMERA_POSE to the headset, PING every ping_every_frames frames).
//
// Log lines (text, numbers round-trip exact):
//   inputs:  T tick now_ns scheduled_ns | C rx_ns ID#DATA | H rx_ns hex | M tick yaw rail | K tick pose(7) |
//            X tick (stop request)
//   outputs: c ID#DATA | h hex | S tick cycle sp_yaw sp_rail cmd_yaw cmd_rail meas_yaw meas_rail
//            state phase | P tick t_sample_local_ns raw(7) compensated(7) | E tick text

#include <array>
#include <cstdint>
#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "hardware/can_frame.h"
#include "hardware/cia402_master.h"
#include "hardware/hmd_protocol.h"
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
  std::int64_t hmd_timeout_ns{250'000'000};  ///< no head pose this long: HMD stale
  bool hmd_required{true};
  std::uint32_t session_id{1};
  SafetyConfig safety;
  MasterConfig master;

  std::string Validate() const;
  /// "key=value ..." for the log header, and back.
  std::string ToHeader() const;
  static std::optional<SessionConfig> FromHeader(const std::string& header, std::string* error);
};

struct RxFrame {
  std::int64_t rx_ns{0};
  CanFrame frame;
};
struct RxDatagram {
  std::int64_t rx_ns{0};
  std::vector<std::uint8_t> bytes;
};

struct SessionInputs {
  std::int64_t now_ns{0};        ///< when the step ran (CLOCK_MONOTONIC)
  std::int64_t scheduled_ns{0};  ///< when it was due (start + tick * dt)
  std::vector<RxFrame> can;
  std::vector<RxDatagram> hmd;
  std::optional<std::array<double, kPlatformAxes>> setpoint;  ///< on drive ticks
  std::optional<Pose> camera;                                 ///< on frame ticks
  bool stop_request{false};
};

struct SessionOutputs {
  std::vector<CanFrame> can;
  std::vector<std::vector<std::uint8_t>> hmd;
  std::vector<std::string> log;  ///< output log lines (without the inputs)
  void Clear() {
    can.clear();
    hmd.clear();
    log.clear();
  }
};

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

class SessionCore {
 public:
  explicit SessionCore(SessionConfig config);
  void Step(std::int64_t tick, const SessionInputs& in, SessionOutputs* out);
  bool done() const { return done_; }
  SessionReport Report() const;
  const SafetySupervisor& supervisor() const { return supervisor_; }
  const Cia402Master& master() const { return master_; }
  const SessionConfig& config() const { return config_; }
  bool is_drive_tick(std::int64_t tick) const { return tick % config_.drive_cycle_ticks == 0; }
  bool is_frame_tick(std::int64_t tick) const { return tick % config_.frame_ticks == 0; }

 private:
  void HandleHmd(std::int64_t tick, const RxDatagram& d, SessionOutputs* out);
  void SendHmd(HmdBody body, std::int64_t now_ns, SessionOutputs* out);
  std::array<double, 2> MeasuredAt(std::int64_t local_ns) const;

  SessionConfig config_;
  SafetySupervisor supervisor_;
  Cia402Master master_;
  ClockOffsetEstimator offset_;
  HmdReceiveFilter hmd_filter_;
  std::uint32_t hmd_seq_{0};
  bool hmd_seen_{false};
  bool hmd_bye_{false};
  std::int64_t last_head_rx_ns_{0};
  bool bus_off_{false};
  bool stop_request_{false};
  bool done_{false};
  std::int64_t stop_since_tick_{-1};
  std::int64_t disable_ticks_{0};
  std::int64_t last_sync_tick_{-1};
  std::int64_t last_drive_now_ns_{-1};
  SupervisorState last_state_{SupervisorState::kIdle};
  MasterPhase last_phase_{MasterPhase::kResetComm};
  std::vector<double> lateness_us_;
  std::vector<double> period_jitter_us_;
  std::vector<std::int64_t> sync_sent_tick_;     ///< ticks of SYNCs
  std::vector<std::int64_t> platform_rx_ns_;     ///< rail TPDO answering each of them (or -1)
  std::vector<std::int64_t> frame_tick_;         ///< tick of each visual frame
  std::vector<std::int64_t> frame_shown_ns_;     ///< its arrival at the headset (local clock)
  struct Measured {
    std::int64_t ns;
    std::array<double, 2> q;
  };
  std::vector<Measured> measured_;               ///< platform pose history (for compensation)
  std::array<std::array<double, 3>, 2> last_cmd_{};  ///< p, v, a history for limit checks
  SessionReport report_;
  std::int64_t last_tick_{0};
  std::int64_t steps_{0};
};

// --- log ------------------------------------------------------------------------------------
std::string HexEncode(std::span<const std::uint8_t> bytes);
bool HexDecode(std::string_view hex, std::vector<std::uint8_t>* bytes);
/// The input lines for one step (T, M, K, X, C, H), in the order Replay reads them.
void AppendInputLines(std::int64_t tick, const SessionInputs& in, std::vector<std::string>* lines);

struct ReplayResult {
  bool ok{false};
  std::int64_t steps{0};
  std::int64_t lines_compared{0};
  std::string message;  ///< first mismatch or parse error
  SessionReport report;
};
/// Re-runs a session log offline and compares every output line.
ReplayResult ReplaySessionLog(std::istream& log);

}  // namespace pwsim::hw
