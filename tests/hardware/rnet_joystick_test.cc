// The R-Net joystick reader (hardware/rnet_joystick.h): the frame layout published by can2RNET,
// the tick-exact watchdog, garbage counted and ignored, on the shipped synthetic candump log
// (scripts/make-rnet-log.py says what it contains) and on the in-process bus.
#include "hardware/rnet_joystick.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "engine/input_error.h"

namespace pwsim::hw {
namespace {

CanFrame Text(const char* text) {
  CanFrame f;
  EXPECT_EQ(ParseFrameText(text, &f), CodecError::kOk) << text;
  return f;
}

TEST(RnetFrame, ThePublishedJoystickLayout) {
  RnetJoystickFrame j;
  // can2RNET's examples: 02000100#0064 full forward, #6400 full right, #009C full reverse.
  ASSERT_EQ(ClassifyRnetFrame(Text("02000100#0064"), &j), RnetFrameKind::kJoystick);
  EXPECT_EQ(j.device, 1);
  EXPECT_EQ(j.x_percent, 0);
  EXPECT_EQ(j.y_percent, 100);
  ASSERT_EQ(ClassifyRnetFrame(Text("02000000#6400"), &j), RnetFrameKind::kJoystick);
  EXPECT_EQ(j.device, 0);
  EXPECT_EQ(j.x_percent, 100);
  ASSERT_EQ(ClassifyRnetFrame(Text("02000F00#9C9C"), &j), RnetFrameKind::kJoystick);
  EXPECT_EQ(j.device, 15);
  EXPECT_EQ(j.x_percent, -100);
  EXPECT_EQ(j.y_percent, -100);
  EXPECT_EQ(EncodeRnetJoystick(1, 0, 100), Text("02000100#0064"));
  EXPECT_EQ(EncodeRnetJoystick(2, -150, 30), Text("02000200#9C1E"));  // clamped
  // Garbage on the joystick identifier.
  for (const char* bad : {"02000000#00", "02000000#000000", "02000000#8100", "02000000#0065", "02000000#R"})
    EXPECT_EQ(ClassifyRnetFrame(Text(bad), &j), RnetFrameKind::kGarbage) << bad;
  // Other R-Net frames and foreign ones: not garbage, not ours.
  for (const char* other : {"03C30F0F#8787878787878787", "1C0C0000#64", "02000001#0064", "200#0064", "0C000005#"})
    EXPECT_EQ(ClassifyRnetFrame(Text(other), &j), RnetFrameKind::kOther) << other;
  EXPECT_EQ(ClassifyRnetFrame(MakeErrorFrame(kCanErrBusOff), &j), RnetFrameKind::kOther);
}

TEST(RnetWatchdog, ZeroDeflectionExactlyTimeoutTicksAfterTheLastValidFrame) {
  const RnetJoystickParams params{-1, 100};
  RnetJoystickState state;
  EXPECT_FALSE(RnetSample(params, &state, 0).valid);  // nothing seen yet
  RnetOnFrame(params, &state, EncodeRnetJoystick(0, 40, 80), 5, 123);
  for (std::int64_t k = 5; k < 105; ++k) {
    const JoystickSample s = RnetSample(params, &state, k);
    ASSERT_TRUE(s.valid) << k;
    EXPECT_DOUBLE_EQ(s.x, 0.4);
    EXPECT_DOUBLE_EQ(s.y, 0.8);
    EXPECT_EQ(s.input_ns, 123);
  }
  const JoystickSample lost = RnetSample(params, &state, 105);
  EXPECT_FALSE(lost.valid);
  EXPECT_EQ(lost.x, 0.0);
  EXPECT_EQ(lost.y, 0.0);
  EXPECT_EQ(state.counters.timeouts, 1U);
  // garbage does not feed the watchdog
  RnetOnFrame(params, &state, Text("02000000#7F00"), 106, 0);
  EXPECT_FALSE(RnetSample(params, &state, 106).valid);
  EXPECT_EQ(state.counters.garbage, 1U);
  RnetOnFrame(params, &state, EncodeRnetJoystick(0, 0, 10), 200, 0);
  EXPECT_TRUE(RnetSample(params, &state, 200).valid);
  EXPECT_EQ(WatchdogTicks(100.0, 1000), 100);
  EXPECT_EQ(WatchdogTicks(100.0, 60), 6);
  EXPECT_EQ(WatchdogTicks(0.1, 1000), 1);
}

TEST(RnetWatchdog, LocksOntoTheFirstSlotUnlessOneIsConfigured) {
  RnetJoystickState state;
  RnetOnFrame({-1, 100}, &state, EncodeRnetJoystick(3, 10, 10), 0, 0);
  RnetOnFrame({-1, 100}, &state, EncodeRnetJoystick(1, -100, 0), 1, 0);
  EXPECT_DOUBLE_EQ(RnetSample({-1, 100}, &state, 1).x, 0.1);
  EXPECT_EQ(state.counters.other_device, 1U);
  RnetJoystickState fixed;
  RnetOnFrame({1, 100}, &fixed, EncodeRnetJoystick(3, 10, 10), 0, 0);
  EXPECT_FALSE(RnetSample({1, 100}, &fixed, 0).valid);
}

// The shipped synthetic log, replayed at 1 kHz. What it holds is stated by its generator
// (scripts/make-rnet-log.py): the truth below is that script's description, not the reader.
TEST(RnetLogJoystick, ReplaysTheShippedSyntheticLogOnTicks) {
  const auto records = ReadCandumpFile(std::filesystem::path(PWSIM_SOURCE_DIR) / "assets/rnet/joystick_synthetic.log");
  ASSERT_EQ(records.size(), 418U);
  RnetLogJoystick joystick(records, 1000, {-1, WatchdogTicks(100.0, 1000)}, "log");
  std::vector<JoystickSample> s;
  for (std::int64_t k = 0; k <= 4100; ++k) s.push_back(joystick.Poll(k, k * 1'000'000));
  EXPECT_TRUE(s[0].valid);
  EXPECT_EQ(s[500].y, 0.0);
  EXPECT_DOUBLE_EQ(s[1500].y, 0.30);                 // ramp: 60 % x 0.5 s / 1 s
  EXPECT_DOUBLE_EQ(s[2500].x, 0.30);
  EXPECT_DOUBLE_EQ(s[2500].y, 0.60);
  // Records are taken at the first tick at or after their log time (the log starts at its
  // first record, 0.25 ms into the joystick's 10 ms period). Last frame before the loss at
  // 2.990 s after the first: tick 2990, valid through tick 3089, zero from 3090 on.
  EXPECT_TRUE(s[3089].valid);
  EXPECT_DOUBLE_EQ(s[3089].y, 0.60);
  EXPECT_FALSE(s[3090].valid);
  EXPECT_EQ(s[3090].y, 0.0);
  EXPECT_EQ(s[3299].x, 0.0);
  EXPECT_TRUE(s[3300].valid);                        // frames again at 3.300 s, centred
  EXPECT_EQ(s[3300].y, 0.0);
  // the heartbeat 4.75 ms after the first record is taken at tick 5, not 4
  RnetLogJoystick early(records, 1000, {-1, 100}, "log");
  early.Poll(4, 0);
  EXPECT_EQ(early.counters().other, 0U);
  early.Poll(5, 0);
  EXPECT_EQ(early.counters().other, 1U);
  const RnetJoystickCounters& c = joystick.counters();
  EXPECT_EQ(c.valid, 370U);
  EXPECT_EQ(c.garbage, 3U);
  EXPECT_EQ(c.other_device, 1U);
  EXPECT_EQ(c.other, 44U);
  EXPECT_EQ(c.timeouts, 2U);  // the loss, and the end of the log (its last frame at 3.990 s)
  EXPECT_TRUE(s[4089].valid);
  EXPECT_FALSE(s[4090].valid);
  // A replay is the same, sample for sample, however often it is polled: records carry the
  // ticks of their log times.
  RnetLogJoystick again(records, 1000, {-1, 100}, "log");
  for (std::int64_t k = 0; k <= 4100; k += 7) {
    const JoystickSample a = again.Poll(k, k * 1'000'000);
    EXPECT_EQ(a.valid, s[static_cast<std::size_t>(k)].valid);
    EXPECT_EQ(a.x, s[static_cast<std::size_t>(k)].x);
    EXPECT_EQ(a.y, s[static_cast<std::size_t>(k)].y);
  }
}

TEST(RnetLogJoystick, AMalformedLogNamesFileAndLine) {
  const auto file = std::filesystem::temp_directory_path() / ("rnet_bad_" + std::to_string(::getpid()) + ".log");
  {
    std::ofstream out(file);
    out << "(1700000000.000000) can0 02000000#0000\n(1700000000.010000) can0 02000000#00G0\n";
  }
  try {
    ReadCandumpFile(file);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  std::filesystem::remove(file);
  EXPECT_THROW(ReadCandumpFile("/nonexistent/rnet.log"), InputError);
}

TEST(RnetJoystick, OnTheInProcessBusWithLostAndGarbageFrames) {
  InProcessBus hub;
  std::unique_ptr<ICanBus> jsm = hub.Connect("jsm");
  std::unique_ptr<ICanBus> monitor = hub.Connect("monitor");
  RnetJoystick reader(ListenOnly(hub.Connect("reader")), {-1, 30});  // 30 ticks: 3 frame periods
  // 10 ms frames at 1 kHz ticks; frames 20..29 are lost on the bus.
  int lost_from = -1, sent = 0;
  for (std::int64_t k = 0; k < 600; ++k) {
    if (k % 10 == 0) {
      const int frame = static_cast<int>(k / 10);
      if (frame == 20) hub.DropNext(10);
      ASSERT_EQ(jsm->Send(EncodeRnetJoystick(0, 0, 50)), BusStatus::kOk);
      ++sent;
      if (frame == 40) {
        ASSERT_EQ(jsm->Send(Text("02000000#FFFF00")), BusStatus::kOk);  // garbage
      }
      if (frame == 41) hub.InjectErrorFrame(0x004U);
    }
    const JoystickSample s = reader.Poll(k, k);
    if (!s.valid && k > 0 && lost_from < 0) lost_from = static_cast<int>(k);
    if (k < 200) {
      EXPECT_TRUE(s.valid) << k;
    }
    EXPECT_EQ(s.y, s.valid ? 0.5 : 0.0) << k;
  }
  // last frame before the loss at tick 190: zero from tick 220 on; frames again from tick 300
  EXPECT_EQ(lost_from, 220);
  EXPECT_EQ(reader.counters().valid, static_cast<std::uint64_t>(sent - 10));
  EXPECT_EQ(reader.counters().garbage, 1U);
  EXPECT_EQ(reader.counters().other, 1U);  // the error frame
  EXPECT_EQ(reader.counters().timeouts, 1U);
  // The reader put nothing on the bus: the monitor saw the joystick's frames and nothing else.
  std::uint64_t seen = 0;
  CanFrame f;
  while (monitor->Receive(&f) == BusStatus::kOk) seen += f.error() ? 0 : 1;
  EXPECT_EQ(seen, static_cast<std::uint64_t>(sent - 10 + 1));
}

TEST(RnetJoystick, TakesFramesBetweenTicksStampedWithTheirArrival) {
  // A socket pair stands in for the CAN socket: it has a file descriptor to wait on.
  auto [writer, reader_end] = MakeSocketPairBus();
  ASSERT_TRUE(writer && reader_end);
  RnetJoystick reader(ListenOnly(std::move(reader_end)), {-1, 100});
  ASSERT_GE(reader.fd(), 0);
  ASSERT_EQ(writer->Send(EncodeRnetJoystick(0, 0, 30)), BusStatus::kOk);
  reader.Take(7, 1'000);  // the runner, between steps, waiting for tick 7
  const JoystickSample s = reader.Poll(7, 5'000);
  EXPECT_TRUE(s.valid);
  EXPECT_DOUBLE_EQ(s.y, 0.3);
  EXPECT_EQ(s.input_ns, 1'000);  // when it was taken, not when the step polled
  EXPECT_EQ(s.input_seq, 1U);
}

TEST(RnetJoystick, SocketCanListenOnlyWhereTheKernelHasCan) {
  ListenerOpenResult opened = OpenSocketCanListenOnly("vcan0", kRnetJoystickId, kRnetJoystickMask);
  if (!opened.listener) {
    GTEST_SKIP() << "no SocketCAN here (" << opened.message << ")";
  }
  BusOpenResult writer = OpenSocketCan("vcan0");
  ASSERT_TRUE(writer.bus) << writer.message;
  ASSERT_EQ(writer.bus->Send(Text("03C30F0F#8787878787878787")), BusStatus::kOk);  // filtered out
  ASSERT_EQ(writer.bus->Send(EncodeRnetJoystick(0, 20, 40)), BusStatus::kOk);
  RnetJoystick reader(std::move(opened.listener), {-1, 100});
  JoystickSample s;
  for (int k = 0; k < 1000 && !s.valid; ++k) s = reader.Poll(k, k);
  EXPECT_TRUE(s.valid);
  EXPECT_DOUBLE_EQ(s.y, 0.4);
  EXPECT_EQ(reader.counters().other, 0U);  // the kernel filter admitted the joystick id only
}

}  // namespace
}  // namespace pwsim::hw
