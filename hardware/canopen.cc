#include "hardware/canopen.h"

#include <cstring>

namespace pwsim::hw::canopen {
namespace {

void PutU16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}
void PutU32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint16_t GetU16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t GetU32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
bool IsStandardData(const CanFrame& f) { return !f.extended() && !f.remote() && !f.error(); }
bool NodeOf(const CanFrame& f, std::uint32_t base, std::uint8_t* node) {
  const std::uint32_t id = f.arbitration_id();
  if (id <= base || id > base + 127) return false;
  *node = static_cast<std::uint8_t>(id - base);
  return true;
}
CanFrame Frame(std::uint32_t id, std::uint8_t len) {
  CanFrame f;
  f.id = id;
  f.len = len;
  return f;
}

}  // namespace

const char* NmtStateName(NmtState state) {
  switch (state) {
    case NmtState::kBootUp: return "boot-up";
    case NmtState::kStopped: return "stopped";
    case NmtState::kOperational: return "operational";
    case NmtState::kPreOperational: return "pre-operational";
  }
  return "?";
}

FrameKind Classify(const CanFrame& frame, std::uint8_t* node) {
  *node = 0;
  if (!IsStandardData(frame)) return FrameKind::kOther;
  const std::uint32_t id = frame.arbitration_id();
  if (id == kCobNmt) return FrameKind::kNmt;
  if (id == kCobSync) return FrameKind::kSync;
  if (NodeOf(frame, kCobEmcy, node)) return FrameKind::kEmcy;
  if (NodeOf(frame, kCobTpdo1, node)) return FrameKind::kTpdo1;
  if (NodeOf(frame, kCobRpdo1, node)) return FrameKind::kRpdo1;
  if (NodeOf(frame, kCobTpdo2, node)) return FrameKind::kTpdo2;
  if (NodeOf(frame, kCobHeartbeat, node)) return FrameKind::kHeartbeat;
  *node = 0;
  return FrameKind::kOther;
}

CanFrame EncodeNmt(NmtCommand command, std::uint8_t node) {
  CanFrame f = Frame(kCobNmt, 2);
  f.data[0] = static_cast<std::uint8_t>(command);
  f.data[1] = node;
  return f;
}

bool DecodeNmt(const CanFrame& frame, NmtCommand* command, std::uint8_t* node) {
  if (!IsStandardData(frame) || frame.arbitration_id() != kCobNmt || frame.len != 2) return false;
  switch (frame.data[0]) {
    case 0x01: case 0x02: case 0x80: case 0x81: case 0x82: break;
    default: return false;
  }
  if (frame.data[1] > 127) return false;
  *command = static_cast<NmtCommand>(frame.data[0]);
  *node = frame.data[1];
  return true;
}

CanFrame EncodeSync(std::uint8_t counter) {
  CanFrame f = Frame(kCobSync, counter == 0 ? 0 : 1);
  f.data[0] = counter;
  return f;
}

bool DecodeSync(const CanFrame& frame, std::uint8_t* counter) {
  if (!IsStandardData(frame) || frame.arbitration_id() != kCobSync) return false;
  if (frame.len == 0) {
    *counter = 0;
    return true;
  }
  if (frame.len != 1 || frame.data[0] == 0 || frame.data[0] > 240) return false;
  *counter = frame.data[0];
  return true;
}

CanFrame EncodeHeartbeat(std::uint8_t node, NmtState state) {
  CanFrame f = Frame(kCobHeartbeat + node, 1);
  f.data[0] = static_cast<std::uint8_t>(state);
  return f;
}

bool DecodeHeartbeat(const CanFrame& frame, std::uint8_t* node, NmtState* state) {
  std::uint8_t n = 0;
  if (!IsStandardData(frame) || frame.len != 1 || !NodeOf(frame, kCobHeartbeat, &n)) return false;
  const std::uint8_t s = frame.data[0] & 0x7F;  // bit 7 is the toggle bit of node guarding
  if (s != 0x00 && s != 0x04 && s != 0x05 && s != 0x7F) return false;
  *node = n;
  *state = static_cast<NmtState>(s);
  return true;
}

CanFrame EncodeEmcy(std::uint8_t node, const Emcy& emcy) {
  CanFrame f = Frame(kCobEmcy + node, 8);
  PutU16(f.data.data(), emcy.code);
  f.data[2] = emcy.error_register;
  std::memcpy(f.data.data() + 3, emcy.vendor.data(), 5);
  return f;
}

