#pragma once
// CAN over UDP in cannelloni framing: each Send() is one cannelloni v2 DATA datagram carrying
// one frame, so two processes on loopback (or a real cannelloni on a lab machine) share a bus.
// A bus opened without a remote answers whoever sent to it last (the platform-sim side).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hardware/can_bus.h"
#include "hardware/udp_socket.h"

namespace pwsim::hw {

class UdpCanBus final : public ICanBus {
 public:
  /// Binds `local` ("HOST:PORT", port 0 = ephemeral) and sends to `remote` (may be empty).
  static BusOpenResult Open(const std::string& local, const std::string& remote);

  BusStatus Send(const CanFrame& frame) override;
  BusStatus Receive(CanFrame* frame) override;
  int fd() const override { return socket_.fd(); }
  const BusStats& stats() const override { return stats_; }
  std::string name() const override;
  std::uint16_t local_port() const { return socket_.local_port(); }
  bool has_peer() const { return remote_.has_value(); }

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
