#pragma once
// CiA 402 cyclic-synchronous-position (CSP) master for the platform's drives: one node per
// actuator (drive_axes.h; node = 1 + the actuator's index by default). Runs on drive cycles
// (integers), never on the wall clock, so it is deterministic and replayable:
//   each cycle: handle received frames (OnFrame), then Cycle() emits RPDO1 per axis + SYNC
//   (and the master heartbeat every `heartbeat_period_cycles`).
// Start-up: NMT reset-communication -> wait boot-up -> NMT start -> drives operational ->
// controlword walk 0x06, 0x07, 0x0F while holding the actual position -> kRunning, where the
// target position is the caller's setpoint. Heartbeat loss, EMCY and statusword faults are
// reported (not acted on): the safety supervisor decides.
//
// Re-admission of a drive that comes back. A boot-up (0x700+n, data 0x00) from a node after the
// start-up means the drive restarted: its state is "switch on disabled", its NMT state
// pre-operational, its feedback void until it answers again. A heartbeat from a node whose
// heartbeat had been lost (silent longer than heartbeat_timeout_cycles) without a boot-up means
// the drive is back in an unknown state: the master sends it NMT reset-communication and waits
// for its boot-up. Either way the master runs the start-up again (kStartNodes: NMT start to the
// nodes not operational; kEnabling: the controlword walk, every drive held at its actual
// position) and streams the caller's setpoints once every drive is operation enabled again;
// SYNCs never stop. A drive's quick stop is walked back the same way (disable voltage, then the
// walk); a drive fault is not (it waits for RequestFaultReset). What the platform does after a
// re-admission is the caller's (the session ramps from the measured positions to neutral and
// parks: session_core.h). Nothing is re-admitted once a disable was requested.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hardware/can_frame.h"
#include "hardware/canopen.h"
#include "hardware/drive_axes.h"

namespace pwsim::hw {

struct AxisConfig {
  std::uint8_t node{1};
  double counts_per_unit{1e6};  ///< [counts per rad] or [counts per m]
};

struct MasterConfig {
  int axis_count{2};  ///< the car: q1 yaw (node 1), q2 rail (node 2)
  std::array<AxisConfig, kMaxDriveAxes> axes{{{1, 1e6}, {2, 1e6}, {3, 1e6}, {4, 1e6},
                                              {5, 1e6}, {6, 1e6}, {7, 1e6}, {8, 1e6}}};
  std::uint8_t master_node{0x7F};       ///< the master's own heartbeat id
  int heartbeat_period_cycles{25};      ///< master heartbeat (25 x 4 ms = 100 ms)
  int heartbeat_timeout_cycles{75};     ///< a drive silent this long is lost (3 periods)
  int tpdo_timeout_cycles{3};           ///< a drive missing this many TPDOs is stale
  int boot_timeout_cycles{500};         ///< start-up gives up after this (2 s at 4 ms)
};

enum class MasterPhase { kResetComm, kWaitBoot, kStartNodes, kEnabling, kRunning, kDisabled,
                         kFailed };
const char* MasterPhaseName(MasterPhase phase);

struct AxisStatus {
  canopen::NmtState nmt{canopen::NmtState::kStopped};
  canopen::DriveState drive{canopen::DriveState::kNotReadyToSwitchOn};
  bool seen_heartbeat{false};
  std::int64_t last_heartbeat_cycle{-1};
  std::int64_t last_tpdo_cycle{-1};
  std::uint16_t statusword{0};  ///< as last received (TPDO1)
  double position{0.0};         ///< measured [rad] or [m]
  double velocity{0.0};         ///< measured [rad/s] or [m/s]
  double torque_permille{0.0};
  std::int32_t last_target_counts{0};
  std::uint64_t emcy_count{0};
  std::uint16_t last_emcy_code{0};
  bool emcy_fault{false};       ///< an EMCY with a non-zero code since the last fault reset
  bool fault{false};            ///< statusword shows fault (reaction) or emcy_fault
  bool heartbeat_lost{false};   ///< silent longer than the timeout since it was last heard
  bool awaiting_boot{false};    ///< came back without a boot-up: reset-comm sent, boot-up awaited
  std::uint64_t restarts{0};    ///< boot-ups after the start-up (drive restarted)
  std::uint64_t returns{0};     ///< heartbeats back after a loss
  std::uint64_t readmissions{0};  ///< times it was operation enabled again after one of those
  bool readmitting{false};      ///< restarted or returned, not yet operation enabled again
};

class Cia402Master {
 public:
  explicit Cia402Master(MasterConfig config = {});

  /// Feeds one received frame (any order within a cycle).
  void OnFrame(const CanFrame& frame);
  /// Emits this cycle's frames to `out` (appended). `setpoint` is used only in kRunning.
  void Cycle(std::int64_t cycle, const AxisValues& setpoint, std::vector<CanFrame>* out);
  /// Stop streaming: walk the drives to "ready to switch on" (0x06) and then NMT pre-op.
  void RequestDisable() { disable_requested_ = true; }
  /// Operator action after a fault: send fault reset and re-enable.
  void RequestFaultReset();

  MasterPhase phase() const { return phase_; }
  int axis_count() const { return config_.axis_count; }
  const AxisStatus& axis(int i) const { return axes_[static_cast<std::size_t>(i)]; }
  bool running() const { return phase_ == MasterPhase::kRunning; }
  bool any_fault() const;
  /// A drive in quick stop active (by its last statusword).
  bool any_quick_stop() const;
  /// A drive restarted or came back and is not operation enabled again yet.
  bool readmitting() const;
  /// Total boot-ups of drives after the start-up.
  std::uint64_t restarts() const;
  /// True when every drive's heartbeat is younger than the timeout (at the last Cycle).
  bool heartbeats_ok() const { return heartbeats_ok_; }
  /// True when every drive answered the last SYNCs with a TPDO1.
  bool tpdos_fresh() const { return tpdos_fresh_; }
  std::uint8_t sync_counter() const { return sync_counter_; }
  std::uint64_t frames_ignored() const { return frames_ignored_; }
  const MasterConfig& config() const { return config_; }

 private:
  int AxisIndex(std::uint8_t node) const;
  template <class Pred> bool All(Pred pred) const;

  MasterConfig config_;
  std::array<AxisStatus, kMaxDriveAxes> axes_{};
  MasterPhase phase_{MasterPhase::kResetComm};
  std::int64_t phase_start_{0};
  std::int64_t cycle_{0};
  std::uint8_t sync_counter_{0};
  bool disable_requested_{false};
  bool fault_reset_requested_{false};
  bool heartbeats_ok_{false};
  bool tpdos_fresh_{false};
  std::uint64_t frames_ignored_{0};
  std::array<std::uint16_t, kMaxDriveAxes> last_controlword_{};
};

}  // namespace pwsim::hw
