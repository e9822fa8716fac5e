#pragma once
// A small non-blocking UDP socket (IPv4) used by the CAN-over-UDP bus and the HMD bridge.
// Endpoints are "HOST:PORT" strings; port 0 binds an ephemeral port.
//
// A link that carries a person's platform accepts datagrams from its one peer only: after
// AcceptOnlyFrom(peer), Receive reads every waiting datagram but hands back only those whose
// source address AND port equal the peer's; the others are counted (refused()) and dropped.
// UDP source addresses can be forged by anyone on the same network, so this is a guard against
// stray and misdirected traffic, not authentication: docs/hardware.md says how to put the
// links on a network of their own.
//
// Authenticated mode (EnableAuth, link_auth.h): SendTo wraps every datagram with a tag under
// the pre-shared key, Receive hands back only datagrams whose tag verifies and that are fresh
// and not replayed (their payload, unwrapped); the link's HELLOs are answered inside Receive.
// Datagrams that fail the tag or the replay check are counted in refused() as well, since
// they are not the peer's whatever their source address says. Neither path allocates or throws.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "hardware/link_auth.h"

namespace pwsim::hw {

struct UdpAddress {
  std::uint32_t ip{0};    ///< network byte order
  std::uint16_t port{0};  ///< host byte order
  bool operator==(const UdpAddress&) const = default;
  std::string ToString() const;
};

/// Parses "HOST:PORT" (HOST a dotted IPv4 address or "localhost"). Empty on error.
std::optional<UdpAddress> ParseUdpAddress(const std::string& text);

/// Monotonic clock [ns] (CLOCK_MONOTONIC), the time base of every hardware timestamp.
std::int64_t MonotonicNs();

class UdpSocket {
 public:
  UdpSocket();
  ~UdpSocket();
  UdpSocket(UdpSocket&& other) noexcept;
  UdpSocket& operator=(UdpSocket&& other) noexcept;
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  /// Binds to `local` (port 0 = ephemeral). Returns an error message, or "" on success.
  std::string Bind(const UdpAddress& local);
  bool is_open() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  std::uint16_t local_port() const;

  /// Sends one datagram; false when the kernel refused it (counted by the caller).
  bool SendTo(const UdpAddress& to, std::span<const std::uint8_t> bytes);
  /// Receives one datagram into `buffer`; returns its size, or -1 when none waits.
  /// A datagram larger than the buffer is reported with size buffer.size()+1 (truncated).
  long Receive(std::span<std::uint8_t> buffer, UdpAddress* from);
  /// Waits up to `timeout_ms` for a datagram. False on timeout.
  bool WaitReadable(int timeout_ms) const;

  /// From now on Receive hands back only datagrams from `peer` (address and port).
  void AcceptOnlyFrom(const UdpAddress& peer) { peer_ = peer; }
  const std::optional<UdpAddress>& peer() const { return peer_; }
  /// Datagrams read and dropped because another sender sent them (in authenticated mode also
  /// those whose tag did not verify, that were replayed or that were not authenticated datagrams).
  std::uint64_t refused() const { return refused_; }

  /// Authenticated mode from now on, this end being `role` of a `kind` link with a new epoch
  /// (NewLinkEpoch). Allocates its state and buffers here, once.
  void EnableAuth(const LinkKey& key, LinkKind kind, LinkRole role);
  bool authenticated() const { return auth_ != nullptr; }
  /// The authenticated mode's counters; null in plain mode.
  const LinkAuthCounters* auth_counters() const;
  /// Authenticated mode: tells `to` this end's epoch now (a HELLO), so that its first datagrams
  /// are fresh. False in plain mode or when the kernel refused it.
  bool SendHello(const UdpAddress& to);

 private:
  struct Auth;
  bool SendRaw(const UdpAddress& to, std::span<const std::uint8_t> bytes);
  int fd_{-1};
  std::optional<UdpAddress> peer_;
  std::uint64_t refused_{0};
  std::unique_ptr<Auth> auth_;
};

}  // namespace pwsim::hw
