#include "hardware/hmd_protocol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

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
