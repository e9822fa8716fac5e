#include "hardware/udp_can_bus.h"

#include <algorithm>
#include <array>
#include <cerrno>

#include "hardware/canopen.h"

namespace pwsim::hw {

BusOpenResult UdpCanBus::Open(const std::string& local, const std::string& remote, const Options& options) {
  BusOpenResult result;
  const auto local_addr = ParseUdpAddress(local);
  if (!local_addr) {
    result.error = EINVAL;
    result.message = "bad local UDP address '" + local + "' (expected HOST:PORT)";
    return result;
  }
  std::unique_ptr<UdpCanBus> bus(new UdpCanBus());
  if (options.policy == PeerPolicy::kAdoptConfirmed) {
    if (!remote.empty()) {
      result.error = EINVAL;
      result.message = "a bus that adopts its peer takes no remote address (got '" + remote + "')";
      return result;
    }
    if (!options.confirm && !options.key) {
      result.error = EINVAL;
      result.message = "a plain bus that adopts its peer needs a confirmation (a sender's first datagram is not one)";
      return result;
    }
    bus->adopting_ = true;
    bus->confirm_ = options.confirm;
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
  if (options.key) {
    bus->socket_.EnableAuth(*options.key, LinkKind::kCan, options.role);
    if (bus->remote_) (void)bus->socket_.SendHello(*bus->remote_);
  }
  bus->pending_.reserve(64);
  result.bus = std::move(bus);
  return result;
}

std::string UdpCanBus::name() const {
  return std::string(authenticated() ? "udp+auth:" : "udp:") + std::to_string(local_port()) + "->" +
         (remote_ ? remote_->ToString() : "?");
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

void UdpCanBus::Consider(const UdpAddress& from) {
  // The candidate's slot: its own, else a free one, else the one heard from longest ago.
  Candidate* slot = nullptr;
  for (Candidate& c : candidates_)
    if (c.used && c.from == from) slot = &c;
  if (slot == nullptr) {
    for (Candidate& c : candidates_)
      if (!c.used) {
        slot = &c;
        break;
      }
  }
  if (slot == nullptr) {
    slot = &*std::min_element(candidates_.begin(), candidates_.end(),
                              [](const Candidate& a, const Candidate& b) { return a.last_heard < b.last_heard; });
    candidates_refused_ += slot->datagrams;  // evicted: what it sent is dropped
  }
  if (!slot->used || slot->from != from) *slot = Candidate{from, {}, 0, 0, 0, true};
  slot->last_heard = ++heard_;
  ++slot->datagrams;
  for (const CanFrame& f : pending_) {  // keep the newest kCandidateFrames
    if (slot->count == slot->frames.size()) {
      std::move(slot->frames.begin() + 1, slot->frames.end(), slot->frames.begin());
      --slot->count;
    }
    slot->frames[slot->count++] = f;
  }
  pending_.clear();
  const std::span<const CanFrame> held(slot->frames.data(), slot->count);
  const bool confirmed = confirm_ ? confirm_(held) : socket_.authenticated();
  if (!confirmed) return;
  remote_ = from;
  socket_.AcceptOnlyFrom(from);
  adopting_ = false;
  pending_.assign(held.begin(), held.end());  // within the reserved capacity (64 >= 16)
  for (Candidate& c : candidates_) {
    if (c.used && &c != slot) candidates_refused_ += c.datagrams;
    c.used = false;
  }
}

std::uint64_t UdpCanBus::held_datagrams() const {
  std::uint64_t n = 0;
  for (const Candidate& c : candidates_)
    if (c.used) n += c.datagrams;
  return n;
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
    stats_.rx_refused = socket_.refused() + candidates_refused_;
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
    if (adopting_) {
      Consider(from);
      stats_.rx_refused = socket_.refused() + candidates_refused_;
      if (adopting_) continue;  // held, not handed on
    }
    if (rx_seq_) {
      const auto gap = static_cast<std::uint8_t>(seq - static_cast<std::uint8_t>(*rx_seq_ + 1));
      if (gap != 0 && gap < 128) stats_.rx_lost += gap;
    }
    rx_seq_ = seq;
  }
}

UdpCanBus::PeerConfirmation MasterStartsNodes(std::vector<std::uint8_t> nodes) {
  return [nodes = std::move(nodes)](std::span<const CanFrame> frames) {
    bool nmt_to_us = false;
    for (const CanFrame& f : frames) {
      canopen::NmtCommand command{};
      std::uint8_t node = 0;
      std::uint8_t counter = 0;
      if (canopen::DecodeNmt(f, &command, &node)) {
        if (node == 0 || std::find(nodes.begin(), nodes.end(), node) != nodes.end()) nmt_to_us = true;
      } else if (nmt_to_us && canopen::DecodeSync(f, &counter)) {
        return true;
      }
    }
    return false;
  };
}

}  // namespace pwsim::hw
