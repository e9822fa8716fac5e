#pragma once
// CANopen (CiA 301) frames of the pre-defined connection set and the CiA 402 drive state
// machine, as pure functions. The platform's PDO mapping (fixed, documented in docs/hardware.md):
//   RPDO1 0x200+n  controlword u16 | target position i32 (0x607A)          6 bytes, sync type 1
//   TPDO1 0x180+n  statusword u16  | position actual i32 (0x6064)          6 bytes, every SYNC
//   TPDO2 0x280+n  velocity actual i32 (0x606C) | torque actual i16 (0x6077, per mille)
// All multi-byte fields little endian, as CANopen requires.

#include <array>
#include <cstdint>

#include "hardware/can_frame.h"

namespace pwsim::hw::canopen {

enum class NmtCommand : std::uint8_t {
  kStart = 0x01, kStop = 0x02, kEnterPreOperational = 0x80, kResetNode = 0x81, kResetComm = 0x82
};
enum class NmtState : std::uint8_t {
  kBootUp = 0x00, kStopped = 0x04, kOperational = 0x05, kPreOperational = 0x7F
};
const char* NmtStateName(NmtState state);

inline constexpr std::uint32_t kCobNmt = 0x000, kCobSync = 0x080, kCobEmcy = 0x080,
                               kCobTpdo1 = 0x180, kCobRpdo1 = 0x200, kCobTpdo2 = 0x280,
                               kCobHeartbeat = 0x700;

enum class FrameKind { kNmt, kSync, kEmcy, kTpdo1, kTpdo2, kRpdo1, kHeartbeat, kOther };
/// What a frame is in the pre-defined connection set, and for which node (0 when none).
FrameKind Classify(const CanFrame& frame, std::uint8_t* node);

CanFrame EncodeNmt(NmtCommand command, std::uint8_t node);  ///< node 0 = all nodes
bool DecodeNmt(const CanFrame& frame, NmtCommand* command, std::uint8_t* node);

/// SYNC with a counter 1..240 (0 = no counter byte).
CanFrame EncodeSync(std::uint8_t counter);
bool DecodeSync(const CanFrame& frame, std::uint8_t* counter);

CanFrame EncodeHeartbeat(std::uint8_t node, NmtState state);
bool DecodeHeartbeat(const CanFrame& frame, std::uint8_t* node, NmtState* state);

struct Emcy {
  std::uint16_t code{0};            ///< e.g. 0x8611 following error, 0x0000 reset/no error
  std::uint8_t error_register{0};   ///< object 0x1001
  std::array<std::uint8_t, 5> vendor{};
  bool operator==(const Emcy&) const = default;
};
CanFrame EncodeEmcy(std::uint8_t node, const Emcy& emcy);
bool DecodeEmcy(const CanFrame& frame, std::uint8_t* node, Emcy* emcy);

struct CspCommand {            // RPDO1
  std::uint16_t controlword{0};
  std::int32_t target_position{0};  ///< [counts]
  bool operator==(const CspCommand&) const = default;
};
CanFrame EncodeCspCommand(std::uint8_t node, const CspCommand& command);
bool DecodeCspCommand(const CanFrame& frame, std::uint8_t* node, CspCommand* command);

struct CspStatus {             // TPDO1
  std::uint16_t statusword{0};
  std::int32_t position_actual{0};  ///< [counts]
  bool operator==(const CspStatus&) const = default;
};
CanFrame EncodeCspStatus(std::uint8_t node, const CspStatus& status);
bool DecodeCspStatus(const CanFrame& frame, std::uint8_t* node, CspStatus* status);

struct CspFeedback {           // TPDO2
  std::int32_t velocity_actual{0};  ///< [counts/s]
  std::int16_t torque_actual{0};    ///< [per mille of rated]
  bool operator==(const CspFeedback&) const = default;
};
CanFrame EncodeCspFeedback(std::uint8_t node, const CspFeedback& feedback);
bool DecodeCspFeedback(const CanFrame& frame, std::uint8_t* node, CspFeedback* feedback);

// --- CiA 402 -------------------------------------------------------------------------------
enum class DriveState {
  kNotReadyToSwitchOn, kSwitchOnDisabled, kReadyToSwitchOn, kSwitchedOn, kOperationEnabled,
  kQuickStopActive, kFaultReactionActive, kFault
};
const char* DriveStateName(DriveState state);

namespace controlword {
inline constexpr std::uint16_t kShutdown = 0x0006;
inline constexpr std::uint16_t kSwitchOn = 0x0007;
inline constexpr std::uint16_t kEnableOperation = 0x000F;
inline constexpr std::uint16_t kQuickStop = 0x0002;
inline constexpr std::uint16_t kDisableVoltage = 0x0000;
inline constexpr std::uint16_t kFaultReset = 0x0080;
}  // namespace controlword

/// Statusword -> state (masks 0x4F / 0x6F of CiA 402).
DriveState DecodeStatusword(std::uint16_t statusword);
/// The statusword a drive reports in `state` (bit 9 remote set; `target_reached` bit 10).
std::uint16_t StatuswordFor(DriveState state, bool target_reached = false);
/// Drive side: the state after receiving `controlword` in `state`. `previous_controlword` is
/// needed for the fault-reset rising edge.
DriveState NextDriveState(DriveState state, std::uint16_t controlword,
                          std::uint16_t previous_controlword);
/// Master side: the controlword that moves a drive from `state` one step toward Operation
/// Enabled (fault reset from Fault; quick-stop exit via disable voltage).
std::uint16_t ControlwordTowardEnabled(DriveState state);

}  // namespace pwsim::hw::canopen
