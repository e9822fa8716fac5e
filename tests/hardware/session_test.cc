// The session core with the simulated drives on an in-process bus and a scripted headset, on
// a fake clock: whole sessions in milliseconds, the fault matrix at session level, and the
// log replayed bit for bit.
#include "hardware/session.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "tests/hardware/session_world.h"

namespace pwsim::hw {
namespace {

using session_testing::World;

TEST(Session, RunsParksAndReportsSkewAndJitter) {
  World w;
  w.Finish();
  ASSERT_TRUE(w.core->done());
  const SessionReport r = w.core->Report();
  EXPECT_EQ(r.final_state, "parked");
  EXPECT_EQ(r.stop_reason, "stop requested");
  EXPECT_EQ(r.stop_tick, 3000);
  EXPECT_TRUE(r.limits_ok);
  EXPECT_GT(r.peak_abs_command[1], 0.2);  // it really moved
  EXPECT_NEAR(r.peak_abs_measured[1], r.peak_abs_command[1], 0.02);
  EXPECT_NEAR(std::abs(w.drives.platform().q[1]), 0.0, 2e-3);  // parked at neutral
  EXPECT_GT(r.skew_ms.n, 50U);
  // Frame shown 350 us after sending; the platform answered the SYNC 150 us after it.
  EXPECT_NEAR(r.skew_ms.p50, 0.2, 0.01);
  EXPECT_LT(r.skew_ms.stddev, 0.01);
  EXPECT_NEAR(static_cast<double>(r.clock_offset_ns), 0.0, 1000.0);
  EXPECT_NEAR(r.cycle_lateness_us.p50, 15.0, 1e-9);
  EXPECT_EQ(r.hmd_rx.out_of_order, 0U);
  EXPECT_GT(r.hmd_rx.accepted, 100U);
  w.ExpectPlatformInsideLimits();
}

TEST(Session, LogReplaysBitForBitAndDetectsTampering) {
  World w(1500);
  w.Finish();
  ASSERT_TRUE(w.core->done());
  std::istringstream in(w.LogText());
  const ReplayResult r = ReplaySessionLog(in);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_GT(r.lines_compared, 1000);
  EXPECT_EQ(r.report.ToJson(), w.core->Report().ToJson());

  std::string tampered = w.LogText();
  const std::size_t at = tampered.find("\nS 800 ");
  ASSERT_NE(at, std::string::npos);
  const std::size_t digit = tampered.find_first_of("123456789", at + 10);
  tampered[digit] = tampered[digit] == '9' ? '8' : static_cast<char>(tampered[digit] + 1);
  std::istringstream bad(tampered);
  const ReplayResult r2 = ReplaySessionLog(bad);
  EXPECT_FALSE(r2.ok);
  EXPECT_NE(r2.message.find("line"), std::string::npos) << r2.message;
}

struct SessionFault {
  const char* name;
  std::function<void(World&)> inject;
  const char* reason;
  const char* final_state;
  std::int64_t max_reaction_ticks;
};

TEST(Session, EachPeerOrBusFaultEndsInItsDocumentedReactionAndAParkedPlatform) {
  const std::vector<SessionFault> cases = {
      // The timeout runs from the first frame left unanswered (up to one frame period, 10
      // ticks, after the headset vanished), seen at the next drive cycle.
      {"headset vanishes", [](World& w) { w.hmd_alive = false; }, "HMD link stale", "parked",
       250 + 10 + 8},
      {"drives go silent", [](World& w) { w.drives.SetSilent(true); }, "drive feedback stale",
       "parked", 4 * 5},
      {"bus-off", [](World& w) { w.hub.SetBusOff(true); }, "bus-off", "fault", 8},
      {"drive fault (EMCY)",
       [](World& w) {
         std::vector<CanFrame> emcy;
         w.drives.InjectFault(1, 0x7300, &emcy);
         for (const CanFrame& f : emcy) w.drive_bus->Send(f);
       },
       "drive fault", "fault", 8},
  };
  for (const SessionFault& fc : cases) {
    SCOPED_TRACE(fc.name);
    World w(20000);
    w.RunUntil(1200, nullptr);
    ASSERT_EQ(w.core->supervisor().state(), SupervisorState::kRunning);
    const std::int64_t injected = w.tick;
    fc.inject(w);
    w.Finish();
    ASSERT_TRUE(w.core->done());
    const SessionReport r = w.core->Report();
    EXPECT_EQ(r.stop_reason, fc.reason);
    EXPECT_EQ(r.final_state, fc.final_state);
    EXPECT_LE(r.stop_tick - injected, fc.max_reaction_ticks);
    EXPECT_GE(r.parked_tick, r.stop_tick);
    EXPECT_TRUE(r.limits_ok);
    w.ExpectPlatformInsideLimits();
  }
}

TEST(Session, AStopThatParksAtOnceStillReportsItsReasonAndTick) {
  // The platform rests at neutral, so the soft stop after the drives go silent finds nothing
  // to brake: the supervisor goes from RUNNING straight to PARKED in one cycle.
  World w(20000);
  w.still = true;
  w.RunUntil(1200, nullptr);
  ASSERT_EQ(w.core->supervisor().state(), SupervisorState::kRunning);
  const std::int64_t injected = w.tick;
  w.drives.SetSilent(true);
  w.Finish();
  ASSERT_TRUE(w.core->done());
  const std::string log = w.LogText();
  ASSERT_NE(log.find("supervisor parked (drive feedback stale)"), std::string::npos) << log.substr(0, 2000);
  ASSERT_EQ(log.find("supervisor soft-stop"), std::string::npos) << "this case should park at once";
  const SessionReport r = w.core->Report();
  EXPECT_EQ(r.stop_reason, "drive feedback stale");
  EXPECT_GE(r.stop_tick, injected);
  EXPECT_EQ(r.stop_tick, r.parked_tick);
  EXPECT_EQ(r.final_state, "parked");
}

TEST(Session, DropsReorderedAndStaleHeadsetPackets) {
  World w(800);
  w.RunUntil(400, nullptr);
  // Re-deliver an old head pose (duplicate seq) and one far in the past (stale).
  HmdMessage m;
  m.header.type = HmdType::kHeadPose;
  m.header.seq = 0;
  m.header.t_send_ns = World::kT0;
  m.body = HeadPoseMsg{World::kT0, Pose{}, 0, World::kT0};
  std::vector<std::uint8_t> b(kHmdMaxSize);
  b.resize(EncodeHmd(m, b));
  w.to_session.push_back({World::kT0 + w.tick * 1'000'000, b});
  m.header.seq = 1'000'000;
  b.resize(kHmdMaxSize);
  b.resize(EncodeHmd(m, b));
  w.to_session.push_back({World::kT0 + w.tick * 1'000'000, b});
  w.to_session.push_back({World::kT0 + w.tick * 1'000'000, {1, 2, 3}});
  w.Finish();
  const SessionReport r = w.core->Report();
  EXPECT_GE(r.hmd_rx.out_of_order, 1U);
  EXPECT_EQ(r.hmd_rx.stale, 1U);
  EXPECT_EQ(r.hmd_rx.malformed, 1U);
  EXPECT_EQ(r.final_state, "parked");
}

}  // namespace
}  // namespace pwsim::hw
