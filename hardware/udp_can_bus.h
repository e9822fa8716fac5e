#pragma once
// CAN over UDP in cannelloni framing: each Send() is one cannelloni v2 DATA datagram carrying
// one frame, so two processes on loopback (or a real cannelloni on a lab machine) share a bus.
//
// The bus has exactly one peer and takes frames from no one else: datagrams whose source
// address or port differ from the peer's are read, counted (BusStats::rx_refused) and dropped
// before they are decoded. The peer is either configured (`remote`) or, only when asked for
// (`PeerPolicy::kAdoptConfirmed`, platform-sim's --adopt-first-peer), adopted once a sender
// has confirmed that it is a peer, never on its first datagram alone:
//   - a candidate is any sender of well-formed datagrams while the bus has no peer; up to
//     kCandidates of them are followed at once, each with its last kCandidateFrames frames;
//     their frames are held, not handed on;
//   - after each of its datagrams the confirmation (Options::confirm, e.g.
//     MasterStartsNodes: a CANopen master's start-up, an NMT command to the bus's nodes and
//     then a SYNC) sees the candidate's held frames, oldest first; true adopts it, its held
//     frames are handed on in order, and every other candidate's held datagrams are counted
//     refused;
//   - in authenticated mode only authenticated, fresh datagrams reach this logic at all, and
//     without a confirmation the first of them adopts its sender (the key is the proof).
// An adopted peer is fixed from then on.
//
// Authenticated mode (Options::key; link_auth.h): the same cannelloni datagrams wrapped with a
// tag under a pre-shared key. Not cannelloni on the wire any more: for links between pwsim
// processes; bridges to real CAN hardware (cannelloni) use the plain mode.
//
// Receive allocates nothing and never throws (the pending frames' storage is reserved at Open).

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hardware/can_bus.h"
#include "hardware/link_auth.h"
#include "hardware/udp_socket.h"

namespace pwsim::hw {

class UdpCanBus final : public ICanBus {
 public:
  enum class PeerPolicy {
    kConfigured,      ///< `remote` is the peer (required)
    kAdoptConfirmed,  ///< `remote` empty: a sender becomes the peer once it confirmed (above)
  };
  static constexpr std::size_t kCandidates = 4;
  static constexpr std::size_t kCandidateFrames = 16;
  /// Decides from a candidate's frames (its last kCandidateFrames, oldest first) whether it
  /// is a peer. Runs on the receive path: must not allocate or throw.
  using PeerConfirmation = std::function<bool(std::span<const CanFrame> frames)>;

  struct Options {
    PeerPolicy policy{PeerPolicy::kConfigured};
    /// kAdoptConfirmed: required in plain mode; optional in authenticated mode.
    PeerConfirmation confirm;
    /// Authenticated mode when set (copied at Open).
    std::optional<LinkKey> key;
    /// This end's role in authenticated mode (the session end, or the drives' end: kPeer).
    LinkRole role{LinkRole::kSession};
  };

  /// Binds `local` ("HOST:PORT", port 0 = ephemeral); sends to and accepts from `remote`, or,
  /// with kAdoptConfirmed, from the sender that confirmed. A missing or malformed remote, or
  /// an adopting bus without a way to confirm, is an error. An authenticated bus with a
  /// configured remote tells it its epoch at once (a HELLO).
  static BusOpenResult Open(const std::string& local, const std::string& remote, const Options& options);
  static BusOpenResult Open(const std::string& local, const std::string& remote) {
    return Open(local, remote, Options{});
  }

  BusStatus Send(const CanFrame& frame) override;
  BusStatus Receive(CanFrame* frame) override;
  int fd() const override { return socket_.fd(); }
  const BusStats& stats() const override { return stats_; }
  std::string name() const override;
  std::uint16_t local_port() const { return socket_.local_port(); }
  bool has_peer() const { return remote_.has_value(); }
  /// The peer ("HOST:PORT"), or "" while an adopting bus has none yet.
  std::string peer() const { return remote_ ? remote_->ToString() : ""; }
  bool authenticated() const { return socket_.authenticated(); }
  /// The authenticated mode's counters (null in plain mode).
  const LinkAuthCounters* auth_counters() const { return socket_.auth_counters(); }
  /// Datagrams of candidates held while adopting (0 once a peer is adopted).
  std::uint64_t held_datagrams() const;

 private:
  struct Candidate {
    UdpAddress from;
    std::array<CanFrame, kCandidateFrames> frames{};
    std::size_t count{0};          ///< frames held
    std::uint64_t datagrams{0};    ///< datagrams held (counted refused if another is adopted)
    std::uint64_t last_heard{0};   ///< order of arrival, for eviction
    bool used{false};
  };
  UdpCanBus() = default;
  /// A well-formed datagram's frames (in pending_) from `from` while no peer is adopted:
  /// held, and the sender adopted when it confirms (pending_ then holds its frames).
  void Consider(const UdpAddress& from);

  UdpSocket socket_;
  std::optional<UdpAddress> remote_;
  bool adopting_{false};
  PeerConfirmation confirm_;
  std::array<Candidate, kCandidates> candidates_{};
  std::uint64_t heard_{0};
  std::uint64_t candidates_refused_{0};  ///< held datagrams of candidates not adopted
  std::uint8_t tx_seq_{0};
  std::optional<std::uint8_t> rx_seq_;
  std::vector<CanFrame> pending_;
  std::size_t pending_pos_{0};
  BusStats stats_;
};

/// The CANopen confirmation for a bus that serves drives with node ids `nodes`: the candidate
/// sent an NMT command addressed to one of them (or to all, node 0) and after it a SYNC, as a
/// master's start-up does (cia402_master.h). A stranger's well-formed RPDO, SYNC or heartbeat
/// alone does not confirm.
UdpCanBus::PeerConfirmation MasterStartsNodes(std::vector<std::uint8_t> nodes);

}  // namespace pwsim::hw
