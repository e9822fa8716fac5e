#pragma once
// Classic CAN frames and their wire codecs, as pure functions (no I/O, no allocation except
// where a std::vector/std::string is the result):
//   - the Linux `struct can_frame` layout (16 bytes, what a CAN_RAW socket reads and writes),
//   - the can-utils text form "ID#DATA" used by candump logs and cansend,
//   - cannelloni's CAN-over-UDP datagram (doc/udp_format.md of mguentner/cannelloni).
// Identifiers carry the Linux flags (EFF, RTR, ERR) in their top bits, as SocketCAN does.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pwsim::hw {

inline constexpr std::uint32_t kCanEffFlag = 0x80000000U;  ///< 29-bit identifier
inline constexpr std::uint32_t kCanRtrFlag = 0x40000000U;  ///< remote transmission request
inline constexpr std::uint32_t kCanErrFlag = 0x20000000U;  ///< error frame (from the controller)
inline constexpr std::uint32_t kCanSffMask = 0x000007FFU;
inline constexpr std::uint32_t kCanEffMask = 0x1FFFFFFFU;
// Error classes carried in an error frame's identifier (linux/can/error.h).
inline constexpr std::uint32_t kCanErrTxTimeout = 0x001U;
inline constexpr std::uint32_t kCanErrCtrl = 0x004U;      ///< controller state, data[1]
inline constexpr std::uint32_t kCanErrBusOff = 0x040U;
inline constexpr std::uint32_t kCanErrRestarted = 0x100U;
inline constexpr std::uint8_t kCanErrCtrlRxPassive = 0x10U;  ///< data[1] bits
inline constexpr std::uint8_t kCanErrCtrlTxPassive = 0x20U;

struct CanFrame {
  std::uint32_t id{0};            ///< identifier with the EFF/RTR/ERR flags
  std::uint8_t len{0};            ///< 0..8 data bytes
  std::array<std::uint8_t, 8> data{};

  bool extended() const { return (id & kCanEffFlag) != 0; }
  bool remote() const { return (id & kCanRtrFlag) != 0; }
  bool error() const { return (id & kCanErrFlag) != 0; }
  /// The bare identifier (11 or 29 bits; error class bits for an error frame).
  std::uint32_t arbitration_id() const { return id & (extended() ? kCanEffMask : kCanSffMask); }
  bool operator==(const CanFrame&) const = default;
};

/// A standard-identifier data frame (`bytes.size()` <= 8, checked).
CanFrame MakeFrame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes);
/// An error frame of `error_class` (kCanErrBusOff, ...), 8 data bytes as the kernel sends them.
CanFrame MakeErrorFrame(std::uint32_t error_class, std::uint8_t ctrl_state = 0);
/// True when the frame's fields are self-consistent (len <= 8, id inside its mask).
bool IsValidFrame(const CanFrame& frame);

enum class CodecError {
  kOk,
  kTruncated,    ///< input shorter than its header or declared content
  kBadLength,    ///< a length field above 8 (or a CAN FD frame, which we do not carry)
  kBadVersion,   ///< cannelloni version other than 2
  kBadOpcode,    ///< cannelloni op code other than DATA
  kBadSyntax,    ///< text not of the form ID#DATA
  kBadId,        ///< identifier out of range for its form
  kTrailing,     ///< bytes left over after the declared content
  kNoSpace,      ///< output buffer too small
};
const char* CodecErrorName(CodecError error);

// --- Linux struct can_frame: u32 can_id (host order), u8 len, 3 pad, u8 data[8] --------------
inline constexpr std::size_t kRawFrameSize = 16;
void EncodeRawFrame(const CanFrame& frame, std::span<std::uint8_t, kRawFrameSize> out);
CodecError DecodeRawFrame(std::span<const std::uint8_t> in, CanFrame* frame);

// --- can-utils text: "123#DEADBEEF", "12345678#00" (extended), "123#R", "20000040#..." ---------
std::string FormatFrameText(const CanFrame& frame);
/// The longest text FormatFrameText writes: 8 id digits, '#', 16 data digits.
inline constexpr std::size_t kFrameTextMax = 8 + 1 + 16;
/// The same text into a fixed buffer (no allocation); returns its length.
std::size_t FormatFrameText(const CanFrame& frame, std::span<char, kFrameTextMax> out);
CodecError ParseFrameText(std::string_view text, CanFrame* frame);

// --- cannelloni v2 DATA datagram: u8 version=2, u8 op=0, u8 seq, u16 count (big endian), then
// per frame u32 can_id (big endian, Linux flags), u8 len, data[len] (no data for RTR frames).
inline constexpr std::uint8_t kCannelloniVersion = 2;
inline constexpr std::uint8_t kCannelloniOpData = 0;
inline constexpr std::size_t kCannelloniHeaderSize = 5;
/// Bytes one frame takes in a cannelloni datagram.
std::size_t CannelloniFrameSize(const CanFrame& frame);
/// Writes a datagram; returns bytes written, or 0 when `out` is too small.
std::size_t EncodeCannelloni(std::uint8_t seq, std::span<const CanFrame> frames,
                             std::span<std::uint8_t> out);
/// Decodes a datagram, appending to `frames` (which the caller may reuse across calls).
CodecError DecodeCannelloni(std::span<const std::uint8_t> in, std::uint8_t* seq,
                            std::vector<CanFrame>* frames);

}  // namespace pwsim::hw
