#include "hardware/can_bus.h"

#include <gtest/gtest.h>

#include <cerrno>

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
  BusOpenResult server = UdpCanBus::Open("127.0.0.1:0", "");
  ASSERT_TRUE(server.bus) << server.message;
  const auto port = static_cast<UdpCanBus*>(server.bus.get())->local_port();
  BusOpenResult client = UdpCanBus::Open("127.0.0.1:0", "127.0.0.1:" + std::to_string(port));
  ASSERT_TRUE(client.bus) << client.message;
  // The server learns its peer from the first datagram.
  EXPECT_EQ(server.bus->Send(MakeFrame(1, {})), BusStatus::kWouldBlock);
  for (std::uint8_t i = 0; i < 5; ++i) ASSERT_EQ(client.bus->Send(MakeFrame(0x200U + i, {i, i})), BusStatus::kOk);
  CanFrame f;
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
  EXPECT_FALSE(UdpCanBus::Open("nonsense", "").bus);
  EXPECT_FALSE(UdpCanBus::Open("127.0.0.1:0", "1.2.3:99999").bus);
}

}  // namespace
}  // namespace pwsim::hw