bool DecodeEmcy(const CanFrame& frame, std::uint8_t* node, Emcy* emcy) {
  std::uint8_t n = 0;
  if (!IsStandardData(frame) || frame.len != 8 || !NodeOf(frame, kCobEmcy, &n)) return false;
  *node = n;
  emcy->code = GetU16(frame.data.data());
  emcy->error_register = frame.data[2];
  std::memcpy(emcy->vendor.data(), frame.data.data() + 3, 5);
  return true;
}

CanFrame EncodeCspCommand(std::uint8_t node, const CspCommand& command) {
  CanFrame f = Frame(kCobRpdo1 + node, 6);
  PutU16(f.data.data(), command.controlword);
  PutU32(f.data.data() + 2, static_cast<std::uint32_t>(command.target_position));
  return f;
}

bool DecodeCspCommand(const CanFrame& frame, std::uint8_t* node, CspCommand* command) {
  std::uint8_t n = 0;
  if (!IsStandardData(frame) || frame.len != 6 || !NodeOf(frame, kCobRpdo1, &n)) return false;
  *node = n;
  command->controlword = GetU16(frame.data.data());
  command->target_position = static_cast<std::int32_t>(GetU32(frame.data.data() + 2));
  return true;
}

CanFrame EncodeCspStatus(std::uint8_t node, const CspStatus& status) {
  CanFrame f = Frame(kCobTpdo1 + node, 6);
  PutU16(f.data.data(), status.statusword);
  PutU32(f.data.data() + 2, static_cast<std::uint32_t>(status.position_actual));
  return f;
}

bool DecodeCspStatus(const CanFrame& frame, std::uint8_t* node, CspStatus* status) {
  std::uint8_t n = 0;
  if (!IsStandardData(frame) || frame.len != 6 || !NodeOf(frame, kCobTpdo1, &n)) return false;
  *node = n;
  status->statusword = GetU16(frame.data.data());
  status->position_actual = static_cast<std::int32_t>(GetU32(frame.data.data() + 2));
  return true;
}

CanFrame EncodeCspFeedback(std::uint8_t node, const CspFeedback& feedback) {
  CanFrame f = Frame(kCobTpdo2 + node, 6);
  PutU32(f.data.data(), static_cast<std::uint32_t>(feedback.velocity_actual));
  PutU16(f.data.data() + 4, static_cast<std::uint16_t>(feedback.torque_actual));
  return f;
}

bool DecodeCspFeedback(const CanFrame& frame, std::uint8_t* node, CspFeedback* feedback) {
  std::uint8_t n = 0;
  if (!IsStandardData(frame) || frame.len != 6 || !NodeOf(frame, kCobTpdo2, &n)) return false;
  *node = n;
  feedback->velocity_actual = static_cast<std::int32_t>(GetU32(frame.data.data()));
  feedback->torque_actual = static_cast<std::int16_t>(GetU16(frame.data.data() + 4));
  return true;
}

const char* DriveStateName(DriveState state) {
  switch (state) {
    case DriveState::kNotReadyToSwitchOn: return "not ready to switch on";
    case DriveState::kSwitchOnDisabled: return "switch on disabled";
    case DriveState::kReadyToSwitchOn: return "ready to switch on";
    case DriveState::kSwitchedOn: return "switched on";
    case DriveState::kOperationEnabled: return "operation enabled";
    case DriveState::kQuickStopActive: return "quick stop active";
    case DriveState::kFaultReactionActive: return "fault reaction active";
    case DriveState::kFault: return "fault";
  }
  return "?";
}

DriveState DecodeStatusword(std::uint16_t sw) {
  const unsigned s4f = sw & 0x4FU;
  if (s4f == 0x00) return DriveState::kNotReadyToSwitchOn;
  if (s4f == 0x40) return DriveState::kSwitchOnDisabled;
  if (s4f == 0x0F) return DriveState::kFaultReactionActive;
  if (s4f == 0x08) return DriveState::kFault;
  const unsigned s6f = sw & 0x6FU;
  if (s6f == 0x21) return DriveState::kReadyToSwitchOn;
  if (s6f == 0x23) return DriveState::kSwitchedOn;
  if (s6f == 0x27) return DriveState::kOperationEnabled;
  if (s6f == 0x07) return DriveState::kQuickStopActive;
  return DriveState::kNotReadyToSwitchOn;  // undefined patterns: treat as not ready
}

