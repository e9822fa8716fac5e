#pragma once
// CAN over UDP in cannelloni framing: each Send() is one cannelloni v2 DATA datagram carrying
// one frame, so two processes on loopback (or a real cannelloni on a lab machine) share a bus.
//
// The bus has exactly one peer and takes frames from no one else: datagrams whose source
// address or port differ from the peer's are read, counted (BusStats::rx_refused) and dropped
// before they are decoded. The peer is either configured (`remote`) or, only when asked for
// (`PeerPolicy::kAdoptFirst`, the platform-sim side in tests), the sender of the first
// well-formed datagram, fixed from then on.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hardware/can_bus.h"
#include "hardware/udp_socket.h"

namespace pwsim::hw {

class UdpCanBus final : public ICanBus {
 public:
  enum class PeerPolicy {
    kConfigured,  ///< `remote` is the peer (required)
    kAdoptFirst,  ///< `remote` empty: the first well-formed datagram's sender becomes the peer
  };
  /// Binds `local` ("HOST:PORT", port 0 = ephemeral); sends to and accepts from `remote`, or,
  /// with kAdoptFirst, from the first sender. A missing or malformed remote is an error.
  static BusOpenResult Open(const std::string& local, const std::string& remote,
                            PeerPolicy policy = PeerPolicy::kConfigured);

  BusStatus Send(const CanFrame& frame) override;
  BusStatus Receive(CanFrame* frame) override;
  int fd() const override { return socket_.fd(); }
  const BusStats& stats() const override { return stats_; }
  std::string name() const override;
  std::uint16_t local_port() const { return socket_.local_port(); }
  bool has_peer() const { return remote_.has_value(); }
  /// The peer ("HOST:PORT"), or "" while a kAdoptFirst bus has none yet.
  std::string peer() const { return remote_ ? remote_->ToString() : ""; }

 private:
  UdpCanBus() = default;
  UdpSocket socket_;
  std::optional<UdpAddress> remote_;
  bool learn_peer_{false};
  std::uint8_t tx_seq_{0};
  std::optional<std::uint8_t> rx_seq_;
  std::vector<CanFrame> pending_;
  std::size_t pending_pos_{0};
  BusStats stats_;
};

}  // namespace pwsim::hw
