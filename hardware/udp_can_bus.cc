#include "hardware/udp_can_bus.h"

#include <array>
#include <cerrno>

namespace pwsim::hw {

BusOpenResult UdpCanBus::Open(const std::string& local, const std::string& remote, PeerPolicy policy) {
  BusOpenResult result;
  const auto local_addr = ParseUdpAddress(local);
  if (!local_addr) {
    result.error = EINVAL;
    result.message = "bad local UDP address '" + local + "' (expected HOST:PORT)";
    return result;
  }
  std::unique_ptr<UdpCanBus> bus(new UdpCanBus());
  if (policy == PeerPolicy::kAdoptFirst) {
    if (!remote.empty()) {
      result.error = EINVAL;
      result.message = "a bus that adopts its first sender takes no remote address (got '" + remote + "')";
      return result;
    }
    bus->learn_peer_ = true;
  } else {
    bus->remote_ = ParseUdpAddress(remote);
    if (!bus->remote_) {
      result.error = EINVAL;
      result.message = "bad or missing peer UDP address '" + remote + "' (expected HOST:PORT)";
      return result;
    }
    bus->socket_.AcceptOnlyFrom(*bus->remote_);
  }
  const std::string error = bus->socket_.Bind(*local_addr);
  if (!error.empty()) {
    result.error = EADDRNOTAVAIL;
    result.message = error;
    return result;
  }
  bus->pending_.reserve(64);
  result.bus = std::move(bus);
  return result;
}

std::string UdpCanBus::name() const {
  return "udp:" + std::to_string(local_port()) + "->" + (remote_ ? remote_->ToString() : "?");
}

BusStatus UdpCanBus::Send(const CanFrame& frame) {
  if (!remote_) {
    ++stats_.tx_failed;
    return BusStatus::kWouldBlock;  // no peer known yet
  }
  std::array<std::uint8_t, kCannelloniHeaderSize + 13> buffer{};
  const std::size_t n = EncodeCannelloni(tx_seq_, std::span<const CanFrame>(&frame, 1), buffer);
  if (n == 0) {
    ++stats_.tx_failed;
    return BusStatus::kError;
  }
  if (!socket_.SendTo(*remote_, std::span<const std::uint8_t>(buffer.data(), n))) {
    ++stats_.tx_failed;
    return BusStatus::kWouldBlock;
  }
  ++tx_seq_;
  ++stats_.tx;
  return BusStatus::kOk;
}

BusStatus UdpCanBus::Receive(CanFrame* frame) {
  for (;;) {
    if (pending_pos_ < pending_.size()) {
      *frame = pending_[pending_pos_++];
      ++stats_.rx;
      if (frame->error()) ++stats_.error_frames;
      return BusStatus::kOk;
    }
    pending_.clear();
    pending_pos_ = 0;
    std::array<std::uint8_t, 1500> buffer{};
    UdpAddress from;
    const long n = socket_.Receive(buffer, &from);  // drops (and counts) other senders
    stats_.rx_refused = socket_.refused();
    if (n < 0) return BusStatus::kWouldBlock;
    if (static_cast<std::size_t>(n) > buffer.size()) {
      ++stats_.rx_malformed;
      continue;
    }
    std::uint8_t seq = 0;
    if (DecodeCannelloni(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)),
                         &seq, &pending_) != CodecError::kOk) {
      ++stats_.rx_malformed;
      pending_.clear();
      continue;
    }
    if (rx_seq_) {
      const auto gap = static_cast<std::uint8_t>(seq - static_cast<std::uint8_t>(*rx_seq_ + 1));
      if (gap != 0 && gap < 128) stats_.rx_lost += gap;
    }
    rx_seq_ = seq;
    if (learn_peer_) {  // adopted once, on the first well-formed datagram; fixed from then on
      remote_ = from;
      socket_.AcceptOnlyFrom(from);
      learn_peer_ = false;
    }
  }
}

}  // namespace pwsim::hw