std::uint16_t StatuswordFor(DriveState state, bool target_reached) {
  std::uint16_t sw = 0;
  switch (state) {
    case DriveState::kNotReadyToSwitchOn: sw = 0x00; break;
    case DriveState::kSwitchOnDisabled: sw = 0x40; break;
    case DriveState::kReadyToSwitchOn: sw = 0x21; break;
    case DriveState::kSwitchedOn: sw = 0x23; break;
    case DriveState::kOperationEnabled: sw = 0x27; break;
    case DriveState::kQuickStopActive: sw = 0x07; break;
    case DriveState::kFaultReactionActive: sw = 0x0F; break;
    case DriveState::kFault: sw = 0x08; break;
  }
  sw = static_cast<std::uint16_t>(sw | 0x0200U | (target_reached ? 0x0400U : 0U));
  if (state != DriveState::kNotReadyToSwitchOn && state != DriveState::kSwitchOnDisabled &&
      state != DriveState::kFault)
    sw = static_cast<std::uint16_t>(sw | 0x0010U);  // voltage enabled
  return sw;
}

DriveState NextDriveState(DriveState state, std::uint16_t cw, std::uint16_t previous_cw) {
  const bool disable_voltage = (cw & 0x02U) == 0;        // bit 1 clear
  const bool quick_stop = (cw & 0x06U) == 0x02U;         // bit 1 set, bit 2 clear
  const bool shutdown = (cw & 0x87U) == 0x06U;
  const bool switch_on = (cw & 0x8FU) == 0x07U;
  const bool enable = (cw & 0x8FU) == 0x0FU;
  const bool fault_reset_edge = (cw & 0x80U) != 0 && (previous_cw & 0x80U) == 0;
  switch (state) {
    case DriveState::kNotReadyToSwitchOn:
      return DriveState::kSwitchOnDisabled;  // automatic after self test
    case DriveState::kSwitchOnDisabled:
      return shutdown ? DriveState::kReadyToSwitchOn : state;
    case DriveState::kReadyToSwitchOn:
      if (disable_voltage || quick_stop) return DriveState::kSwitchOnDisabled;
      if (switch_on) return DriveState::kSwitchedOn;
      if (enable) return DriveState::kSwitchedOn;  // 0x0F from ready: switch on first
      return state;
    case DriveState::kSwitchedOn:
      if (disable_voltage || quick_stop) return DriveState::kSwitchOnDisabled;
      if (shutdown) return DriveState::kReadyToSwitchOn;
      if (enable) return DriveState::kOperationEnabled;
      return state;
    case DriveState::kOperationEnabled:
      if (disable_voltage) return DriveState::kSwitchOnDisabled;
      if (quick_stop) return DriveState::kQuickStopActive;
      if (shutdown) return DriveState::kReadyToSwitchOn;
      if (switch_on) return DriveState::kSwitchedOn;
      return state;
    case DriveState::kQuickStopActive:
      if (disable_voltage) return DriveState::kSwitchOnDisabled;
      return state;  // option code 6: stay until disable voltage
    case DriveState::kFaultReactionActive:
      return DriveState::kFault;  // automatic when the reaction ends
    case DriveState::kFault:
      return fault_reset_edge ? DriveState::kSwitchOnDisabled : state;
  }
  return state;
}

std::uint16_t ControlwordTowardEnabled(DriveState state) {
  switch (state) {
    case DriveState::kNotReadyToSwitchOn: return controlword::kDisableVoltage;
    case DriveState::kSwitchOnDisabled: return controlword::kShutdown;
    case DriveState::kReadyToSwitchOn: return controlword::kSwitchOn;
    case DriveState::kSwitchedOn: return controlword::kEnableOperation;
    case DriveState::kOperationEnabled: return controlword::kEnableOperation;
    case DriveState::kQuickStopActive: return controlword::kDisableVoltage;
    case DriveState::kFaultReactionActive: return controlword::kDisableVoltage;
    case DriveState::kFault: return controlword::kFaultReset;
  }
  return controlword::kDisableVoltage;
}

}  // namespace pwsim::hw::canopen
