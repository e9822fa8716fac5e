#pragma once
// The immersive session as a deterministic core plus a real-time runner.
//
// SessionCore::Step(tick, inputs) is a pure function of its inputs and state: the wall clock,
// every received CAN frame and HMD datagram (with its receive time), the MCA pose command and
// the camera pose all come in as inputs. The runner (session_runner.h) logs every input and
// every output line; `pwsim replay LOG` feeds the logged inputs back through a fresh core and
// checks that every output line comes out identical, bit for bit.
//
// The platform is a mechanism (mca/mechanism.h, SessionConfig::mechanism) of N actuators, one
// CiA 402 drive each (node = 1 + the actuator's index). Per engine tick: platform work on ticks
// that are multiples of drive_cycle_ticks: the MCA pose command -> actuator setpoints by inverse
// kinematics -> safety supervisor (actuator space) -> CiA 402 master -> RPDOs + SYNC, and the
// measured actuator positions -> the measured pose by forward kinematics; visual work on
// multiples of frame_ticks (CAMERA_POSE to the headset, PING every ping_every_frames frames).
// Motion compensation removes the measured pose (all six axes) interpolated at the head pose's
// sample time.
//
// Truth about the drives. The session ends on what the drives report, not on what it
// commanded: it finishes (disables the drives, says BYE) when
//   - the supervisor parked and every drive's fresh feedback (TPDO1 within tpdo_timeout_cycles)
//     shows it operation enabled, within park_measured_tolerance of neutral and at rest
//     (|v| <= rest_velocity_tolerance)                                       -> "parked"
//   - a latched fault and every drive's fresh feedback at rest               -> "fault"
//   - the drives' feedback has been lost for drive_return_ticks              -> "feedback-lost"
//   - it waited max_stop_ticks after the stop began                          -> from the feedback
//   - it never started and a stop was requested                              -> "not-started"
// final_state is read from the drives at that moment: "feedback-lost" (a drive's feedback is
// not fresh), "fault" (a drive in fault, or the supervisor's latched fault), "quick-stop" (a
// drive in quick stop), "parked", else "not-parked". The report lists what each drive last
// said (state, statusword, position, velocity, age of its last feedback) and every drive event
// (feedback lost, restarts, re-admissions, quick stops, faults); SessionReport::ExitStatus says
// how a session that lost its drives, or whose drives quick-stopped or faulted, never exits 0.
//
// After a re-admission (cia402_master.h: a drive's boot-up or a returning heartbeat -> start-up
// again), the session does not resume the cueing: the supervisor is in its soft stop, holds
// while the drives are walked back to operation enabled (each held at its actual position),
// then ramps from the measured positions to neutral under the comfort limits and parks; the
// session then finishes as above ("parked", exit status 6: parked after drive trouble).
//
// Log lines (text, numbers round-trip exact; N = the number of drive axes, from the header):
//   header:  # pwsim-session-log/2 key=value ... (SessionConfig::ToHeader: timing, limits,
//            nodes and the mechanism)
//   inputs:  T tick now_ns scheduled_ns | C rx_ns ID#DATA | H rx_ns hex |
//            M tick pose(6: surge sway heave [m] roll pitch yaw [rad]) | K tick pose(7) |
//            X tick (stop request)
//   outputs: c ID#DATA | h hex |
//            S tick cycle setpoint(N) command(N) measured(N) measured_pose(6) state phase
//              (setpoint: inverse kinematics of the M pose, nan when none or not computable;
//               measured_pose: forward kinematics of the measured positions) |
//            P tick t_sample_local_ns raw(7) compensated(7) | E tick text

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
#include "mca/dof.h"
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
  std::optional<mca::DofArray> setpoint;  ///< the MCA's pose command, on drive ticks
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

/// The platform top's motion in the room for a pose x (mca/mechanism.h):
/// X_BP(x) · X_BP(0)⁻¹ = Rz(ψ) · Trans(s, w, h₀ + z) · Ry(−θ) · Rx(φ) · Trans(0, 0, −h₀), identity
/// at neutral; for the car's rail + yaw, Rz(q1) · Tx(q2) (seed 001's RP chain).
Pose PlatformMotion(const mca::DofArray& pose, double pivot_height);

/// Step allocates nothing once constructed (tests/hardware/session_alloc_test.cc), given an
/// `out` reused from step to step: the per-session histories are reserved up front for the
/// longest session the configuration allows (run_ticks + max_stop_ticks, capped at about
/// 70 min of 1 kHz ticks, beyond which they grow), log lines are formatted into `out->log`, and
/// the kinematics work on fixed-capacity vectors.
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
  /// The last measured pose (forward kinematics of the measured actuator positions).
  const mca::DofArray& measured_pose() const { return measured_pose_; }

 private:
  void HandleHmd(std::int64_t tick, const RxDatagram& d, SessionOutputs* out);
  void SendHmd(HmdBody body, std::int64_t now_ns, SessionOutputs* out);
  mca::DofArray MeasuredAt(std::int64_t local_ns) const;
  /// Drive events since the last cycle (master axis status) as E lines, counted in the report.
  void LogDriveEvents(std::int64_t tick, SessionOutputs* out);
  /// What the drives say now (the rules in the header comment).
  const char* FinalStateFromDrives() const;

  SessionConfig config_;
  SafetySupervisor supervisor_;
  Cia402Master master_;
  ClockOffsetEstimator offset_;
  HmdReceiveFilter hmd_filter_;
  int n_{0};                ///< drive axes
  int yaw_axis_{-1};        ///< the stage actuator on yaw / surge (for CAMERA_POSE), -1: none
  int surge_axis_{-1};
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
  bool finishing_{false};
  const char* final_state_{"not-started"};
  std::int64_t stop_since_tick_{-1};
  std::int64_t lost_since_tick_{-1};  ///< drive feedback not fresh since (-1: fresh)
  std::int64_t disable_ticks_{0};
  std::int64_t last_drive_now_ns_{-1};
  SupervisorState last_state_{SupervisorState::kIdle};
  MasterPhase last_phase_{MasterPhase::kResetComm};
  std::vector<double> lateness_us_;
  std::vector<double> period_jitter_us_;
  std::vector<std::int64_t> platform_rx_ns_;     ///< first axis' TPDO answering each SYNC (or -1)
  std::vector<std::int64_t> frame_shown_ns_;     ///< its arrival at the headset (local clock)
  /// Measured pose history (for compensation): step times [ns, as double] and poses.
  std::vector<double> measured_ns_;
  std::vector<mca::DofArray> measured_poses_;
  mca::DofArray measured_pose_{};     ///< the last forward kinematics (and its next guess)
  bool measured_all_{false};          ///< every drive answered at least once
  std::array<std::int64_t, kMaxDriveAxes> feedback_rx_ns_{};  ///< each drive's last TPDO1 (-1: none)
  std::array<AxisStatus, kMaxDriveAxes> last_axis_{};         ///< master status at the last cycle
  std::array<std::array<double, 3>, kMaxDriveAxes> last_cmd_{};  ///< p, v, a history for limit checks
  SessionReport report_;        ///< stop_reason is filled in by Report()
  std::string_view stop_reason_;  ///< the supervisor's (static) reason text
  std::int64_t last_tick_{0};
  std::int64_t last_now_ns_{0};
  std::int64_t steps_{0};
};

}  // namespace pwsim::hw
