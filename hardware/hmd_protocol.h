#pragma once
// The HMD bridge protocol: one message per UDP datagram, little endian, fixed layouts.
//   header (24 B): magic "PWHM" | u16 version | u16 type | u32 seq | u32 session | i64 t_send_ns
//   1 CAMERA_POSE  (session -> headset, each visual frame): i64 tick | i64 frame | camera pose
//                  (f64 p[3] m, f64 q[4] x,y,z,w; world W) | f64 platform[2] (yaw rad, rail m,
//                  as commanded: lets a simulated headset ride the platform)          88 B
//   2 HEAD_POSE    (headset -> session): i64 t_sample_ns (sender clock) | head pose in the room
//                  (tracker frame, platform motion included) | i64 last_frame |
//                  i64 t_frame_rx_ns (sender clock, when last_frame arrived)          80 B
//   3 PING: i64 t0 | 4 PONG: i64 t0, t1 (ping received), t2 (pong sent) | 5 BYE: empty
//   6 HELLO        (either way; an addition to version 1): u32 stream | u32 echo       8 B
// Receivers accept only the newest seq per type, drop stale messages (older than a window on
// the receiver's clock, once the clock offset is known), and count every drop.
//
// Streams (the start-up that lets a restarted end back in). Each end that runs it has a stream
// id, random and non-zero, new at every start, and puts it in the header's `session` field of
// everything it sends (the session its session_id; headsets used to echo the session's id
// there, which nobody checked). Its seq counts from 0 in each stream. HELLO says "my stream is
// `stream`, yours as I last heard it is `echo`" (0: not yet). A receiver with stream S_me:
//   HELLO with echo == S_me and a stream other than the confirmed one: the sender heard us, so
//     its stream is confirmed: every per-type seq starts over (a restart is counted when
//     another stream was confirmed before), and it is answered (so that it confirms us too);
//   HELLO with echo != S_me: the sender does not know our stream: answered, nothing changes;
//   HELLO with echo == S_me of the confirmed stream: nothing to do (ends the exchange);
//   any other message whose header names a stream other than the confirmed one: dropped and
//     counted (other_stream), and a HELLO is wanted (TakeHelloWanted, at most one per 100 ms
//     of receive time).
// The answer is HelloAnswer(): {S_me, the stream last heard}. From either side the exchange
// is HELLO{A, ?} -> HELLO{B, A} -> HELLO{A, B} -> HELLO{B, A}: both confirmed in two round trips.
// An end that never sent a HELLO (older headsets) is taken as before: nothing is confirmed and
// no stream is checked. A blind spoofer who cannot read our datagrams does not learn S_me.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include "hardware/can_frame.h"  // CodecError

namespace pwsim::hw {

inline constexpr std::uint32_t kHmdMagic = 0x4D485750U;  // bytes "PWHM"
inline constexpr std::uint16_t kHmdVersion = 1;
inline constexpr std::size_t kHmdHeaderSize = 24;
inline constexpr std::size_t kHmdMaxSize = 128;

enum class HmdType : std::uint16_t { kCameraPose = 1, kHeadPose = 2, kPing = 3, kPong = 4, kBye = 5, kHello = 6 };

struct Pose {
  std::array<double, 3> p{0.0, 0.0, 0.0};
  std::array<double, 4> q{0.0, 0.0, 0.0, 1.0};  ///< x, y, z, w
  bool operator==(const Pose&) const = default;
};

struct HmdHeader {
  HmdType type{HmdType::kPing};
  std::uint32_t seq{0};
  std::uint32_t session{0};
  std::int64_t t_send_ns{0};
  bool operator==(const HmdHeader&) const = default;
};

struct CameraPoseMsg {
  std::int64_t tick{0};
  std::int64_t frame{0};
  Pose camera;
  std::array<double, 2> platform{};
  bool operator==(const CameraPoseMsg&) const = default;
};
struct HeadPoseMsg {
  std::int64_t t_sample_ns{0};
  Pose head;
  std::int64_t last_frame{-1};
  std::int64_t t_frame_rx_ns{0};
  bool operator==(const HeadPoseMsg&) const = default;
};
struct PingMsg {
  std::int64_t t0{0};
  bool operator==(const PingMsg&) const = default;
};
struct PongMsg {
  std::int64_t t0{0}, t1{0}, t2{0};
  bool operator==(const PongMsg&) const = default;
};
struct ByeMsg {
  bool operator==(const ByeMsg&) const = default;
};
struct HelloMsg {
  std::uint32_t stream{0};  ///< the sender's stream id (non-zero)
  std::uint32_t echo{0};    ///< the receiver's stream as the sender last heard it (0: none)
  bool operator==(const HelloMsg&) const = default;
};
using HmdBody = std::variant<CameraPoseMsg, HeadPoseMsg, PingMsg, PongMsg, ByeMsg, HelloMsg>;

struct HmdMessage {
  HmdHeader header;
  HmdBody body;
  bool operator==(const HmdMessage&) const = default;
};

/// Encodes (the header's type is taken from the body). Returns bytes written, 0 if no space.
std::size_t EncodeHmd(const HmdMessage& message, std::span<std::uint8_t> out);
/// Decodes one datagram: magic, version, type and exact size checked; poses must be finite, a
/// HELLO's stream non-zero.
CodecError DecodeHmd(std::span<const std::uint8_t> in, HmdMessage* message);

/// A new stream id: random (getrandom), non-zero.
std::uint32_t NewHmdStreamId();

/// NTP-style clock offset from ping/pong (peer clock minus local clock), keeping the sample
/// with the smallest round trip among the last `window` ones.
class ClockOffsetEstimator {
 public:
  /// Keeps its window in a ring allocated here: AddSample allocates nothing.
  explicit ClockOffsetEstimator(std::size_t window = 16);
  /// t0 ping sent (local), t1 ping received (peer), t2 pong sent (peer), t3 pong received (local).
  void AddSample(std::int64_t t0, std::int64_t t1, std::int64_t t2, std::int64_t t3);
  bool valid() const { return count_ > 0; }
  std::int64_t offset_ns() const;  ///< peer - local
  std::int64_t rtt_ns() const;     ///< of the sample used
  std::size_t samples() const { return total_; }

