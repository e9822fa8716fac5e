// The links' receive and send paths allocate nothing once open (the real-time rule): an
// authenticated CAN bus pair exchanging frames, replayed / forged / garbage datagrams being
// refused, an adopting bus holding a stranger's frames and adopting a master, and the
// authenticated HMD socket with the decoder and the stream filter. Its own executable: it
// replaces the global operator new to count allocations.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include "hardware/canopen.h"
#include "hardware/hmd_protocol.h"
#include "hardware/link_auth.h"
#include "hardware/udp_can_bus.h"
#include "hardware/udp_socket.h"
#include "tests/hardware/forged_udp.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace pwsim::hw {
namespace {

LinkKey Key() {
  LinkKey k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<std::uint8_t>(5 * i + 3);
  return k;
}
std::string Loopback(std::uint16_t port) { return "127.0.0.1:" + std::to_string(port); }

/// Takes what waits on `bus` until `frames` frames arrived or the guard (a count of waits) ran out.
int ReceiveFrames(ICanBus& bus, int frames) {
  int got = 0;
  CanFrame f;
  for (int waits = 0; got < frames && waits < 1000; ++waits) {
    while (bus.Receive(&f) == BusStatus::kOk) ++got;
    if (got < frames) WaitReadable(bus, 10);
  }
  return got;
}

TEST(LinkAlloc, AuthenticatedCanFramesBothWaysAndRefusalsAllocateNothing) {
  UdpCanBus::Options drives_options, session_options;
  drives_options.key = session_options.key = Key();
  drives_options.role = LinkRole::kPeer;
  UdpSocket reserve;
  ASSERT_EQ(reserve.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  const std::uint16_t session_port = reserve.local_port();
  reserve = UdpSocket();
  BusOpenResult drives = UdpCanBus::Open("127.0.0.1:0", Loopback(session_port), drives_options);
  ASSERT_TRUE(drives.bus) << drives.message;
  const std::uint16_t drives_port = static_cast<UdpCanBus&>(*drives.bus).local_port();
  BusOpenResult session = UdpCanBus::Open(Loopback(session_port), Loopback(drives_port), session_options);
  ASSERT_TRUE(session.bus) << session.message;
  // Warm up: the HELLO exchange, first frames both ways.
  CanFrame f;
  for (int i = 0; i < 200 && (drives.bus->stats().rx == 0 || session.bus->stats().rx == 0); ++i) {
    (void)session.bus->Send(canopen::EncodeSync(1));
    (void)drives.bus->Send(canopen::EncodeHeartbeat(1, canopen::NmtState::kOperational));
    WaitReadable(*drives.bus, 10);
    while (drives.bus->Receive(&f) == BusStatus::kOk) {
    }
    WaitReadable(*session.bus, 10);
    while (session.bus->Receive(&f) == BusStatus::kOk) {
    }
  }
  ASSERT_GT(drives.bus->stats().rx, 0U);
  ASSERT_GT(session.bus->stats().rx, 0U);
  // A stranger's datagrams under another key: from its own address (refused by address), and,
  // where a raw socket may be opened, 50 with the session's address (refused by the tag check),
  // queued before the measurement and read inside it.
  LinkAuth foreign([] {
    LinkKey k = Key();
    k.bytes[0] ^= 1;
    return k;
  }(), LinkKind::kCan, LinkRole::kSession, NewLinkEpoch());
  std::vector<std::uint8_t> forged(256);
  const std::uint8_t plain[5] = {2, 0, 0, 0, 0};
  forged.resize(foreign.Seal(plain, forged));
  UdpSocket stranger;
  ASSERT_EQ(stranger.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  const UdpAddress drives_at = *ParseUdpAddress(Loopback(drives_port));
  int forged_sent = 0;
  for (int i = 0; i < 50; ++i) {
    const auto sent = test::SendForgedUdp(*ParseUdpAddress(Loopback(session_port)), drives_at, forged);
    if (!sent) break;
    forged_sent += *sent ? 1 : 0;
  }

  const long before = g_allocations.load();
  int received = 0;
  for (int i = 0; i < 200; ++i) {
    (void)session.bus->Send(canopen::EncodeSync(static_cast<std::uint8_t>(i % 240 + 1)));
    (void)session.bus->Send(canopen::EncodeCspCommand(2, {canopen::controlword::kEnableOperation, i}));
    (void)stranger.SendTo(drives_at, forged);
    received += ReceiveFrames(*drives.bus, 2);
    (void)drives.bus->Send(canopen::EncodeCspStatus(2, {0x0237, i}));
    received += ReceiveFrames(*session.bus, 1);
  }
  const long allocations = g_allocations.load() - before;
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(received, 600);
  EXPECT_EQ(drives.bus->stats().rx_refused, 200U + static_cast<std::uint64_t>(forged_sent));
  EXPECT_EQ(static_cast<UdpCanBus&>(*drives.bus).auth_counters()->bad_tag, static_cast<std::uint64_t>(forged_sent));
}

TEST(LinkAlloc, AnAdoptingBusHoldsAStrangerAndAdoptsAMasterWithoutAllocating) {
  UdpCanBus::Options adopt;
  adopt.policy = UdpCanBus::PeerPolicy::kAdoptConfirmed;
  adopt.confirm = MasterStartsNodes({1, 2});
  BusOpenResult drives = UdpCanBus::Open("127.0.0.1:0", "", adopt);
  ASSERT_TRUE(drives.bus) << drives.message;
  auto& bus = static_cast<UdpCanBus&>(*drives.bus);
  BusOpenResult master = UdpCanBus::Open("127.0.0.1:0", Loopback(bus.local_port()));
  ASSERT_TRUE(master.bus) << master.message;
  UdpSocket stranger;
  ASSERT_EQ(stranger.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  std::array<std::uint8_t, 32> datagram{};
  const CanFrame sync = canopen::EncodeSync(1);
  const std::size_t n = EncodeCannelloni(0, std::span<const CanFrame>(&sync, 1), datagram);
  const UdpAddress bus_at = *ParseUdpAddress(Loopback(bus.local_port()));

  const long before = g_allocations.load();
  for (int i = 0; i < 40; ++i) (void)stranger.SendTo(bus_at, std::span<const std::uint8_t>(datagram.data(), n));
  CanFrame f;
  for (int waits = 0; bus.held_datagrams() < 40 && waits < 1000; ++waits) {
    while (bus.Receive(&f) == BusStatus::kOk) {
    }
    WaitReadable(bus, 10);
  }
  (void)master.bus->Send(canopen::EncodeNmt(canopen::NmtCommand::kResetComm, 0));
  (void)master.bus->Send(sync);
  const int got = ReceiveFrames(bus, 2);
  const long allocations = g_allocations.load() - before;
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(got, 2);
  EXPECT_TRUE(bus.has_peer());
  EXPECT_EQ(bus.stats().rx_refused, 40U);
}

TEST(LinkAlloc, AuthenticatedHmdWithDecoderAndStreamFilterAllocatesNothing) {
  UdpSocket session, headset;
  ASSERT_EQ(session.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  ASSERT_EQ(headset.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  session.EnableAuth(Key(), LinkKind::kHmd, LinkRole::kSession);
  headset.EnableAuth(Key(), LinkKind::kHmd, LinkRole::kPeer);
  const UdpAddress session_at = *ParseUdpAddress(Loopback(session.local_port()));
  const UdpAddress headset_at = *ParseUdpAddress(Loopback(headset.local_port()));
  session.AcceptOnlyFrom(headset_at);
  headset.AcceptOnlyFrom(session_at);
  HmdReceiveFilter filter(1'000'000'000, 77);
  ClockOffsetEstimator offset;
  std::array<std::uint8_t, kHmdMaxSize> out{};
  std::array<std::uint8_t, 512> in{};
  auto head_pose = [&](std::uint32_t seq) {
    HmdMessage m;
    m.header.seq = seq;
    m.header.session = 88;
    m.header.type = HmdType::kHeadPose;
    m.body = HeadPoseMsg{};
    return std::span<const std::uint8_t>(out.data(), EncodeHmd(m, out));
  };
  // Warm up: each end hears the other's epoch (datagrams both ways, HELLOs answered inside Receive).
  for (int i = 0; i < 100 && (session.auth_counters()->accepted == 0 || headset.auth_counters()->accepted == 0); ++i) {
    (void)headset.SendTo(session_at, head_pose(0));
    (void)session.SendTo(headset_at, head_pose(0));
    session.WaitReadable(10);
    while (session.Receive(in, nullptr) >= 0) {
    }
    headset.WaitReadable(10);
    while (headset.Receive(in, nullptr) >= 0) {
    }
  }
  ASSERT_GT(session.auth_counters()->accepted, 0U);
  ASSERT_GT(headset.auth_counters()->accepted, 0U);
  const long before = g_allocations.load();
  int taken = 0;
  for (std::uint32_t seq = 1; seq <= 200; ++seq) {
    (void)headset.SendTo(session_at, head_pose(seq));
    for (int waits = 0; waits < 100; ++waits) {
      session.WaitReadable(10);
      const long n = session.Receive(in, nullptr);
      if (n < 0) continue;
      HmdMessage r;
      if (DecodeHmd(std::span<const std::uint8_t>(in.data(), static_cast<std::size_t>(n)), &r) == CodecError::kOk &&
          filter.Accept(r, MonotonicNs(), offset))
        ++taken;
      break;
    }
  }
  const long allocations = g_allocations.load() - before;
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(taken, 200);
}

}  // namespace
}  // namespace pwsim::hw
