#pragma once
// Test harness for the session core: the simulated drives of a platform (one CiA 402 node per
// actuator of its mechanism: the car's 2 by default, the PW platform's 5, ...) on an in-process
// bus and a scripted headset riding the platform, on a fake clock (1 ms ticks from kT0). Whole
// sessions run in milliseconds.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "hardware/can_bus.h"
#include "hardware/session.h"
#include "hardware/simulated_drives.h"
#include "mca/platform.h"

namespace pwsim::hw::session_testing {

/// The platform top's motion for a pose x, in closed form with Eigen (independent of the core's
/// PlatformMotion): X_BP(x) · X_BP(0)^-1 with X_BP = Rz(yaw) Trans(s, w, h0 + z) Ry(-pitch) Rx(roll).
inline Pose RidePose(const mca::DofArray& x, double h0) {
  using mca::Dof;
  using mca::Index;
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(x[Index(Dof::kYaw)], Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(-x[Index(Dof::kPitch)], Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(x[Index(Dof::kRoll)], Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const Eigen::Matrix3d rz = Eigen::AngleAxisd(x[Index(Dof::kYaw)], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d t = rz * Eigen::Vector3d(x[Index(Dof::kSurge)], x[Index(Dof::kSway)], h0 + x[Index(Dof::kHeave)]) -
                            r * Eigen::Vector3d(0.0, 0.0, h0);
  const Eigen::Quaterniond q(r);
  Pose p;
  p.p = {t.x(), t.y(), t.z()};
  p.q = {q.x(), q.y(), q.z(), q.w()};
  return p;
}

struct World {
  mca::PlatformSpec platform;
  SessionConfig cfg;
  std::unique_ptr<SessionCore> core;
  InProcessBus hub;
  std::unique_ptr<ICanBus> master_bus = hub.Connect("session");
  std::unique_ptr<ICanBus> drive_bus = hub.Connect("drives");
  SimulatedDrives drives{cfg.mechanism};
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

  /// The car (seed 001, 2 drives) by default, or `spec`'s mechanism.
  explicit World(std::int64_t run_ticks = 3000, const mca::PlatformSpec& spec = mca::MakeCar2DofPlatform())
      : platform(spec), cfg(Configured(spec, run_ticks)) {
    core = std::make_unique<SessionCore>(cfg);
    log.push_back(std::string(kSessionLogMagic) + " " + cfg.ToHeader());
  }
  static SessionConfig Configured(const mca::PlatformSpec& spec, std::int64_t run_ticks) {
    SessionConfig c;
    c.run_ticks = run_ticks;
    c.SetPlatform(spec.name, spec.mechanism);
    return c;
  }

  bool still = false;  ///< setpoints at neutral (the platform never moves)
  /// Amplitude of the test motion on each axis the platform moves, as a fraction of the axis
  /// box's travel (a free axis: 0.05 rad).
  double fraction = 0.25;

  /// The MCA pose command at time t [ms]: neutral during the start-up (the first 0.2 s), then
  /// a slow sinusoid on every axis the mechanism moves, each at its own frequency (0.5 .. 1.3
  /// rad/s), faded in over 1.5 s (6u^5 - 15u^4 + 10u^3: continuous up to the acceleration, so the
  /// jerk stays finite), as a cueing starts from rest.
  mca::DofArray PoseAt(double t_ms) const {
    mca::DofArray x{};
    if (still) return x;
    const double s = t_ms / 1000.0;
    const double u = std::clamp((s - 0.2) / 1.5, 0.0, 1.0);
    const double window = u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
    for (mca::Dof d : mca::kAllDofs) {
      const auto k = static_cast<std::size_t>(mca::Index(d));
      if (!cfg.mechanism.Moves(d)) continue;
      const double travel = platform.limits(d).travel;
      const double amplitude = std::isfinite(travel) && travel > 0.0 ? fraction * travel : 0.05;
      x[k] = window * amplitude * std::sin((0.5 + 0.16 * static_cast<double>(k)) * s);
    }
    return x;
  }
  mca::DofArray Setpoint(std::int64_t t) const { return PoseAt(static_cast<double>(t)); }

  /// The scripted headset: one-way delay hmd_delay_ns each way, 1 us to answer.
  void HeadsetReceives(std::span<const std::uint8_t> bytes, std::int64_t sent) {
    HmdMessage m;
    if (!hmd_alive || DecodeHmd(bytes, &m) != CodecError::kOk) return;
    HmdMessage r;
    const std::int64_t rx = sent + hmd_delay_ns;
    if (const auto* cam = std::get_if<CameraPoseMsg>(&m.body)) {
      Pose head;
      head.p = {0.0, 0.0, 1.2};
      // the head rides the simulated platform: its pose by the drives' own forward kinematics
      // of their actual positions, composed in closed form
      const Pose ride = RidePose(drives.measured_pose(), cfg.mechanism.pivot_height());
      r.body = HeadPoseMsg{rx, ComposePose(ride, head), cam->frame, rx};
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
  /// Every simulated actuator stayed inside its stroke and speed (its actual states, sampled on
  /// every substep of the simulation), against the mechanism's limits (an unlimited rotary stage:
  /// the session's range).
  void ExpectPlatformInsideLimits() const {
    for (int i = 0; i < cfg.axis_count(); ++i) {
      const ActuatorMeasurement m = drives.measurement(i);
      const AxisLimits& l = cfg.safety.axes[static_cast<std::size_t>(i)];
      const mca::ActuatorLimits& a = cfg.mechanism.actuator(i).limits;
      EXPECT_GE(m.q_min, l.hard_min) << cfg.mechanism.actuator(i).name;
      EXPECT_LE(m.q_max, l.hard_max) << cfg.mechanism.actuator(i).name;
      EXPECT_LE(m.peak_speed, a.speed) << cfg.mechanism.actuator(i).name;
    }
  }
};

}  // namespace pwsim::hw::session_testing
