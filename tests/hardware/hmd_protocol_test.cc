#include "hardware/hmd_protocol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <variant>
#include <vector>

namespace pwsim::hw {
namespace {

HmdMessage Msg(HmdBody body, std::uint32_t seq, std::int64_t t) {
  HmdMessage m;
  m.header.type = static_cast<HmdType>(body.index() + 1);
  m.header.seq = seq;
  m.header.session = 77;
  m.header.t_send_ns = t;
  m.body = body;
  return m;
}

std::vector<std::uint8_t> Encode(const HmdMessage& m) {
  std::vector<std::uint8_t> b(kHmdMaxSize);
  b.resize(EncodeHmd(m, b));
  return b;
}

TEST(HmdProtocol, EveryMessageRoundTripsWithItsDocumentedSize) {
  Pose p;
  p.p = {1.5, -2.0, 1.25};
  p.q = {0.0, 0.1, 0.0, std::sqrt(1 - 0.01)};
  const std::vector<std::pair<HmdMessage, std::size_t>> cases = {
      {Msg(CameraPoseMsg{120, 12, p, {0.1, -0.2}}, 1, 1000), 112},
      {Msg(HeadPoseMsg{5, p, 12, 6}, 2, 2000), 104},
      {Msg(PingMsg{42}, 3, 3000), 32},
      {Msg(PongMsg{1, 2, 3}, 4, 4000), 48},
      {Msg(ByeMsg{}, 5, 5000), 24},
      {Msg(HelloMsg{0xDEADBEEF, 77}, 6, 6000), 32},
  };
  for (const auto& [m, size] : cases) {
    const auto bytes = Encode(m);
    ASSERT_EQ(bytes.size(), size);
    EXPECT_EQ(bytes[0], 'P');
    EXPECT_EQ(bytes[1], 'W');
    EXPECT_EQ(bytes[2], 'H');
    EXPECT_EQ(bytes[3], 'M');
    HmdMessage back;
    ASSERT_EQ(DecodeHmd(bytes, &back), CodecError::kOk);
    EXPECT_EQ(back, m);
  }
}

TEST(HmdProtocol, RejectsMalformedDatagrams) {
  const auto good = Encode(Msg(HeadPoseMsg{5, Pose{}, 1, 2}, 1, 1));
  struct Case {
    const char* name;
    std::vector<std::uint8_t> bytes;
    CodecError error;
  };
  std::vector<Case> cases;
  cases.push_back({"empty", {}, CodecError::kTruncated});
  cases.push_back({"short header", std::vector<std::uint8_t>(good.begin(), good.begin() + 23), CodecError::kTruncated});
  auto bad_magic = good;
  bad_magic[0] = 'X';
  cases.push_back({"magic", bad_magic, CodecError::kBadSyntax});
  auto bad_version = good;
  bad_version[4] = 2;
  cases.push_back({"version", bad_version, CodecError::kBadVersion});
  auto bad_type = good;
  bad_type[6] = 9;
  cases.push_back({"type", bad_type, CodecError::kBadOpcode});
  cases.push_back({"short body", std::vector<std::uint8_t>(good.begin(), good.end() - 1), CodecError::kTruncated});
  auto longer = good;
  longer.push_back(0);
  cases.push_back({"trailing", longer, CodecError::kTrailing});
  auto hello_stream_zero = Encode(Msg(HelloMsg{1, 2}, 1, 1));
  hello_stream_zero[24] = 0;  // stream = 0: no stream at all
  cases.push_back({"HELLO stream 0", hello_stream_zero, CodecError::kBadSyntax});
  Pose nan_pose;
  nan_pose.p[0] = std::numeric_limits<double>::quiet_NaN();
  cases.push_back({"NaN pose", Encode(Msg(HeadPoseMsg{5, nan_pose, 1, 2}, 1, 1)), CodecError::kBadSyntax});
  for (const Case& c : cases) {
    HmdMessage m;
    EXPECT_EQ(DecodeHmd(c.bytes, &m), c.error) << c.name;
  }
}

TEST(HmdReceiveFilter, DropsOutOfOrderDuplicateAndStaleAndCountsThem) {
  HmdReceiveFilter filter(100'000'000);
  ClockOffsetEstimator offset;
  const auto head = [](std::uint32_t seq, std::int64_t t) { return Msg(HeadPoseMsg{t, Pose{}, -1, 0}, seq, t); };
  EXPECT_TRUE(filter.Accept(head(5, 0), 0, offset));
  EXPECT_FALSE(filter.Accept(head(5, 0), 0, offset));  // duplicate
  EXPECT_FALSE(filter.Accept(head(3, 0), 0, offset));  // older
  EXPECT_TRUE(filter.Accept(head(6, 0), 0, offset));
  EXPECT_TRUE(filter.Accept(Msg(PongMsg{}, 1, 0), 0, offset));  // per-type sequences
  EXPECT_EQ(filter.counters().out_of_order, 2U);
  // Once the clock offset is known (peer 1 s ahead), a message sent 150 ms ago is stale.
  offset.AddSample(0, 1'000'000'000, 1'000'000'000, 0);
  ASSERT_TRUE(offset.valid());
  EXPECT_FALSE(filter.Accept(head(7, 1'000'000'000), 150'000'000, offset));
  EXPECT_EQ(filter.counters().stale, 1U);
  EXPECT_TRUE(filter.Accept(head(8, 1'140'000'000), 150'000'000, offset));
  EXPECT_EQ(filter.counters().accepted, 4U);
}

TEST(ClockOffsetEstimator, RecoversAnInjectedOffsetUnderAsymmetricJitter) {
  std::mt19937_64 rng(3);
  std::exponential_distribution<double> delay(1.0 / 200'000.0);  // mean 0.2 ms each way
  const std::int64_t offset = 37'000'000;                          // peer 37 ms ahead
  ClockOffsetEstimator est(16);
  std::int64_t t = 1'000'000'000;
  for (int k = 0; k < 50; ++k) {
    const auto up = static_cast<std::int64_t>(20'000 + delay(rng));
    const auto down = static_cast<std::int64_t>(20'000 + 3 * delay(rng));
    const std::int64_t t0 = t;
    const std::int64_t t1 = t0 + up + offset;
    const std::int64_t t2 = t1 + 5'000;
    const std::int64_t t3 = t2 - offset + down;
    est.AddSample(t0, t1, t2, t3);
    t += 100'000'000;
  }
  EXPECT_NEAR(static_cast<double>(est.offset_ns()), static_cast<double>(offset), 100'000.0);
  EXPECT_LT(est.rtt_ns(), 400'000);
  EXPECT_EQ(est.samples(), 50U);
}

// One end of the HMD link as the session core and hmd-peer run it: a filter with a stream of
// its own, answering a HELLO that asks for it and a wanted HELLO (hmd_protocol.h).
struct End {
  explicit End(std::uint32_t own) : filter(1'000'000'000, own), stream(own) {}
  HmdReceiveFilter filter;
  ClockOffsetEstimator offset;
  std::uint32_t stream;
  std::uint32_t seq{0};
  std::vector<HmdMessage> outbox;
  HmdMessage Make(HmdBody body) {
    HmdMessage m = Msg(std::move(body), seq++, 0);
    m.header.session = stream;
    return m;
  }
  /// Receives `m`; returns whether it was used (a HELLO: answered).
  bool Receive(const HmdMessage& m) {
    if (!filter.Accept(m, 0, offset)) {
      if (filter.TakeHelloWanted()) outbox.push_back(Make(filter.HelloAnswer()));
      return false;
    }
    if (std::holds_alternative<HelloMsg>(m.body)) outbox.push_back(Make(filter.HelloAnswer()));
    return true;
  }
};

/// Delivers each end's outbox to the other until both are empty; returns the messages moved.
int Exchange(End& a, End& b) {
  int moved = 0;
  while (!a.outbox.empty() || !b.outbox.empty()) {
    for (End* from : {&a, &b}) {
      End& to = from == &a ? b : a;
      std::vector<HmdMessage> out;
      out.swap(from->outbox);
      for (const HmdMessage& m : out) {
        to.Receive(m);
        ++moved;
      }
    }
  }
  return moved;
}

HeadPoseMsg Head() { return HeadPoseMsg{0, Pose{}, -1, 0}; }

TEST(HmdStreams, AHelloHandshakeConfirmsBothStreamsInFourMessages) {
  End session(0x5E55), headset(0x4EAD);
  headset.outbox.push_back(headset.Make(HelloMsg{headset.stream, 0}));
  EXPECT_EQ(Exchange(session, headset), 4);
  EXPECT_EQ(session.filter.peer_stream(), headset.stream);
  EXPECT_EQ(headset.filter.peer_stream(), session.stream);
  EXPECT_EQ(session.filter.counters().restarts, 0U);
}

TEST(HmdStreams, ARestartedHeadsetIsReadmittedWhereItUsedToBeLockedOut) {
  End session(0x5E55), headset(0x4EAD);
  headset.outbox.push_back(headset.Make(HelloMsg{headset.stream, 0}));
  Exchange(session, headset);
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(session.Receive(headset.Make(Head())));
  // The headset restarts: a new stream, seq from 0 again.
  End reborn(0x4EAE);
  EXPECT_FALSE(session.Receive(reborn.Make(Head())));  // another stream: dropped, HELLO wanted
  EXPECT_EQ(session.filter.counters().other_stream, 1U);
  ASSERT_EQ(session.outbox.size(), 1U);
  EXPECT_EQ(std::get<HelloMsg>(session.outbox[0].body), (HelloMsg{session.stream, reborn.stream}));
  EXPECT_EQ(Exchange(session, reborn), 3);
  EXPECT_EQ(session.filter.peer_stream(), reborn.stream);
  EXPECT_EQ(session.filter.counters().restarts, 1U);
  EXPECT_TRUE(session.Receive(reborn.Make(Head())));  // seq 3 < the old stream's 10: taken
  // The old stream's late datagrams are not.
  EXPECT_FALSE(session.Receive(headset.Make(Head())));
  // Without streams (the protocol as it was) the same restart stays locked out.
  End old_session(0), old_headset(0);
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(old_session.Receive(old_headset.Make(Head())));
  End old_reborn(0);
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(old_session.Receive(old_reborn.Make(Head())));
  EXPECT_EQ(old_session.filter.counters().out_of_order, 5U);
}

TEST(HmdStreams, ARestartedSessionIsReadmittedByTheHeadset) {
  End session(0x5E55), headset(0x4EAD);
  headset.outbox.push_back(headset.Make(HelloMsg{headset.stream, 0}));
  Exchange(session, headset);
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(headset.Receive(session.Make(CameraPoseMsg{})));
  End session2(0x5E56);
  EXPECT_FALSE(headset.Receive(session2.Make(CameraPoseMsg{})));
  EXPECT_EQ(Exchange(session2, headset), 3);
  EXPECT_EQ(headset.filter.peer_stream(), session2.stream);
  EXPECT_TRUE(headset.Receive(session2.Make(CameraPoseMsg{})));
}

TEST(HmdStreams, AHelloThatDoesNotEchoOurStreamChangesNothing) {
  End session(0x5E55), headset(0x4EAD);
  headset.outbox.push_back(headset.Make(HelloMsg{headset.stream, 0}));
  Exchange(session, headset);
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(session.Receive(headset.Make(Head())));
  const HmdMessage replay = headset.Make(Head());
  EXPECT_TRUE(session.Receive(replay));
  // A spoofer that cannot read our datagrams guesses the stream wrong: answered, not taken.
  HmdMessage forged = Msg(HelloMsg{0xBAD, session.stream ^ 1}, 0, 0);
  forged.header.session = 0xBAD;
  EXPECT_TRUE(session.Receive(forged));  // answered (tells it nothing it could not see)
  EXPECT_EQ(session.filter.peer_stream(), headset.stream);
  EXPECT_FALSE(session.Receive(replay));  // sequences not reset
  EXPECT_EQ(session.filter.counters().restarts, 0U);
}

TEST(HmdStreams, AnOldHeadsetWithoutHellosIsTakenAsBefore) {
  End session(0x5E55);
  End old_headset(0);
  for (int i = 0; i < 10; ++i) {
    HmdMessage m = old_headset.Make(Head());
    m.header.session = session.stream;  // old headsets echo the session's id
    EXPECT_TRUE(session.Receive(m));
  }
  EXPECT_TRUE(session.outbox.empty());
  EXPECT_EQ(session.filter.peer_stream(), 0U);
  // An end without a stream ignores HELLOs.
  EXPECT_FALSE(old_headset.Receive(session.Make(HelloMsg{session.stream, 0})));
  EXPECT_TRUE(old_headset.outbox.empty());
}

TEST(MotionCompensation, RemovesThePlatformPoseFromTheTrackedHead) {
  Pose head_in_rig;
  head_in_rig.p = {0.1, -0.05, 1.2};
  const double yaw = 0.3;
  head_in_rig.q = {0.0, std::sin(0.5 * 0.1), 0.0, std::cos(0.5 * 0.1)};
  for (double rail : {-0.5, 0.0, 0.37}) {
    const Pose in_room = ComposePose(PlatformPose(yaw, rail), head_in_rig);
    const Pose back = CompensateHeadPose(in_room, yaw, rail);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(back.p[i], head_in_rig.p[i], 1e-12);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(back.q[i], head_in_rig.q[i], 1e-12);
  }
  // The rig's origin moves along its own rotated x axis (RP chain of seed 001).
  const Pose rig = PlatformPose(M_PI / 2, 0.4);
  EXPECT_NEAR(rig.p[0], 0.0, 1e-12);
  EXPECT_NEAR(rig.p[1], 0.4, 1e-12);
}

}  // namespace
}  // namespace pwsim::hw
