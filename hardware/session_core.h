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
#include <optional>
#include <span>
#include <string_view>
#include <string>
#include <vector>

#include "hardware/can_frame.h"
#include "hardware/cia402_master.h"
#include "hardware/hmd_protocol.h"
#include "hardware/safety_supervisor.h"
#include "hardware/session_config.h"
#include "hardware/session_report.h"
#include "hardware/session_text.h"

namespace pwsim::hw {

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

/// One HMD datagram the core sends, stored inline (no heap).
struct HmdDatagram {
  std::array<std::uint8_t, kHmdMaxSize> data{};
  std::size_t size{0};
  std::span<const std::uint8_t> bytes() const { return {data.data(), size}; }
};

/// What one step produced. Storage is reserved on construction and kept by Clear(), so a
/// SessionOutputs reused from step to step lets Step run without allocating.
struct SessionOutputs {
  SessionOutputs() {
    can.reserve(64);
    hmd.reserve(16);
  }
  std::vector<CanFrame> can;
  std::vector<HmdDatagram> hmd;
  LogLines log;  ///< output log lines (without the inputs)
  void Clear() {
    can.clear();
    hmd.clear();
    log.clear();
  }
};

/// Step allocates nothing once constructed (tests/hardware/session_alloc_test.cc), given an
/// `out` reused from step to step: the per-session histories are reserved up front for the
/// longest session the configuration allows (run_ticks + max_stop_ticks, capped at about
/// 70 min of 1 kHz ticks, beyond which they grow), and log lines are formatted into `out->log`.
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
  /// When the oldest camera pose still without a head pose after it was sent (-1: none). The
  /// HMD is stale when that wait exceeds hmd_timeout_ns: counted from a frame the headset
  /// could answer, so a session that itself paused (lockstep wait, a descheduled process)
  /// does not blame the headset for the frames it never sent.
  std::int64_t awaiting_head_since_ns_{-1};
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
  std::vector<std::int64_t> platform_rx_ns_;     ///< rail TPDO answering each of them (or -1)
  std::vector<std::int64_t> frame_shown_ns_;     ///< its arrival at the headset (local clock)
  /// Platform pose history (for compensation): step times [ns, as double] and positions.
  std::vector<double> measured_ns_;
  std::vector<std::array<double, 2>> measured_q_;
  std::array<std::array<double, 3>, 2> last_cmd_{};  ///< p, v, a history for limit checks
  SessionReport report_;        ///< stop_reason is filled in by Report()
  std::string_view stop_reason_;  ///< the supervisor's (static) reason text
  std::int64_t last_tick_{0};
  std::int64_t steps_{0};
};

}  // namespace pwsim::hw
