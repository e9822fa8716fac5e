#pragma once
// The platform's two CiA 402 servo drives, simulated: what `pwsim platform-sim` runs behind
// the CAN-over-UDP link, and what the in-process tests put on the other end of the bus.
//   NMT (reset-comm -> boot-up heartbeat, start -> operational), heartbeat producer,
//   RPDO1 (controlword, target) latched on SYNC, TPDO1/TPDO2 answered on every SYNC,
//   CiA 402 state machine, CSP: on each SYNC the PlatformPlant advances one drive cycle toward
//   the latched target; following-error trip (EMCY 0x8611, fault), master heartbeat consumer
//   (loss -> quick stop: decelerate and hold, the 0x6007 reaction), injectable faults.
// Time: SYNCs drive the physics; Poll(now) adds the time-based parts (heartbeats, watchdog).

#include <array>
#include <cstdint>
#include <vector>

#include "hardware/can_frame.h"
#include "hardware/canopen.h"
#include "hardware/platform_model.h"

namespace pwsim::hw {

struct DriveSimConfig {
  std::array<std::uint8_t, 2> nodes{1, 2};        ///< yaw, rail
  std::array<double, 2> counts_per_unit{1e6, 1e6};
  double cycle_s{0.004};                          ///< SYNC period the drives expect
  std::int64_t heartbeat_period_ns{100'000'000};  ///< producer heartbeat 0x1017 (100 ms)
  std::int64_t master_timeout_ns{300'000'000};    ///< consumer heartbeat 0x1016 (300 ms)
  std::array<double, 2> following_error_window{0.2, 0.05};  ///< 0x6065 [rad, m]
  std::array<double, 2> quick_stop_decel{0.5, 3.0};         ///< 0x6085 [rad/s^2, m/s^2]
};

class SimulatedDrives {
 public:
  explicit SimulatedDrives(DriveSimConfig config = {}, PlatformParams params = {});

  /// Handles one frame from the bus; responses are appended to `out`.
  void OnFrame(const CanFrame& frame, std::int64_t now_ns, std::vector<CanFrame>* out);
  /// Time-based duties (heartbeat, master watchdog, quick-stop motion without SYNCs).
  void Poll(std::int64_t now_ns, std::vector<CanFrame>* out);

  // Fault injection (tests, `platform-sim --fault-at`).
  void InjectFault(int axis, std::uint16_t emcy_code, std::vector<CanFrame>* out);
  void SetSilent(bool silent) { silent_ = silent; }  ///< stop answering (a dead node)

  const PlatformState& platform() const { return plant_.state(); }
  canopen::DriveState drive_state(int axis) const { return drive_[static_cast<std::size_t>(axis)]; }
  canopen::NmtState nmt_state() const { return nmt_; }
  std::uint64_t syncs() const { return syncs_; }
  bool master_lost() const { return master_lost_; }
  /// Largest |q| seen on each axis since start.
  const std::array<double, 2>& peak_abs_position() const { return peak_abs_; }

 private:
  int AxisOf(std::uint8_t node) const;
  void Boot(std::int64_t now_ns, std::vector<CanFrame>* out);
  void StepPhysics(std::vector<CanFrame>* out);

  DriveSimConfig config_;
  PlatformPlant plant_;
  canopen::NmtState nmt_{canopen::NmtState::kBootUp};
  std::array<canopen::DriveState, 2> drive_{canopen::DriveState::kSwitchOnDisabled,
                                            canopen::DriveState::kSwitchOnDisabled};
  std::array<std::uint16_t, 2> controlword_{};
  std::array<std::int32_t, 2> target_counts_{};
  std::array<double, 2> latched_target_{};
  std::array<double, 2> quick_stop_velocity_{};
  std::int64_t last_heartbeat_ns_{0};
  std::int64_t last_master_ns_{0};
  std::int64_t last_motion_ns_{0};
  bool booted_{false};
  bool master_seen_{false};
  bool master_lost_{false};
  bool silent_{false};
  std::uint64_t syncs_{0};
  std::array<double, 2> peak_abs_{};
};

}  // namespace pwsim::hw
