#include "hardware/cia402_master.h"

#include <cmath>

namespace pwsim::hw {

using canopen::DriveState;
using canopen::NmtState;

const char* MasterPhaseName(MasterPhase phase) {
  switch (phase) {
    case MasterPhase::kResetComm: return "reset-comm";
    case MasterPhase::kWaitBoot: return "wait-boot";
    case MasterPhase::kStartNodes: return "start-nodes";
    case MasterPhase::kEnabling: return "enabling";
    case MasterPhase::kRunning: return "running";
    case MasterPhase::kDisabled: return "disabled";
    case MasterPhase::kFailed: return "failed";
  }
  return "?";
}

Cia402Master::Cia402Master(MasterConfig config) : config_(config) {}

int Cia402Master::AxisIndex(std::uint8_t node) const {
  for (int i = 0; i < config_.axis_count; ++i)
    if (config_.axes[static_cast<std::size_t>(i)].node == node) return i;
  return -1;
}

template <class Pred>
bool Cia402Master::All(Pred pred) const {
  for (int i = 0; i < config_.axis_count; ++i)
    if (!pred(axes_[static_cast<std::size_t>(i)])) return false;
  return true;
}

bool Cia402Master::any_fault() const {
  return !All([](const AxisStatus& a) { return !a.fault; });
}

bool Cia402Master::any_quick_stop() const {
  return !All([](const AxisStatus& a) { return a.drive != DriveState::kQuickStopActive; });
}

bool Cia402Master::readmitting() const {
  return !All([](const AxisStatus& a) { return !a.readmitting; });
}

std::uint64_t Cia402Master::restarts() const {
  std::uint64_t n = 0;
  for (int i = 0; i < config_.axis_count; ++i) n += axes_[static_cast<std::size_t>(i)].restarts;
  return n;
}

void Cia402Master::RequestFaultReset() {
  fault_reset_requested_ = true;
  for (int i = 0; i < config_.axis_count; ++i) {
    AxisStatus& a = axes_[static_cast<std::size_t>(i)];
    a.emcy_fault = false;
    a.fault = a.drive == DriveState::kFault || a.drive == DriveState::kFaultReactionActive;
  }
  if (phase_ == MasterPhase::kRunning) phase_ = MasterPhase::kEnabling;
}

void Cia402Master::OnFrame(const CanFrame& frame) {
  std::uint8_t node = 0;
  const canopen::FrameKind kind = canopen::Classify(frame, &node);
  const int i = AxisIndex(node);
  if (i < 0) {
    ++frames_ignored_;
    return;
  }
  AxisStatus& a = axes_[static_cast<std::size_t>(i)];
  const AxisConfig& c = config_.axes[static_cast<std::size_t>(i)];
  switch (kind) {
    case canopen::FrameKind::kHeartbeat: {
      NmtState s{};
      if (canopen::DecodeHeartbeat(frame, &node, &s)) {
        // Past the start-up (a boot-up during it is the answer to its reset-comm, or a node
        // that rebooted before it was started: kStartNodes starts it either way).
        const bool started = phase_ == MasterPhase::kEnabling || phase_ == MasterPhase::kRunning ||
                             phase_ == MasterPhase::kDisabled ||
                             (phase_ == MasterPhase::kStartNodes && readmitting());
        if (s == NmtState::kBootUp && started) {
          // The drive restarted: whatever it was doing is gone; its feedback is void.
          ++a.restarts;
          a.readmitting = true;
          a.awaiting_boot = false;
          a.drive = DriveState::kSwitchOnDisabled;
          a.last_tpdo_cycle = -1;
          a.fault = a.emcy_fault;
        } else if (a.heartbeat_lost && started && !a.awaiting_boot && s != NmtState::kBootUp) {
          // Back without a boot-up: its state is unknown. Reset it (Cycle sends the NMT).
          ++a.returns;
          a.readmitting = true;
          a.awaiting_boot = true;
        }
        a.nmt = s == NmtState::kBootUp ? NmtState::kPreOperational : s;
        a.seen_heartbeat = true;
        a.heartbeat_lost = false;
        a.last_heartbeat_cycle = cycle_;
      }
      break;
    }
    case canopen::FrameKind::kTpdo1: {
      canopen::CspStatus s;
      if (canopen::DecodeCspStatus(frame, &node, &s)) {
        a.statusword = s.statusword;
        a.drive = canopen::DecodeStatusword(s.statusword);
        a.position = static_cast<double>(s.position_actual) / c.counts_per_unit;
        a.last_tpdo_cycle = cycle_;
        a.nmt = NmtState::kOperational;  // PDOs flow only in operational
        a.fault = a.emcy_fault || a.drive == DriveState::kFault ||
                  a.drive == DriveState::kFaultReactionActive;
      }
      break;
    }
    case canopen::FrameKind::kTpdo2: {
      canopen::CspFeedback f;
      if (canopen::DecodeCspFeedback(frame, &node, &f)) {
        a.velocity = static_cast<double>(f.velocity_actual) / c.counts_per_unit;
        a.torque_permille = f.torque_actual;
      }
      break;
    }
    case canopen::FrameKind::kEmcy: {
      canopen::Emcy e;
      if (canopen::DecodeEmcy(frame, &node, &e)) {
        ++a.emcy_count;
        a.last_emcy_code = e.code;
        if (e.code != 0) {
          a.emcy_fault = true;
          a.fault = true;
        }
      }
      break;
    }
    default:
      ++frames_ignored_;
      break;
  }
}

void Cia402Master::Cycle(std::int64_t cycle, const AxisValues& setpoint, std::vector<CanFrame>* out) {
  cycle_ = cycle;
  heartbeats_ok_ = true;
  tpdos_fresh_ = true;
  const auto n = static_cast<std::size_t>(config_.axis_count);
  for (std::size_t k = 0; k < n; ++k) {
    AxisStatus& a = axes_[k];
    if (!a.seen_heartbeat || cycle - a.last_heartbeat_cycle > config_.heartbeat_timeout_cycles) {
      heartbeats_ok_ = false;
      if (a.seen_heartbeat) a.heartbeat_lost = true;
    }
    if (a.last_tpdo_cycle < 0 || cycle - a.last_tpdo_cycle > config_.tpdo_timeout_cycles)
      tpdos_fresh_ = false;
  }
  if (cycle % config_.heartbeat_period_cycles == 0)
    out->push_back(canopen::EncodeHeartbeat(config_.master_node, NmtState::kOperational));

  // A drive that came back: start it again (unless the session is ending).
  if (!disable_requested_ && (phase_ == MasterPhase::kEnabling || phase_ == MasterPhase::kRunning)) {
    for (std::size_t k = 0; k < n; ++k) {
      AxisStatus& a = axes_[k];
      if (!a.readmitting) continue;
      if (a.awaiting_boot) {
        // once per heartbeat period until its boot-up arrives
        if ((cycle - a.last_heartbeat_cycle) % config_.heartbeat_period_cycles == 0)
          out->push_back(canopen::EncodeNmt(canopen::NmtCommand::kResetComm, config_.axes[k].node));
      } else if (a.nmt != NmtState::kOperational) {
        phase_ = MasterPhase::kStartNodes;
        phase_start_ = cycle;
      }
    }
  }

  switch (phase_) {
    case MasterPhase::kResetComm:
      for (AxisStatus& a : axes_) a.seen_heartbeat = false;
      out->push_back(canopen::EncodeNmt(canopen::NmtCommand::kResetComm, 0));
      phase_ = MasterPhase::kWaitBoot;
      phase_start_ = cycle;
      break;
    case MasterPhase::kWaitBoot:
      if (All([](const AxisStatus& a) { return a.seen_heartbeat; })) {
        phase_ = MasterPhase::kStartNodes;
        phase_start_ = cycle;
      } else if (cycle - phase_start_ > config_.boot_timeout_cycles) {
        phase_ = MasterPhase::kResetComm;  // try again: a drive may have started late
      }
      break;
    case MasterPhase::kStartNodes:
      if (All([](const AxisStatus& a) { return a.nmt == NmtState::kOperational; })) {
        phase_ = MasterPhase::kEnabling;
        phase_start_ = cycle;
      } else if (All([](const AxisStatus& a) { return !a.readmitting; })) {
        out->push_back(canopen::EncodeNmt(canopen::NmtCommand::kStart, 0));  // the start-up: all
      } else {
        for (std::size_t k = 0; k < n; ++k)  // a re-admission: the nodes that need it
          if (axes_[k].nmt != NmtState::kOperational && !axes_[k].awaiting_boot)
            out->push_back(canopen::EncodeNmt(canopen::NmtCommand::kStart, config_.axes[k].node));
      }
      break;
    default:
      break;
  }

  auto enabled = [](const AxisStatus& a) { return a.drive == DriveState::kOperationEnabled; };
  // While re-admitting, the other drives keep answering SYNCs holding their positions.
  const bool streaming = phase_ == MasterPhase::kEnabling || phase_ == MasterPhase::kRunning ||
                         phase_ == MasterPhase::kDisabled ||
                         (phase_ == MasterPhase::kStartNodes && readmitting());
  if (streaming) {
    if (disable_requested_ && phase_ != MasterPhase::kDisabled) phase_ = MasterPhase::kDisabled;
    if (phase_ == MasterPhase::kEnabling && All(enabled)) {
      phase_ = MasterPhase::kRunning;
      for (std::size_t k = 0; k < n; ++k) {
        if (axes_[k].readmitting) ++axes_[k].readmissions;
        axes_[k].readmitting = false;
      }
    }
    if (phase_ == MasterPhase::kRunning && !All(enabled)) {
      phase_ = MasterPhase::kEnabling;  // a drive dropped out (quick stop, fault): hold, re-walk
    }
    for (std::size_t k = 0; k < n; ++k) {
      AxisStatus& a = axes_[k];
      canopen::CspCommand cmd;
      if (phase_ == MasterPhase::kRunning) {
        cmd.controlword = canopen::controlword::kEnableOperation;
        const double counts = std::round(setpoint[k] * config_.axes[k].counts_per_unit);
        cmd.target_position = std::isfinite(counts) && std::abs(counts) < 2.0e9
                                  ? static_cast<std::int32_t>(counts)
                                  : a.last_target_counts;
      } else {
        // Hold where the drive is while walking the state machine.
        const double counts = std::round(a.position * config_.axes[k].counts_per_unit);
        cmd.target_position = std::abs(counts) < 2.0e9 ? static_cast<std::int32_t>(counts) : a.last_target_counts;
        if (phase_ == MasterPhase::kDisabled) {
          cmd.controlword = canopen::controlword::kShutdown;
        } else if (a.drive == DriveState::kFault) {
          cmd.controlword = fault_reset_requested_ && (last_controlword_[k] & 0x80U) == 0
                                ? canopen::controlword::kFaultReset
                                : canopen::controlword::kDisableVoltage;
        } else {
          cmd.controlword = canopen::ControlwordTowardEnabled(a.drive);
        }
      }
      a.last_target_counts = cmd.target_position;
      last_controlword_[k] = cmd.controlword;
      out->push_back(canopen::EncodeCspCommand(config_.axes[k].node, cmd));
    }
    if (fault_reset_requested_ && All([](const AxisStatus& a) { return a.drive != DriveState::kFault; }))
      fault_reset_requested_ = false;
  }
  // SYNC after the RPDOs: the drives latch this cycle's targets on it.
  sync_counter_ = static_cast<std::uint8_t>(sync_counter_ % 240 + 1);
  out->push_back(canopen::EncodeSync(sync_counter_));
}

}  // namespace pwsim::hw
