#include "hardware/simulated_drives.h"

#include <algorithm>
#include <cmath>

namespace pwsim::hw {

using canopen::DriveState;
using canopen::NmtState;

SimulatedDrives::SimulatedDrives(DriveSimConfig config, PlatformParams params)
    : config_(config), plant_(params) {}

int SimulatedDrives::AxisOf(std::uint8_t node) const {
  for (int i = 0; i < 2; ++i)
    if (config_.nodes[static_cast<std::size_t>(i)] == node) return i;
  return -1;
}

void SimulatedDrives::Boot(std::int64_t now_ns, std::vector<CanFrame>* out) {
  nmt_ = NmtState::kPreOperational;
  booted_ = true;
  last_heartbeat_ns_ = now_ns;
  for (std::uint8_t node : config_.nodes) out->push_back(canopen::EncodeHeartbeat(node, NmtState::kBootUp));
}

void SimulatedDrives::InjectFault(int axis, std::uint16_t emcy_code, std::vector<CanFrame>* out) {
  const auto k = static_cast<std::size_t>(axis);
  drive_[k] = DriveState::kFault;
  canopen::Emcy e;
  e.code = emcy_code;
  e.error_register = 0x01;
  out->push_back(canopen::EncodeEmcy(config_.nodes[k], e));
}

void SimulatedDrives::OnFrame(const CanFrame& frame, std::int64_t now_ns,
                              std::vector<CanFrame>* out) {
  if (silent_) return;
  std::uint8_t node = 0;
  switch (canopen::Classify(frame, &node)) {
    case canopen::FrameKind::kNmt: {
      canopen::NmtCommand cmd{};
      if (!canopen::DecodeNmt(frame, &cmd, &node)) return;
      if (node != 0 && AxisOf(node) < 0) return;
      if (cmd == canopen::NmtCommand::kResetComm || cmd == canopen::NmtCommand::kResetNode) {
        if (cmd == canopen::NmtCommand::kResetNode)
          drive_ = {DriveState::kSwitchOnDisabled, DriveState::kSwitchOnDisabled};
        Boot(now_ns, out);
      } else if (cmd == canopen::NmtCommand::kStart) {
        nmt_ = NmtState::kOperational;
      } else if (cmd == canopen::NmtCommand::kStop) {
        nmt_ = NmtState::kStopped;
      } else {
        nmt_ = NmtState::kPreOperational;
      }
      master_seen_ = true;
      last_master_ns_ = now_ns;
      master_lost_ = false;
      return;
    }
    case canopen::FrameKind::kHeartbeat: {
      NmtState s{};
      if (canopen::DecodeHeartbeat(frame, &node, &s) && AxisOf(node) < 0) {
        master_seen_ = true;  // the master's heartbeat (any node that is not ours)
        last_master_ns_ = now_ns;
      }
      return;
    }
    case canopen::FrameKind::kRpdo1: {
      const int axis = AxisOf(node);
      canopen::CspCommand cmd;
      if (axis < 0 || nmt_ != NmtState::kOperational || !canopen::DecodeCspCommand(frame, &node, &cmd))
        return;
      const auto k = static_cast<std::size_t>(axis);
      const DriveState before = drive_[k];
      if (!master_lost_) drive_[k] = canopen::NextDriveState(before, cmd.controlword, controlword_[k]);
      controlword_[k] = cmd.controlword;
      target_counts_[k] = cmd.target_position;
      if (drive_[k] == DriveState::kOperationEnabled && before != DriveState::kOperationEnabled) {
        // Enabling: the interpolator starts from where the axis is.
        std::array<double, 2> hold = plant_.state().q;
        plant_.ResetTarget(hold);
        latched_target_ = hold;
      }
      return;
    }
    case canopen::FrameKind::kSync: {
      std::uint8_t counter = 0;
      if (!canopen::DecodeSync(frame, &counter)) return;
      master_seen_ = true;
      last_master_ns_ = now_ns;
      if (nmt_ != NmtState::kOperational) return;
      ++syncs_;
      last_motion_ns_ = now_ns;
      StepPhysics(out);
      for (std::size_t k = 0; k < 2; ++k) {
        const double c = config_.counts_per_unit[k];
        canopen::CspStatus s;
        const bool reached = std::abs(plant_.state().q[k] - latched_target_[k]) < 1e-3;
        s.statusword = canopen::StatuswordFor(drive_[k], reached);
        s.position_actual = static_cast<std::int32_t>(std::lround(plant_.state().q[k] * c));
        out->push_back(canopen::EncodeCspStatus(config_.nodes[k], s));
        canopen::CspFeedback f;
        f.velocity_actual = static_cast<std::int32_t>(std::lround(plant_.state().qd[k] * c));
        const double limit = k == 0 ? plant_.params().tau1_max : plant_.params().tau2_max;
        f.torque_actual = static_cast<std::int16_t>(std::lround(1000.0 * plant_.state().tau[k] / limit));
        out->push_back(canopen::EncodeCspFeedback(config_.nodes[k], f));
      }
      return;
    }
    default:
      return;
  }
}

void SimulatedDrives::StepPhysics(std::vector<CanFrame>* out) {
  const double dt = config_.cycle_s;
  std::array<double, 2> target = plant_.state().q;
  bool enabled = false;
  for (std::size_t k = 0; k < 2; ++k) {
    const DriveState s = drive_[k];
    if (s == DriveState::kOperationEnabled) {
      latched_target_[k] = static_cast<double>(target_counts_[k]) / config_.counts_per_unit[k];
      quick_stop_velocity_[k] = plant_.state().qd[k];
      enabled = true;
    } else if (s == DriveState::kQuickStopActive || s == DriveState::kFault ||
               s == DriveState::kFaultReactionActive) {
      // Decelerate at the quick-stop ramp, then hold (0x605A option 6; 0x605E fault reaction
      // "slow down on quick-stop ramp", the holding brake modelled as position hold).
      double& v = quick_stop_velocity_[k];
      const double dv = config_.quick_stop_decel[k] * dt;
      v = std::abs(v) <= dv ? 0.0 : v - std::copysign(dv, v);
      latched_target_[k] += v * dt;
      enabled = true;
    } else {
      latched_target_[k] = plant_.state().q[k];
    }
    target[k] = latched_target_[k];
  }
  plant_.Advance(dt, target, enabled);
  for (std::size_t k = 0; k < 2; ++k) {
    peak_abs_[k] = std::max(peak_abs_[k], std::abs(plant_.state().q[k]));
    if (drive_[k] == DriveState::kOperationEnabled &&
        std::abs(plant_.state().q[k] - latched_target_[k]) > config_.following_error_window[k]) {
      InjectFault(static_cast<int>(k), 0x8611, out);  // following error
    }
  }
}

void SimulatedDrives::Poll(std::int64_t now_ns, std::vector<CanFrame>* out) {
  if (silent_) return;
  if (!booted_) {
    Boot(now_ns, out);
    return;
  }
  if (now_ns - last_heartbeat_ns_ >= config_.heartbeat_period_ns) {
    last_heartbeat_ns_ = now_ns;
    for (std::uint8_t node : config_.nodes) out->push_back(canopen::EncodeHeartbeat(node, nmt_));
  }
  if (master_seen_ && !master_lost_ && now_ns - last_master_ns_ > config_.master_timeout_ns) {
    master_lost_ = true;  // 0x6007 abort connection: quick stop
    for (DriveState& s : drive_)
      if (s == DriveState::kOperationEnabled) s = DriveState::kQuickStopActive;
  }
  // Without SYNCs the drives still move (quick stop) on their own clock.
  const auto cycle_ns = static_cast<std::int64_t>(config_.cycle_s * 1e9);
  if (master_lost_ && nmt_ == NmtState::kOperational) {
    while (now_ns - last_motion_ns_ >= cycle_ns) {
      last_motion_ns_ += cycle_ns;
      StepPhysics(out);
    }
  }
}

}  // namespace pwsim::hw
