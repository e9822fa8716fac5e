#include "hardware/udp_socket.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

namespace pwsim::hw {

std::string UdpAddress::ToString() const {
  in_addr a{};
  a.s_addr = ip;
  char buf[INET_ADDRSTRLEN] = {};
  ::inet_ntop(AF_INET, &a, buf, sizeof(buf));
  return std::string(buf) + ":" + std::to_string(port);
}

std::optional<UdpAddress> ParseUdpAddress(const std::string& text) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 >= text.size()) return std::nullopt;
  std::string host = text.substr(0, colon);
  if (host == "localhost") host = "127.0.0.1";
  in_addr a{};
  if (::inet_pton(AF_INET, host.c_str(), &a) != 1) return std::nullopt;
  unsigned long port = 0;
  for (std::size_t i = colon + 1; i < text.size(); ++i) {
    const char c = text[i];
    if (c < '0' || c > '9') return std::nullopt;
    port = port * 10 + static_cast<unsigned long>(c - '0');
    if (port > 65535) return std::nullopt;
  }
  return UdpAddress{a.s_addr, static_cast<std::uint16_t>(port)};
}

std::int64_t MonotonicNs() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

/// The authenticated mode's state and its two datagram buffers (allocated once, by EnableAuth).
struct UdpSocket::Auth {
  Auth(const LinkKey& key, LinkKind kind, LinkRole role) : link(key, kind, role, NewLinkEpoch()) {}
  LinkAuth link;
  std::array<std::uint8_t, kLinkAuthOverhead + kLinkMaxPayload> rx{};
  std::array<std::uint8_t, kLinkAuthOverhead + kLinkMaxPayload> tx{};
};

UdpSocket::UdpSocket() = default;
UdpSocket::~UdpSocket() {
  if (fd_ >= 0) ::close(fd_);
}
UdpSocket::UdpSocket(UdpSocket&& other) noexcept
    : fd_(other.fd_), peer_(other.peer_), refused_(other.refused_), auth_(std::move(other.auth_)) {
  other.fd_ = -1;
}
UdpSocket& UdpSocket::operator=(UdpSocket&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    peer_ = other.peer_;
    refused_ = other.refused_;
    auth_ = std::move(other.auth_);
    other.fd_ = -1;
  }
  return *this;
}

void UdpSocket::EnableAuth(const LinkKey& key, LinkKind kind, LinkRole role) {
  auth_ = std::make_unique<Auth>(key, kind, role);
}

const LinkAuthCounters* UdpSocket::auth_counters() const {
  return auth_ ? &auth_->link.counters() : nullptr;
}

bool UdpSocket::SendHello(const UdpAddress& to) {
  if (!auth_) return false;
  const std::size_t n = auth_->link.SealHello(auth_->tx);
  return n > 0 && SendRaw(to, std::span<const std::uint8_t>(auth_->tx.data(), n));
}

std::string UdpSocket::Bind(const UdpAddress& local) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) return std::string("socket(AF_INET, SOCK_DGRAM) failed: ") + std::strerror(errno);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = local.ip;
  addr.sin_port = htons(local.port);
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    const std::string message = "bind " + local.ToString() + " failed: " + std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
    return message;
  }
  return "";
}

std::uint16_t UdpSocket::local_port() const {
  sockaddr_in addr{};
  socklen_t len = sizeof(addr);
  if (fd_ < 0 || ::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return 0;
  return ntohs(addr.sin_port);
}

bool UdpSocket::SendTo(const UdpAddress& to, std::span<const std::uint8_t> bytes) {
  if (!auth_) return SendRaw(to, bytes);
  const std::size_t n = auth_->link.Seal(bytes, auth_->tx);
  return n > 0 && SendRaw(to, std::span<const std::uint8_t>(auth_->tx.data(), n));
}

bool UdpSocket::SendRaw(const UdpAddress& to, std::span<const std::uint8_t> bytes) {
  if (fd_ < 0) return false;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = to.ip;
  addr.sin_port = htons(to.port);
  const ssize_t n = ::sendto(fd_, bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL,
                             reinterpret_cast<sockaddr*>(&addr), sizeof(addr));
  return n == static_cast<ssize_t>(bytes.size());
}

long UdpSocket::Receive(std::span<std::uint8_t> buffer, UdpAddress* from) {
  if (fd_ < 0) return -1;
  for (;;) {
    sockaddr_in addr{};
    socklen_t len = sizeof(addr);
    const std::span<std::uint8_t> into = auth_ ? std::span<std::uint8_t>(auth_->rx) : buffer;
    const ssize_t n = ::recvfrom(fd_, into.data(), into.size(), MSG_DONTWAIT | MSG_TRUNC,
                                 reinterpret_cast<sockaddr*>(&addr), &len);
    if (n < 0) {
      if (errno == EINTR) continue;
      return -1;  // EAGAIN, or ECONNREFUSED from an earlier send: nothing to read
    }
    const UdpAddress sender{addr.sin_addr.s_addr, ntohs(addr.sin_port)};
    if (peer_ && sender != *peer_) {
      ++refused_;  // not our peer: read, counted and dropped
      continue;
    }
    if (!auth_) {
      if (from != nullptr) *from = sender;
      if (static_cast<std::size_t>(n) > buffer.size()) return static_cast<long>(buffer.size()) + 1;
      return static_cast<long>(n);
    }
    // Authenticated mode. A datagram larger than the buffer is no datagram of ours: it is
    // handed to Open as empty, which counts it malformed.
    const std::span<const std::uint8_t> datagram =
        static_cast<std::size_t>(n) > into.size() ? std::span<const std::uint8_t>()
                                                   : std::span<const std::uint8_t>(into.data(), static_cast<std::size_t>(n));
    std::span<const std::uint8_t> payload;
    bool answer = false;
    const std::uint64_t unconfirmed = auth_->link.counters().unconfirmed;
    const LinkAuth::Verdict verdict = auth_->link.Open(datagram, MonotonicNs(), &payload, &answer);
    if (answer) (void)SendHello(sender);
    if (verdict == LinkAuth::Verdict::kHello) continue;
    if (verdict != LinkAuth::Verdict::kData) {
      if (auth_->link.counters().unconfirmed == unconfirmed) ++refused_;  // not the peer's
      continue;
    }
    if (from != nullptr) *from = sender;
    const std::size_t copy = std::min(payload.size(), buffer.size());
    std::memcpy(buffer.data(), payload.data(), copy);
    if (payload.size() > buffer.size()) return static_cast<long>(buffer.size()) + 1;
    return static_cast<long>(payload.size());
  }
}

bool UdpSocket::WaitReadable(int timeout_ms) const {
  if (fd_ < 0) return false;
  pollfd p{fd_, POLLIN, 0};
  return ::poll(&p, 1, timeout_ms) > 0;
}

}  // namespace pwsim::hw