 private:
  struct Sample {
    std::int64_t offset;
    std::int64_t rtt;
  };
  /// The sample of smallest round trip, the oldest among equals (nullptr when none).
  const Sample* Best() const;
  std::vector<Sample> ring_;  ///< the last window samples, oldest at head_
  std::size_t head_{0};
  std::size_t count_{0};
  std::size_t total_{0};
};

/// Per-type newest-sequence and staleness filter with drop counters.
struct HmdRxCounters {
  std::uint64_t accepted{0};
  std::uint64_t out_of_order{0};  ///< seq not newer than the last accepted (incl. duplicates)
  std::uint64_t stale{0};
  std::uint64_t malformed{0};
  std::uint64_t other_stream{0};  ///< from a stream other than the confirmed one
  std::uint64_t restarts{0};      ///< the peer's confirmed stream changed (it restarted)
};

class HmdReceiveFilter {
 public:
  /// `own_stream` != 0: this end runs the stream start-up (above) with that id; 0: it does
  /// not (HELLOs are ignored, nothing is confirmed).
  explicit HmdReceiveFilter(std::int64_t stale_after_ns = 100'000'000, std::uint32_t own_stream = 0)
      : stale_after_ns_(stale_after_ns), own_stream_(own_stream) {}
  /// Returns true when `message`, received at local time `rx_ns`, should be used; for a HELLO,
  /// true when it must be answered with HelloAnswer(). `offset` (peer - local) enables the
  /// staleness check when valid.
  bool Accept(const HmdMessage& message, std::int64_t rx_ns, const ClockOffsetEstimator& offset);
  void CountMalformed() { ++counters_.malformed; }
  const HmdRxCounters& counters() const { return counters_; }
  /// The HELLO this end sends: its stream and the peer's as last heard.
  HelloMsg HelloAnswer() const { return {own_stream_, heard_stream_}; }
  /// True once since a message of an unconfirmed stream asked for a HELLO (then cleared).
  bool TakeHelloWanted();
  /// The peer's confirmed stream (0: none yet).
  std::uint32_t peer_stream() const { return peer_stream_; }
  std::uint32_t own_stream() const { return own_stream_; }

 private:
  // parameters
  std::int64_t stale_after_ns_;
  std::uint32_t own_stream_;
  // state
  std::array<std::int64_t, 7> last_seq_{-1, -1, -1, -1, -1, -1, -1};
  std::uint32_t peer_stream_{0};   ///< confirmed
  std::uint32_t heard_stream_{0};  ///< the latest the peer named
  bool hello_wanted_{false};
  std::int64_t last_wanted_ns_{0};
  bool wanted_before_{false};
  HmdRxCounters counters_;
};

/// a - b, saturated to the int64 range (peer timestamps are outside input).
std::int64_t SaturatingSub(std::int64_t a, std::int64_t b);

// --- poses ---------------------------------------------------------------------------------
Pose ComposePose(const Pose& a, const Pose& b);  ///< a * b
Pose InversePose(const Pose& a);
/// The platform top in the room for seed 001's RP chain: Rz(yaw) then translation rail along x.
Pose PlatformPose(double yaw, double rail);
/// Motion compensation: the head relative to the moving platform, X_PH = X_RP^-1 * X_RH.
Pose CompensateHeadPose(const Pose& head_in_room, double yaw, double rail);

}  // namespace pwsim::hw
