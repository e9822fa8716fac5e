// The session core with the simulated drives on an in-process bus and a scripted headset, on
// a fake clock: whole sessions in milliseconds, the fault matrix at session level, and the
// log replayed bit for bit.
#include "hardware/session.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "hardware/can_bus.h"
#include "hardware/simulated_drives.h"

namespace pwsim::hw {
namespace {

struct World {
  SessionConfig cfg;
  std::unique_ptr<SessionCore> core;
  InProcessBus hub;
  std::unique_ptr<ICanBus> master_bus = hub.Connect("session");
  std::unique_ptr<ICanBus> drive_bus = hub.Connect("drives");
  SimulatedDrives drives;
  std::vector<RxDatagram> to_session;
  bool hmd_alive = true;
  std::int64_t hmd_delay_ns = 350'000;
  std::vector<RxFrame> can_to_session;
  std::uint32_t hmd_seq = 0;
  std::vector<std::string> log;
  std::int64_t tick = 0;
  static constexpr std::int64_t kT0 = 5'000'000'000;

  explicit World(std::int64_t run_ticks = 3000) {
    cfg.run_ticks = run_ticks;
    core = std::make_unique<SessionCore>(cfg);
    log.push_back("# pwsim-session-log/1 " + cfg.ToHeader());
  }

  std::array<double, 2> Setpoint(std::int64_t t) const {
    const double s = static_cast<double>(t) / 1000.0;
    return {0.05 * std::sin(0.9 * s), 0.25 * std::sin(1.1 * s)};
  }

  /// The scripted headset: one-way delay hmd_delay_ns each way, 1 us to answer.
  void HeadsetReceives(const std::vector<std::uint8_t>& bytes, std::int64_t sent) {
    HmdMessage m;
    if (!hmd_alive || DecodeHmd(bytes, &m) != CodecError::kOk) return;
    HmdMessage r;
    const std::int64_t rx = sent + hmd_delay_ns;
    if (const auto* cam = std::get_if<CameraPoseMsg>(&m.body)) {
      Pose head;
      head.p = {0.0, 0.0, 1.2};
      r.body = HeadPoseMsg{rx, ComposePose(PlatformPose(cam->platform[0], cam->platform[1]), head), cam->frame, rx};
    } else if (const auto* ping = std::get_if<PingMsg>(&m.body)) {
      r.body = PongMsg{ping->t0, rx, rx + 1000};
    } else {
      return;
    }
    r.header.type = static_cast<HmdType>(r.body.index() + 1);
    r.header.seq = hmd_seq++;
    r.header.t_send_ns = rx + 1000;
    std::vector<std::uint8_t> out(kHmdMaxSize);
    out.resize(EncodeHmd(r, out));
    to_session.push_back({rx + 1000 + hmd_delay_ns, std::move(out)});
  }

  /// One engine tick with work (the runner skips the others).
  void Step() {
    while (!core->is_drive_tick(tick) && !core->is_frame_tick(tick)) ++tick;
    const std::int64_t now = kT0 + tick * 1'000'000;
    SessionInputs in;
    in.now_ns = now + 15'000;  // woke 15 us late
    in.scheduled_ns = now;
    CanFrame f;
    for (auto it = can_to_session.begin(); it != can_to_session.end();) {
      if (it->rx_ns <= now) {
        in.can.push_back(*it);
        it = can_to_session.erase(it);
      } else {
        ++it;
      }
    }
    while (master_bus->Receive(&f) == BusStatus::kOk) in.can.push_back({now, f});
    for (auto it = to_session.begin(); it != to_session.end();) {
      if (it->rx_ns <= now) {
        in.hmd.push_back(*it);
        it = to_session.erase(it);
      } else {
        ++it;
      }
    }
    if (core->is_drive_tick(tick)) in.setpoint = Setpoint(tick);
    if (core->is_frame_tick(tick)) in.camera = Pose{};
    SessionOutputs out;
    core->Step(tick, in, &out);
    AppendInputLines(tick, in, &log);
    log.insert(log.end(), out.log.begin(), out.log.end());
    for (const CanFrame& x : out.can) master_bus->Send(x);
    for (const auto& d : out.hmd) HeadsetReceives(d, in.now_ns);
    std::vector<CanFrame> replies;
    const std::int64_t drive_now = in.now_ns + 50'000;  // the drives get the SYNC 50 us later
    drives.Poll(drive_now, &replies);
    while (drive_bus->Receive(&f) == BusStatus::kOk) drives.OnFrame(f, drive_now, &replies);
    for (const CanFrame& x : replies) drive_bus->Send(x);
    // Their answers reach the session 100 us after that (stamped like the runner does).
    while (master_bus->Receive(&f) == BusStatus::kOk) can_to_session.push_back({drive_now + 100'000, f});
    ++tick;
  }

  /// Runs until `pred` or done; returns the tick at which pred held (or -1).
  std::int64_t RunUntil(std::int64_t max_tick, const std::function<bool()>& pred) {
    while (tick < max_tick && !core->done()) {
      Step();
      if (pred && pred()) return tick - 1;
    }
    return -1;
  }
  void Finish(std::int64_t max_tick = 60000) { RunUntil(max_tick, nullptr); }
  std::string LogText() const {
    std::string s;
    for (const auto& l : log) s += l + "\n";
    return s;
  }
  void ExpectPlatformInsideLimits() const {
    const auto& peak = drives.peak_abs_position();
    EXPECT_LE(peak[0], cfg.safety.axes[0].hard_limit);
    EXPECT_LE(peak[1], cfg.safety.axes[1].hard_limit);
  }
};

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
      {"headset vanishes", [](World& w) { w.hmd_alive = false; }, "HMD link stale", "parked",
       250 + 8},
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
