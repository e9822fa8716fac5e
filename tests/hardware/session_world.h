#pragma once
// Test harness for the session core: the simulated drives on an in-process bus and a scripted
// headset, on a fake clock (1 ms ticks from kT0). Whole sessions run in milliseconds.

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "hardware/can_bus.h"
#include "hardware/session.h"
#include "hardware/simulated_drives.h"

namespace pwsim::hw::session_testing {

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
  SessionOutputs out;  ///< reused from step to step, as the runner does
  /// Called with true just before SessionCore::Step and false just after (allocation counting).
  std::function<void(bool)> around_step;
  static constexpr std::int64_t kT0 = 5'000'000'000;

  explicit World(std::int64_t run_ticks = 3000) {
    cfg.run_ticks = run_ticks;
    core = std::make_unique<SessionCore>(cfg);
    log.push_back("# pwsim-session-log/1 " + cfg.ToHeader());
  }

  bool still = false;  ///< setpoints at neutral (the platform never moves)

  std::array<double, 2> Setpoint(std::int64_t t) const {
    if (still) return {0.0, 0.0};
    const double s = static_cast<double>(t) / 1000.0;
    return {0.05 * std::sin(0.9 * s), 0.25 * std::sin(1.1 * s)};
  }

  /// The scripted headset: one-way delay hmd_delay_ns each way, 1 us to answer.
  void HeadsetReceives(std::span<const std::uint8_t> bytes, std::int64_t sent) {
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
    std::vector<std::uint8_t> bytes_out(kHmdMaxSize);
    bytes_out.resize(EncodeHmd(r, bytes_out));
    to_session.push_back({rx + 1000 + hmd_delay_ns, std::move(bytes_out)});
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
    out.Clear();
    if (around_step) around_step(true);
    core->Step(tick, in, &out);
    if (around_step) around_step(false);
    AppendInputLines(tick, in, &log);
    for (std::string_view l : out.log) log.emplace_back(l);
    for (const CanFrame& x : out.can) master_bus->Send(x);
    for (const HmdDatagram& d : out.hmd) HeadsetReceives(d.bytes(), in.now_ns);
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

}  // namespace pwsim::hw::session_testing
