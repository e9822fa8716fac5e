#pragma once
// A UDP datagram with a forged source address, sent for real through a raw IPv4 socket
// (IP_HDRINCL): what anyone on the same network can do, and what the plain links' peer check
// cannot tell from the peer's own datagrams.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/ip.h>
#include <netinet/udp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

#include "hardware/udp_socket.h"

namespace pwsim::test {

/// Sends `payload` to `to` as UDP from `from` (forged) through a raw IPv4 socket. nullopt when
/// this process may not open one (no CAP_NET_RAW), else whether the kernel took it.
inline std::optional<bool> SendForgedUdp(const hw::UdpAddress& from, const hw::UdpAddress& to,
                                         const std::vector<std::uint8_t>& payload) {
  const int fd = ::socket(AF_INET, SOCK_RAW, IPPROTO_RAW);
  if (fd < 0) return std::nullopt;
  const int on = 1;
  ::setsockopt(fd, IPPROTO_IP, IP_HDRINCL, &on, sizeof(on));
  std::vector<std::uint8_t> packet(sizeof(iphdr) + sizeof(udphdr) + payload.size());
  iphdr ip{};
  ip.version = 4;
  ip.ihl = 5;
  ip.ttl = 64;
  ip.protocol = IPPROTO_UDP;
  ip.tot_len = htons(static_cast<std::uint16_t>(packet.size()));
  ip.saddr = from.ip;
  ip.daddr = to.ip;  // the kernel fills in the id and the header checksum
  udphdr udp{};
  udp.source = htons(from.port);
  udp.dest = htons(to.port);
  udp.len = htons(static_cast<std::uint16_t>(sizeof(udphdr) + payload.size()));
  udp.check = 0;  // no checksum (allowed on IPv4)
  std::memcpy(packet.data(), &ip, sizeof(ip));
  std::memcpy(packet.data() + sizeof(ip), &udp, sizeof(udp));
  std::memcpy(packet.data() + sizeof(ip) + sizeof(udp), payload.data(), payload.size());
  sockaddr_in dst{};
  dst.sin_family = AF_INET;
  dst.sin_addr.s_addr = to.ip;
  const ssize_t n = ::sendto(fd, packet.data(), packet.size(), 0, reinterpret_cast<sockaddr*>(&dst), sizeof(dst));
  ::close(fd);
  return n == static_cast<ssize_t>(packet.size());
}

}  // namespace pwsim::test
