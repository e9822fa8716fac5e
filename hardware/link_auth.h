#pragma once
// Authenticated mode of the UDP links between pwsim processes (CAN over UDP, HMD bridge):
// every datagram is wrapped with a message authentication code under a pre-shared 32-byte
// key (libsodium crypto_auth: HMAC-SHA-512-256) and carries what the receiver needs to refuse
// replays. Plain datagrams (cannelloni, HMD messages) travel unchanged inside.
//
// Wire format (little endian, 32 B header + payload + 32 B tag):
//   u32 magic "PWLA" | u8 version = 1 | u8 link (1 CAN, 2 HMD) | u8 sender role (1 session end,
//   2 peer end) | u8 type (1 DATA, 2 HELLO) | u64 sender epoch | u64 echo | u64 counter |
//   payload (DATA: the plain datagram; HELLO: empty) | tag[32] = HMAC-SHA-512-256(key, all before it)
//
// Each end has an epoch E (CLOCK_REALTIME [ns] when it started, strictly increasing across
// restarts of one host's processes) and a counter c = 1, 2, ... per epoch. `echo` is the
// receiver's epoch as the sender last heard it (0: none yet). A receiver with epoch E_me
// takes a DATA datagram (after the tag verified) only when
//   link == its link, role != its own role (no reflection of its own datagrams),
//   echo == E_me          (fresh: sent after this end started; nothing recorded earlier passes),
//   epoch >= E_rx         (E_rx: the epoch of the last datagram taken; a larger one is the peer
//                          restarted: the window starts over and the restart is counted),
//   c is new in the window (c > c_max, or one of the 64 below c_max not yet taken).
// Every authenticated datagram (HELLO or DATA, fresh or not) teaches the receiver the sender's
// epoch: E_peer = max(E_peer, epoch), the value it echoes from then on. A datagram that verifies
// but does not echo E_me makes the receiver answer with a HELLO (at most one per
// kHelloIntervalNs), so a peer that (re)started learns E_me within one round trip; until then
// its DATA is dropped and counted as unconfirmed.
//
// Not protected: confidentiality (payloads are in clear), denial of service (anyone can flood
// the port; the tag check is the cost per datagram), and a host whose clock steps back past an
// earlier epoch of its own process (its restarted ends are refused until the receiver restarts).
//
// Seal and Open allocate nothing and never throw (the real-time path); the key file is read at
// start-up only.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace pwsim::hw {

inline constexpr std::uint32_t kLinkAuthMagic = 0x414C5750U;  // bytes "PWLA"
inline constexpr std::uint8_t kLinkAuthVersion = 1;
inline constexpr std::size_t kLinkKeyBytes = 32;
inline constexpr std::size_t kLinkTagBytes = 32;
inline constexpr std::size_t kLinkAuthHeaderSize = 32;
inline constexpr std::size_t kLinkAuthOverhead = kLinkAuthHeaderSize + kLinkTagBytes;
/// Largest payload a link carries (one Ethernet MTU's worth of UDP payload).
inline constexpr std::size_t kLinkMaxPayload = 1472 - kLinkAuthOverhead;
inline constexpr std::int64_t kHelloIntervalNs = 10'000'000;  ///< answers to one peer: <= 100/s
inline constexpr int kReplayWindow = 64;

enum class LinkKind : std::uint8_t { kCan = 1, kHmd = 2 };
/// Which end of a link: the session (or drive) is one, platform-sim / hmd-peer the other.
enum class LinkRole : std::uint8_t { kSession = 1, kPeer = 2 };
enum class LinkAuthType : std::uint8_t { kData = 1, kHello = 2 };

struct LinkKey {
  std::array<std::uint8_t, kLinkKeyBytes> bytes{};
};

/// Reads a key file: exactly 64 hexadecimal digits (32 bytes) and at most one final newline.
/// @throws InputError naming the file, line and what was wrong (missing, size, a non-hex
/// character, an all-zero key). `warning` (may be null) is set when the file is readable by
/// its group or by others ("" otherwise).
LinkKey ReadLinkKeyFile(const std::string& path, std::string* warning);

/// A new epoch for an end starting now: CLOCK_REALTIME [ns], and larger than any epoch this
/// process made before.
std::uint64_t NewLinkEpoch();

struct LinkAuthCounters {
  std::uint64_t sealed{0};       ///< datagrams wrapped for sending (DATA and HELLO)
  std::uint64_t accepted{0};     ///< DATA handed on
  std::uint64_t hellos{0};       ///< authenticated HELLOs taken (they carry no payload)
  std::uint64_t malformed{0};    ///< not an authenticated datagram of this link (size, magic,
                                 ///< version, link, type), or sent by this end's own role
  std::uint64_t bad_tag{0};      ///< the tag did not verify: another key, altered, forged
  std::uint64_t replayed{0};     ///< counter already taken or below the window, or an older epoch
  std::uint64_t unconfirmed{0};  ///< verified but does not echo this end's epoch (recorded before
                                 ///< it started, or a peer that has not heard it yet)
  std::uint64_t peer_restarts{0};  ///< DATA of a newer peer epoch taken after an older one
  std::uint64_t hellos_sent{0};
};

class LinkAuth {
 public:
  /// `epoch` > 0 (NewLinkEpoch()). Initialises libsodium (sodium_init) if needed.
  LinkAuth(const LinkKey& key, LinkKind kind, LinkRole role, std::uint64_t epoch);

  /// Wraps `payload` as DATA into `out`; returns the datagram size, 0 when it does not fit or
  /// libsodium could not start.
  std::size_t Seal(std::span<const std::uint8_t> payload, std::span<std::uint8_t> out);
  /// A HELLO (no payload) that tells the peer this end's epoch; returns its size (0: no space).
  std::size_t SealHello(std::span<std::uint8_t> out);

  enum class Verdict { kData, kHello, kDropped };
  /// Checks one received datagram (rules above) at local time `now_ns` (paces HELLO answers).
  /// kData: `*payload` views the plain datagram inside `in`. `*answer_hello` is set when the
  /// sender should get a HELLO now (SealHello); the caller sends it to the datagram's source.
  Verdict Open(std::span<const std::uint8_t> in, std::int64_t now_ns, std::span<const std::uint8_t>* payload,
               bool* answer_hello);

  std::uint64_t epoch() const { return epoch_; }
  /// The peer's epoch as last heard (0: none), echoed in every datagram sent.
  std::uint64_t peer_epoch() const { return peer_epoch_; }
  LinkKind kind() const { return kind_; }
  LinkRole role() const { return role_; }
  const LinkAuthCounters& counters() const { return counters_; }

 private:
  std::size_t SealType(LinkAuthType type, std::span<const std::uint8_t> payload, std::span<std::uint8_t> out);
  /// True when counter `c` of the current receive epoch was not taken yet; marks it taken.
  bool TakeCounter(std::uint64_t c);

  // parameters
  LinkKey key_;
  LinkKind kind_;
  LinkRole role_;
  std::uint64_t epoch_;
  bool ready_{false};  ///< libsodium initialised
  // send state
  std::uint64_t tx_counter_{0};
  std::uint64_t peer_epoch_{0};
  std::int64_t last_hello_ns_{0};
  bool hello_sent_{false};
  // receive state: the replay window of epoch rx_epoch_
  std::uint64_t rx_epoch_{0};
  std::uint64_t rx_max_{0};     ///< the largest counter taken in rx_epoch_
  std::uint64_t rx_window_{0};  ///< bit i: counter rx_max_ - i taken
  LinkAuthCounters counters_;
};

}  // namespace pwsim::hw
