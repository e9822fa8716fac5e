#include "hardware/can_bus.h"

#include <gtest/gtest.h>

#include <array>
#include <cerrno>
#include <span>
#include <vector>

#include "hardware/udp_can_bus.h"

namespace pwsim::hw {
namespace {

TEST(SocketCan, ReportsMissingKernelSupportClearly) {
  BusOpenResult r = OpenSocketCan("vcan0");
  if (r.bus) GTEST_SKIP() << "this kernel has SocketCAN and vcan0: the failure path is not reachable";
  if (r.error != EAFNOSUPPORT) {
    GTEST_SKIP() << "kernel has AF_CAN but no vcan0 (" << r.message << ")";
  }
  EXPECT_NE(r.message.find("EAFNOSUPPORT"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("udp:HOST:PORT"), std::string::npos) << r.message;
}

TEST(SocketCan, LoopbackOnVcan0) {
  BusOpenResult a = OpenSocketCan("vcan0");
  if (!a.bus) {
    GTEST_SKIP() << "needs a kernel with SocketCAN and a vcan0 interface; here: " << a.message;
  }
  BusOpenResult b = OpenSocketCan("vcan0");
  ASSERT_TRUE(b.bus) << b.message;
  const CanFrame f = MakeFrame(0x123, {1, 2, 3});
  ASSERT_EQ(a.bus->Send(f), BusStatus::kOk);
  ASSERT_TRUE(WaitReadable(*b.bus, 1000));
  CanFrame got;
  ASSERT_EQ(b.bus->Receive(&got), BusStatus::kOk);
  EXPECT_EQ(got, f);
}

TEST(SocketPairBus, CarriesFramesBothWaysWithRecordBoundaries) {
  auto [a, b] = MakeSocketPairBus();
  ASSERT_TRUE(a && b);
  CanFrame got;
  EXPECT_EQ(b->Receive(&got), BusStatus::kWouldBlock);
  for (std::uint8_t i = 0; i < 10; ++i) ASSERT_EQ(a->Send(MakeFrame(0x100U + i, {i})), BusStatus::kOk);
  ASSERT_TRUE(WaitReadable(*b, 1000));
  for (std::uint8_t i = 0; i < 10; ++i) {
    ASSERT_EQ(b->Receive(&got), BusStatus::kOk);
    EXPECT_EQ(got, MakeFrame(0x100U + i, {i}));
  }
  ASSERT_EQ(b->Send(MakeErrorFrame(kCanErrBusOff)), BusStatus::kOk);
  ASSERT_EQ(a->Receive(&got), BusStatus::kOk);
  EXPECT_TRUE(got.error());
  EXPECT_EQ(a->stats().error_frames, 1U);
  b.reset();
  EXPECT_EQ(a->Receive(&got), BusStatus::kClosed);
}

TEST(InProcessBus, BroadcastsToEveryOtherNode) {
  InProcessBus hub;
  auto a = hub.Connect("a");
  auto b = hub.Connect("b");
  auto c = hub.Connect("c", /*loopback=*/true);
  ASSERT_EQ(a->Send(MakeFrame(1, {1})), BusStatus::kOk);
  ASSERT_EQ(c->Send(MakeFrame(2, {2})), BusStatus::kOk);
  CanFrame f;
  ASSERT_EQ(b->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, 1U);
  ASSERT_EQ(b->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, 2U);
  ASSERT_EQ(a->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, 2U);
  EXPECT_EQ(a->Receive(&f), BusStatus::kWouldBlock);  // no loopback for a
  ASSERT_EQ(c->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, 1U);
  ASSERT_EQ(c->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, 2U);  // its own frame, looped back
}

TEST(InProcessBus, InjectsDropsReorderingErrorFramesAndBusOff) {
  InProcessBus hub;
  auto a = hub.Connect("a");
  auto b = hub.Connect("b");
  CanFrame f;
  hub.DropNext(2);
  for (std::uint8_t i = 0; i < 4; ++i) a->Send(MakeFrame(i, {}));
  ASSERT_EQ(b->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, 2U);
  ASSERT_EQ(b->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, 3U);
  EXPECT_EQ(hub.dropped(), 2U);

  hub.SetFaults({.drop_probability = 0.0, .reorder_probability = 1.0, .seed = 3});
  a->Send(MakeFrame(10, {}));
  a->Send(MakeFrame(11, {}));
  ASSERT_EQ(b->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, 11U);
  ASSERT_EQ(b->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, 10U);
  hub.SetFaults({});

  hub.InjectErrorFrame(kCanErrCtrl, kCanErrCtrlTxPassive);
  ASSERT_EQ(b->Receive(&f), BusStatus::kOk);
  EXPECT_TRUE(f.error());
  EXPECT_EQ(f.data[1], kCanErrCtrlTxPassive);

  hub.SetBusOff(true);
  EXPECT_EQ(a->Send(MakeFrame(1, {})), BusStatus::kBusOff);
  ASSERT_EQ(b->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, kCanErrFlag | kCanErrBusOff);
  hub.SetBusOff(false);
  ASSERT_EQ(b->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f.id, kCanErrFlag | kCanErrRestarted);
  EXPECT_EQ(a->Send(MakeFrame(1, {})), BusStatus::kOk);
  EXPECT_EQ(a->stats().tx_failed, 1U);
}

TEST(InProcessBus, RandomDropsAreDeterministicForASeed) {
  auto run = [](std::uint64_t seed) {
    InProcessBus hub({.drop_probability = 0.3, .reorder_probability = 0.1, .seed = seed});
    auto a = hub.Connect("a");
    auto b = hub.Connect("b");
    for (std::uint32_t i = 0; i < 200; ++i) a->Send(MakeFrame(i & 0x7FFU, {}));
    std::vector<std::uint32_t> ids;
    CanFrame f;
    while (b->Receive(&f) == BusStatus::kOk) ids.push_back(f.id);
    return ids;
  };
  const auto first = run(42);
  EXPECT_EQ(first, run(42));
  EXPECT_LT(first.size(), 180U);
  EXPECT_GT(first.size(), 100U);
}

TEST(UdpCanBus, JoinsTwoEndsOnLoopbackInCannelloniFraming) {
  UdpCanBus::Options adopt;
  adopt.policy = UdpCanBus::PeerPolicy::kAdoptConfirmed;
  adopt.confirm = MasterStartsNodes({1, 2});
  BusOpenResult server = UdpCanBus::Open("127.0.0.1:0", "", adopt);
  ASSERT_TRUE(server.bus) << server.message;
  const auto port = static_cast<UdpCanBus*>(server.bus.get())->local_port();
  BusOpenResult client = UdpCanBus::Open("127.0.0.1:0", "127.0.0.1:" + std::to_string(port));
  ASSERT_TRUE(client.bus) << client.message;
  // The server adopts its peer once it starts the nodes as a CANopen master (NMT, SYNC).
  EXPECT_EQ(server.bus->Send(MakeFrame(1, {})), BusStatus::kWouldBlock);
  const CanFrame nmt = MakeFrame(0x000, {0x01, 0x00}), sync = MakeFrame(0x080, {});
  ASSERT_EQ(client.bus->Send(nmt), BusStatus::kOk);
  ASSERT_EQ(client.bus->Send(sync), BusStatus::kOk);
  for (std::uint8_t i = 0; i < 5; ++i) ASSERT_EQ(client.bus->Send(MakeFrame(0x200U + i, {i, i})), BusStatus::kOk);
  CanFrame f;
  for (const CanFrame& expected : {nmt, sync}) {
    ASSERT_TRUE(WaitReadable(*server.bus, 1000));
    ASSERT_EQ(server.bus->Receive(&f), BusStatus::kOk);
    EXPECT_EQ(f, expected);
  }
  for (std::uint8_t i = 0; i < 5; ++i) {
    ASSERT_TRUE(WaitReadable(*server.bus, 1000));
    ASSERT_EQ(server.bus->Receive(&f), BusStatus::kOk);
    EXPECT_EQ(f, MakeFrame(0x200U + i, {i, i}));
  }
  ASSERT_EQ(server.bus->Send(MakeFrame(0x181, {9})), BusStatus::kOk);
  ASSERT_TRUE(WaitReadable(*client.bus, 1000));
  ASSERT_EQ(client.bus->Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f, MakeFrame(0x181, {9}));
  EXPECT_EQ(server.bus->stats().rx_lost, 0U);
}

TEST(UdpCanBus, RejectsBadAddresses) {
  EXPECT_FALSE(UdpCanBus::Open("nonsense", "127.0.0.1:1").bus);
  EXPECT_FALSE(UdpCanBus::Open("127.0.0.1:0", "1.2.3:99999").bus);
  // no peer and no explicit adoption: refused, saying what is missing
  const BusOpenResult none = UdpCanBus::Open("127.0.0.1:0", "");
  EXPECT_FALSE(none.bus);
  EXPECT_NE(none.message.find("peer"), std::string::npos) << none.message;
  UdpCanBus::Options adopt;
  adopt.policy = UdpCanBus::PeerPolicy::kAdoptConfirmed;
  adopt.confirm = MasterStartsNodes({1});
  EXPECT_FALSE(UdpCanBus::Open("127.0.0.1:0", "127.0.0.1:1", adopt).bus);
}

/// A well-formed cannelloni datagram carrying `frame`, as any process could send it.
std::vector<std::uint8_t> Datagram(const CanFrame& frame, std::uint8_t seq) {
  std::vector<std::uint8_t> bytes(kCannelloniHeaderSize + 13);
  bytes.resize(EncodeCannelloni(seq, std::span<const CanFrame>(&frame, 1), bytes));
  return bytes;
}

UdpAddress Loopback(std::uint16_t port) { return *ParseUdpAddress("127.0.0.1:" + std::to_string(port)); }

TEST(UdpCanBus, TakesFramesFromItsConfiguredPeerOnlyAddressAndPort) {
  // The peer: a socket on a known port. The bus is configured with it.
  UdpSocket peer;
  ASSERT_EQ(peer.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  BusOpenResult opened = UdpCanBus::Open("127.0.0.1:0", "127.0.0.1:" + std::to_string(peer.local_port()));
  ASSERT_TRUE(opened.bus) << opened.message;
  auto& bus = static_cast<UdpCanBus&>(*opened.bus);
  const UdpAddress bus_at = Loopback(bus.local_port());
  // A stranger on the same host (same address, another port) sends well-formed frames,
  // then the peer sends one, then the stranger again. Datagrams on loopback keep their order.
  UdpSocket stranger;
  ASSERT_EQ(stranger.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  const CanFrame spoof = MakeFrame(0x202, {0x0F, 0x00, 0x20, 0xA1, 0x07, 0x00});  // rail to 0.5 m
  ASSERT_TRUE(stranger.SendTo(bus_at, Datagram(spoof, 0)));
  ASSERT_TRUE(stranger.SendTo(bus_at, Datagram(MakeFrame(0x000, {0x81, 0x00}), 1)));  // NMT reset all
  const CanFrame genuine = MakeFrame(0x182, {0x37, 0x02, 0, 0, 0, 0});
  ASSERT_TRUE(peer.SendTo(bus_at, Datagram(genuine, 0)));
  ASSERT_TRUE(stranger.SendTo(bus_at, Datagram(spoof, 2)));
  ASSERT_TRUE(WaitReadable(bus, 1000));
  CanFrame f;
  ASSERT_EQ(bus.Receive(&f), BusStatus::kOk);
  EXPECT_EQ(f, genuine);
  // The last spoof may still be on its way into the socket: wait for it as an event.
  while (bus.stats().rx_refused < 3) {
    ASSERT_TRUE(WaitReadable(bus, 1000));
    EXPECT_EQ(bus.Receive(&f), BusStatus::kWouldBlock);
  }
  EXPECT_EQ(bus.stats().rx_refused, 3U);
  EXPECT_EQ(bus.stats().rx, 1U);
  EXPECT_EQ(bus.stats().rx_malformed, 0U);  // refused before decoding: no sequence gaps either
  EXPECT_EQ(bus.stats().rx_lost, 0U);
  EXPECT_EQ(bus.peer(), "127.0.0.1:" + std::to_string(peer.local_port()));
}

TEST(UdpCanBus, AdoptsOnlyASenderThatConfirmsAndKeepsIt) {
  UdpCanBus::Options adopt;
  adopt.policy = UdpCanBus::PeerPolicy::kAdoptConfirmed;
  adopt.confirm = MasterStartsNodes({1, 2});
  BusOpenResult opened = UdpCanBus::Open("127.0.0.1:0", "", adopt);
  ASSERT_TRUE(opened.bus) << opened.message;
  auto& bus = static_cast<UdpCanBus&>(*opened.bus);
  const UdpAddress bus_at = Loopback(bus.local_port());
  UdpSocket first, second;
  ASSERT_EQ(first.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  ASSERT_EQ(second.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  // garbage and a lone SYNC from `second` adopt nothing; `first`'s NMT start then SYNC adopt
  // `first`, whose held frames come out in order
  const std::uint8_t junk[3] = {1, 2, 3};
  ASSERT_TRUE(second.SendTo(bus_at, junk));
  ASSERT_TRUE(second.SendTo(bus_at, Datagram(MakeFrame(0x080, {2}), 0)));
  ASSERT_TRUE(first.SendTo(bus_at, Datagram(MakeFrame(0x000, {0x01, 0x02}), 0)));
  ASSERT_TRUE(first.SendTo(bus_at, Datagram(MakeFrame(0x080, {3}), 1)));
  ASSERT_TRUE(first.SendTo(bus_at, Datagram(MakeFrame(0x080, {4}), 2)));
  std::vector<std::uint8_t> got;
  CanFrame f;
  while (got.size() < 3 || bus.stats().rx_refused < 1) {
    ASSERT_TRUE(WaitReadable(bus, 1000));
    while (bus.Receive(&f) == BusStatus::kOk) got.push_back(f.data[0]);
  }
  EXPECT_EQ(got, (std::vector<std::uint8_t>{0x01, 3, 4}));
  EXPECT_EQ(bus.stats().rx_malformed, 1U);
  EXPECT_EQ(bus.stats().rx_refused, 1U);  // second's SYNC, held, dropped at the adoption
  EXPECT_EQ(bus.peer(), "127.0.0.1:" + std::to_string(first.local_port()));
  // it answers the adopted peer
  ASSERT_EQ(bus.Send(MakeFrame(0x181, {7})), BusStatus::kOk);
  ASSERT_TRUE(first.WaitReadable(1000));
  std::array<std::uint8_t, 64> buffer{};
  EXPECT_GT(first.Receive(buffer, nullptr), 0);
}

TEST(UdpSocket, AcceptOnlyFromDropsOtherSendersAndCountsThem) {
  UdpSocket a, b, c;
  ASSERT_EQ(a.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  ASSERT_EQ(b.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  ASSERT_EQ(c.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
  a.AcceptOnlyFrom(Loopback(b.local_port()));
  const std::uint8_t one[1] = {1}, two[1] = {2};
  ASSERT_TRUE(c.SendTo(Loopback(a.local_port()), two));
  ASSERT_TRUE(b.SendTo(Loopback(a.local_port()), one));
  ASSERT_TRUE(a.WaitReadable(1000));
  std::array<std::uint8_t, 8> buffer{};
  UdpAddress from;
  ASSERT_EQ(a.Receive(buffer, &from), 1);
  EXPECT_EQ(buffer[0], 1);
  EXPECT_EQ(from, Loopback(b.local_port()));
  EXPECT_EQ(a.refused(), 1U);
}

}  // namespace
}  // namespace pwsim::hw
