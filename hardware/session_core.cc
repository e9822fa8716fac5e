#include "hardware/session_core.h"

#include <algorithm>
#include <cmath>

#include "engine/interpolate.h"
#include "hardware/session_text.h"

namespace pwsim::hw {
namespace {

using canopen::DriveState;

Pose Rotation(const std::array<double, 4>& q) {
  Pose p;
  p.q = q;
  return p;
}
Pose Translation(double x, double y, double z) {
  Pose p;
  p.p = {x, y, z};
  return p;
}

}  // namespace

Pose PlatformMotion(const mca::DofArray& x, double h0) {
  using mca::Dof;
  using mca::Index;
  const double yaw = x[Index(Dof::kYaw)], pitch = x[Index(Dof::kPitch)], roll = x[Index(Dof::kRoll)];
  const Pose rz = Rotation({0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw)});
  const Pose ry = Rotation({0.0, std::sin(-0.5 * pitch), 0.0, std::cos(-0.5 * pitch)});
  const Pose rx = Rotation({std::sin(0.5 * roll), 0.0, 0.0, std::cos(0.5 * roll)});
  const Pose up = Translation(x[Index(Dof::kSurge)], x[Index(Dof::kSway)], h0 + x[Index(Dof::kHeave)]);
  return ComposePose(ComposePose(ComposePose(ComposePose(rz, up), ry), rx), Translation(0.0, 0.0, -h0));
}

SessionCore::SessionCore(SessionConfig config)
    : config_(std::move(config)), supervisor_(config_.safety), master_(config_.master),
      hmd_filter_(config_.hmd_timeout_ns, config_.session_id) {
  n_ = config_.master.axis_count;
  for (int i = 0; i < config_.mechanism.actuator_count(); ++i) {
    const mca::Actuator& a = config_.mechanism.actuator(i);
    if (a.kind == mca::ActuatorKind::kLeg) continue;
    if (a.dof == mca::Dof::kYaw) yaw_axis_ = i;
    if (a.dof == mca::Dof::kSurge) surge_axis_ = i;
  }
  feedback_rx_ns_.fill(-1);
  measured_ns_.reserve(8192);
  measured_poses_.reserve(8192);
  // The longest session: motion until run_ticks, then at most max_stop_ticks to park and 10
  // drive cycles to disable (a few more for rounding). Capped so that a hostile log header
  // cannot ask for gigabytes; a longer session grows these (allocating) but stays correct.
  constexpr std::int64_t kMaxReservedTicks = 1LL << 22;  // ~70 min at 1 kHz
  const std::int64_t drive = std::max(1, config_.drive_cycle_ticks);
  const std::int64_t frame = std::max(1, config_.frame_ticks);
  const std::int64_t last_tick = std::clamp<std::int64_t>(
      config_.run_ticks + config_.max_stop_ticks + 16 * drive, 0, kMaxReservedTicks);
  const auto drives = static_cast<std::size_t>(last_tick / drive + 2);
  const auto frames = static_cast<std::size_t>(last_tick / frame + 2);
  lateness_us_.reserve(drives + frames);
  period_jitter_us_.reserve(drives);
  platform_rx_ns_.reserve(drives);
  frame_shown_ns_.reserve(frames);
  report_.platform = config_.platform;
  report_.velocity_tolerance = config_.velocity_tolerance;
  report_.axes.resize(static_cast<std::size_t>(n_));
  for (int i = 0; i < n_; ++i) {
    AxisReport& a = report_.axes[static_cast<std::size_t>(i)];
    const mca::Actuator& act = config_.mechanism.actuator(i);
    const AxisLimits& l = config_.safety.axes[static_cast<std::size_t>(i)];
    a.actuator = act.name;
    a.unit = act.unit();
    a.node = config_.master.axes[static_cast<std::size_t>(i)].node;
    a.stroke_min = l.hard_min;
    a.stroke_max = l.hard_max;
    a.speed = l.velocity;
    a.command_min = a.measured_min = std::numeric_limits<double>::infinity();
    a.command_max = a.measured_max = -std::numeric_limits<double>::infinity();
  }
}

void SessionCore::SendHmd(HmdBody body, std::int64_t now_ns, SessionOutputs* out) {
  HmdMessage m;
  m.header.seq = hmd_seq_++;
  m.header.session = config_.session_id;
  m.header.t_send_ns = now_ns;
  m.header.type = static_cast<HmdType>(body.index() + 1);
  m.body = std::move(body);
  HmdDatagram& d = out->hmd.emplace_back();
  d.size = EncodeHmd(m, d.data);
}

mca::DofArray SessionCore::MeasuredAt(std::int64_t ns) const {
  if (measured_ns_.empty()) return measured_pose_;
  // The times are whole nanoseconds below 2^53: exact as doubles, and so are their differences.
  const auto t = static_cast<double>(ns);
  if (t <= measured_ns_.front()) return measured_poses_.front();
  if (t >= measured_ns_.back()) return measured_poses_.back();
  const KnotSegment seg = FindKnotSegment(measured_ns_, t);
  const auto& a = measured_poses_[seg.k];
  const auto& b = measured_poses_[seg.k + 1];
  mca::DofArray x{};
  for (std::size_t k = 0; k < x.size(); ++k) x[k] = Lerp(a[k], b[k], seg.s);
  return x;
}

void SessionCore::HandleHmd(std::int64_t tick, const RxDatagram& d, SessionOutputs* out) {
  HmdMessage m;
  if (DecodeHmd(d.bytes, &m) != CodecError::kOk) {
    hmd_filter_.CountMalformed();
    return;
  }
  if (!hmd_filter_.Accept(m, d.rx_ns, offset_)) {
    // A headset that restarted names a stream of its own: run the start-up (hmd_protocol.h).
    if (hmd_filter_.TakeHelloWanted()) SendHmd(hmd_filter_.HelloAnswer(), d.rx_ns, out);
    return;
  }
  if (std::holds_alternative<HelloMsg>(m.body)) {
    SendHmd(hmd_filter_.HelloAnswer(), d.rx_ns, out);  // a HELLO that asks for an answer
  } else if (const auto* pong = std::get_if<PongMsg>(&m.body)) {
    offset_.AddSample(pong->t0, pong->t1, pong->t2, d.rx_ns);
  } else if (const auto* head = std::get_if<HeadPoseMsg>(&m.body)) {
    hmd_seen_ = true;
    awaiting_head_since_ns_ = -1;
    const std::int64_t t_local = SaturatingSub(head->t_sample_ns, offset_.offset_ns());
    const Pose platform = PlatformMotion(MeasuredAt(t_local), config_.mechanism.pivot_height());
    const Pose comp = ComposePose(InversePose(platform), head->head);
    out->log.Line('P').Int(tick).Int(t_local).PoseNums(head->head).PoseNums(comp);
    if (head->last_frame >= 0 &&
        static_cast<std::size_t>(head->last_frame) < frame_shown_ns_.size() &&
        frame_shown_ns_[static_cast<std::size_t>(head->last_frame)] < 0) {
      frame_shown_ns_[static_cast<std::size_t>(head->last_frame)] =
          SaturatingSub(head->t_frame_rx_ns, offset_.offset_ns());
    }
  } else if (std::holds_alternative<ByeMsg>(m.body)) {
    hmd_bye_ = true;
    out->log.Line('E').Int(tick).Word("hmd said bye");
  }
}

void SessionCore::LogDriveEvents(std::int64_t tick, SessionOutputs* out) {
  DriveEvents& e = report_.drive_events;
  for (int i = 0; i < n_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const AxisStatus& a = master_.axis(i);
    AxisStatus& before = last_axis_[k];
    auto line = [&](std::string_view what) {
      out->log.Line('E').Int(tick).Word("drive").Int(config_.master.axes[k].node).Word(what);
    };
    if (a.heartbeat_lost && !before.heartbeat_lost) {
      ++e.heartbeat_lost;
      line("heartbeat lost");
    }
    if (a.restarts != before.restarts) {
      e.restarts += a.restarts - before.restarts;
      line("restarted (boot-up): start-up again");
    }
    if (a.returns != before.returns) {
      e.returns += a.returns - before.returns;
      line("back without a boot-up: NMT reset-communication");
    }
    if (a.readmissions != before.readmissions) {
      e.readmissions += a.readmissions - before.readmissions;
      line("re-admitted (operation enabled)");
    }
    if (a.drive != before.drive && a.last_tpdo_cycle >= 0) {
      if (a.drive == DriveState::kQuickStopActive) ++e.quick_stops;
      if ((a.drive == DriveState::kFault || a.drive == DriveState::kFaultReactionActive) &&
          before.drive != DriveState::kFault && before.drive != DriveState::kFaultReactionActive)
        ++e.faults;
      line(canopen::DriveStateName(a.drive));
    }
    if (a.emcy_count != before.emcy_count) {
      line("EMCY");
      out->log.Int(a.last_emcy_code);
    }
    before = a;
  }
}

const char* SessionCore::FinalStateFromDrives() const {
  if (supervisor_.state() == SupervisorState::kIdle && !master_.running()) {
    return master_.tpdos_fresh() ? "not-started" : "feedback-lost";
  }
  if (!master_.tpdos_fresh()) return "feedback-lost";
  bool fault = supervisor_.state() == SupervisorState::kFault, quick = false, parked = true;
  for (int i = 0; i < n_; ++i) {
    const AxisStatus& a = master_.axis(i);
    const auto k = static_cast<std::size_t>(i);
    if (a.fault) fault = true;
    if (a.drive == DriveState::kQuickStopActive) quick = true;
    if (a.drive != DriveState::kOperationEnabled ||
        std::abs(a.position - config_.safety.neutral[k]) > config_.park_measured_tolerance ||
        std::abs(a.velocity) > config_.rest_velocity_tolerance)
      parked = false;
  }
  if (fault) return "fault";
  if (quick) return "quick-stop";
  if (supervisor_.state() == SupervisorState::kIdle) return "not-started";
  return parked ? "parked" : "not-parked";
}

void SessionCore::Step(std::int64_t tick, const SessionInputs& in, SessionOutputs* out) {
  const std::int64_t ns_per_tick = 1'000'000'000LL / config_.clock_rate_hz;
  ++steps_;
  last_tick_ = tick;
  last_now_ns_ = in.now_ns;
  lateness_us_.push_back(static_cast<double>(SaturatingSub(in.now_ns, in.scheduled_ns)) / 1000.0);
  if (in.stop_request && !stop_request_) {
    stop_request_ = true;
    out->log.Line('E').Int(tick).Word("stop requested");
  }

  for (const RxDatagram& d : in.hmd) HandleHmd(tick, d, out);
  const std::uint8_t first_node = config_.master.axes[0].node;
  for (const RxFrame& r : in.can) {
    const CanFrame& f = r.frame;
    if (f.error()) {
      if ((f.id & kCanErrBusOff) != 0 && !bus_off_) {
        bus_off_ = true;
        out->log.Line('E').Int(tick).Word("bus-off error frame");
      }
      continue;
    }
    master_.OnFrame(f);
    std::uint8_t node = 0;
    if (canopen::Classify(f, &node) == canopen::FrameKind::kTpdo1) {
      for (int i = 0; i < n_; ++i)
        if (config_.master.axes[static_cast<std::size_t>(i)].node == node)
          feedback_rx_ns_[static_cast<std::size_t>(i)] = r.rx_ns;
      if (node == first_node && !platform_rx_ns_.empty() && platform_rx_ns_.back() < 0)
        platform_rx_ns_.back() = r.rx_ns;
    }
  }

  if (is_drive_tick(tick)) {
    const std::int64_t cycle = tick / config_.drive_cycle_ticks;
    const std::int64_t period_ns = ns_per_tick * config_.drive_cycle_ticks;
    if (last_drive_now_ns_ >= 0)
      period_jitter_us_.push_back(
          std::abs(static_cast<double>(SaturatingSub(in.now_ns, last_drive_now_ns_)) -
                   static_cast<double>(period_ns)) / 1000.0);
    last_drive_now_ns_ = in.now_ns;
    const auto n = static_cast<std::size_t>(n_);

    // The drives' feedback: measured positions -> the measured pose (forward kinematics).
    AxisValues measured{};
    bool all = true;
    for (std::size_t k = 0; k < n; ++k) {
      const AxisStatus& a = master_.axis(static_cast<int>(k));
      measured[k] = a.position;
      if (a.last_tpdo_cycle >= 0) {
        AxisReport& r = report_.axes[k];
        r.measured = true;
        r.measured_min = std::min(r.measured_min, a.position);
        r.measured_max = std::max(r.measured_max, a.position);
        r.peak_measured_velocity = std::max(r.peak_measured_velocity, std::abs(a.velocity));
        const AxisLimits& l = config_.safety.axes[k];
        if (a.position < l.hard_min || a.position > l.hard_max ||
            std::abs(a.velocity) > l.velocity * (1.0 + config_.velocity_tolerance))
          report_.within_limits = false;
      } else {
        all = false;
      }
    }
    measured_all_ = measured_all_ || all;
    const bool fresh = master_.tpdos_fresh();
    if (measured_all_ && fresh) {
      mca::ActuatorVector q(n_);
      for (std::size_t k = 0; k < n; ++k) q(static_cast<Eigen::Index>(k)) = measured[k];
      mca::DofArray pose = measured_pose_;
      const mca::KinematicsStatus fk = config_.mechanism.Forward(q, measured_pose_, &pose);
      if (fk.ok || std::isfinite(pose[0] + pose[1] + pose[2] + pose[3] + pose[4] + pose[5])) measured_pose_ = pose;
      if (master_.running() && !finishing_) {
        report_.fk_residual_max = std::max(report_.fk_residual_max, fk.residual);
        if (supervisor_.state() == SupervisorState::kRunning)
          report_.fk_residual_tracking_max = std::max(report_.fk_residual_tracking_max, fk.residual);
      }
      for (std::size_t k = 0; k < 6; ++k)
        report_.peak_abs_measured_pose[k] = std::max(report_.peak_abs_measured_pose[k], std::abs(measured_pose_[k]));
      if (measured_ns_.size() >= 8192) {  // keep the newest half (capacity stays: no allocation)
        measured_ns_.erase(measured_ns_.begin(), measured_ns_.begin() + 4096);
        measured_poses_.erase(measured_poses_.begin(), measured_poses_.begin() + 4096);
      }
      measured_ns_.push_back(static_cast<double>(in.now_ns));
      measured_poses_.push_back(measured_pose_);
    }

    // The MCA pose command -> actuator setpoints (inverse kinematics).
    std::optional<AxisValues> setpoint;
    if (in.setpoint) {
      mca::ActuatorVector q(n_);
      if (config_.mechanism.Inverse(*in.setpoint, &q)) {
        AxisValues sp{};
        for (std::size_t k = 0; k < n; ++k) sp[k] = q(static_cast<Eigen::Index>(k));
        setpoint = sp;
      } else {
        ++report_.ik_failures;
      }
    }

    const bool hmd_ok = !config_.hmd_required ||
                        (hmd_seen_ && !hmd_bye_ &&
                         (awaiting_head_since_ns_ < 0 ||
                          SaturatingSub(in.now_ns, awaiting_head_since_ns_) <= config_.hmd_timeout_ns));
    SafetyInputs si;
    si.setpoint = setpoint;
    si.measured = measured;
    si.drives_ready = master_.running() && (!config_.hmd_required || hmd_ok);
    si.drives_enabled = master_.running() || finishing_;  // finishing: the master disables them
    si.heartbeats_ok = master_.heartbeats_ok();
    si.tpdos_fresh = fresh;
    si.drive_fault = master_.any_fault();
    si.drive_quick_stop = master_.any_quick_stop();
    si.drive_restarted = master_.readmitting();
    si.bus_off = bus_off_;
    si.hmd_ok = hmd_ok;
    si.stop_requested = stop_request_ || tick >= config_.run_ticks;
    if (si.stop_requested && stop_since_tick_ < 0) stop_since_tick_ = tick;
    const AxisValues cmd = supervisor_.Step(cycle, si);

    // Independent check of what is streamed (finite differences, like the drive sees it).
    if (supervisor_.streaming() && !supervisor_.holding()) {
      for (std::size_t i = 0; i < n; ++i) {
        auto& h = last_cmd_[i];
        const double dt = config_.safety.dt;
        const double v = (cmd[i] - h[0]) / dt;
        const double a = (v - h[1]) / dt;
        const AxisLimits& lim = config_.safety.axes[i];
        AxisReport& r = report_.axes[i];
        r.command_min = std::min(r.command_min, cmd[i]);
        r.command_max = std::max(r.command_max, cmd[i]);
        if (h[2] > 1.0) {  // two samples of history: v and a are meaningful
          r.peak_command_velocity = std::max(r.peak_command_velocity, std::abs(v));
          if (h[2] > 2.0) r.peak_command_accel = std::max(r.peak_command_accel, std::abs(a));
          if (std::abs(v) > lim.velocity * (1 + 1e-9) ||
              (h[2] > 2.0 && std::abs(a) > lim.accel * (1 + 1e-6)))
            report_.limits_ok = false;
        }
        if (cmd[i] < lim.min - 1e-12 || cmd[i] > lim.max + 1e-12) report_.limits_ok = false;
        h = {cmd[i], v, h[2] + 1.0};
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) last_cmd_[i] = {cmd[i], 0.0, 0.0};
    }

    LogDriveEvents(tick, out);
    if (supervisor_.streaming() && !fresh) {
      if (lost_since_tick_ < 0) {
        lost_since_tick_ = tick;
        ++report_.drive_events.feedback_lost;
        out->log.Line('E').Int(tick).Word("drive feedback lost");
      }
    } else if (fresh && lost_since_tick_ >= 0) {
      lost_since_tick_ = -1;
      out->log.Line('E').Int(tick).Word("drive feedback back");
    }

    const SupervisorState state = supervisor_.state();
    if (state != last_state_) {
      out->log.Line('E').Int(tick).Word("supervisor").Word(SupervisorStateName(state));
      if (!supervisor_.reason().empty()) out->log.Raw(" (").Raw(supervisor_.reason()).Raw(")");
      // A soft stop that finds the platform already at neutral parks in the same cycle: the
      // stop is recorded on reaching PARKED then (with the supervisor's reason).
      const bool stopping = state == SupervisorState::kSoftStop || state == SupervisorState::kFault ||
                            (state == SupervisorState::kParked && !supervisor_.reason().empty());
      if (stopping && report_.stop_tick < 0) {
        report_.stop_tick = tick;
        stop_reason_ = supervisor_.reason();
      }
      last_state_ = state;
    }

    // Finish on what the drives say (header comment): then disable them, say bye, stop after
    // 10 cycles.
    if (!finishing_) {
      const char* now = FinalStateFromDrives();
      const bool is = [&] {
        for (std::size_t k = 0; k < n; ++k)
          if (std::abs(master_.axis(static_cast<int>(k)).velocity) > config_.rest_velocity_tolerance) return false;
        return fresh;
      }();
      const bool parked = state == SupervisorState::kParked && now == std::string_view("parked");
      const bool fault_at_rest = state == SupervisorState::kFault && is &&
                                 (supervisor_.holding() || supervisor_.parked_cycle() >= 0);
      const bool never_started = state == SupervisorState::kIdle && si.stop_requested;
      const bool timed_out = stop_since_tick_ >= 0 && tick - stop_since_tick_ > config_.max_stop_ticks;
      const bool gave_up = lost_since_tick_ >= 0 && tick - lost_since_tick_ > config_.drive_return_ticks;
      if (parked || fault_at_rest || never_started || timed_out || gave_up) {
        finishing_ = true;
        final_state_ = now;
        if (parked || fault_at_rest) report_.parked_tick = tick;
        master_.RequestDisable();
        SendHmd(ByeMsg{}, in.now_ns, out);
        out->log.Line('E').Int(tick).Word("finishing").Word(now);
        if (gave_up) out->log.Word("(gave up waiting for the drives' feedback)");
        else if (timed_out) out->log.Word("(timed out waiting for park)");
      }
    }
    if (finishing_ && ++disable_ticks_ > 10) done_ = true;

    master_.Cycle(cycle, cmd, &out->can);
    if (master_.phase() != last_phase_) {
      last_phase_ = master_.phase();
      out->log.Line('E').Int(tick).Word("master").Word(MasterPhaseName(last_phase_));
      if (last_phase_ == MasterPhase::kResetComm) {
        // the start-up timed out: say which drives never answered (another platform's drives?)
        out->log.Word("(no boot-up from node");
        for (int i = 0; i < n_; ++i)
          if (!master_.axis(i).seen_heartbeat) out->log.Int(config_.master.axes[static_cast<std::size_t>(i)].node);
        out->log.Raw(")");
      }
    }
    const auto idx = static_cast<std::size_t>(cycle);
    if (platform_rx_ns_.size() <= idx) platform_rx_ns_.resize(idx + 1, -1);
    out->log.Line('S').Int(tick).Int(cycle);
    for (std::size_t k = 0; k < n; ++k) out->log.Num(setpoint ? (*setpoint)[k] : NAN);
    for (std::size_t k = 0; k < n; ++k) out->log.Num(cmd[k]);
    for (std::size_t k = 0; k < n; ++k) out->log.Num(measured[k]);
    for (double x : measured_pose_) out->log.Num(x);
    out->log.Word(SupervisorStateName(state)).Word(MasterPhaseName(master_.phase()));
  }

  if (is_frame_tick(tick) && in.camera && !done_) {
    const std::int64_t frame = tick / config_.frame_ticks;
    const auto idx = static_cast<std::size_t>(frame);
    if (frame_shown_ns_.size() <= idx) frame_shown_ns_.resize(idx + 1, -1);
    const auto& m = supervisor_.motion();
    // The commanded yaw and surge stages, for a headset stand-in riding the platform.
    const std::array<double, 2> ride{yaw_axis_ >= 0 ? m[static_cast<std::size_t>(yaw_axis_)].p : 0.0,
                                     surge_axis_ >= 0 ? m[static_cast<std::size_t>(surge_axis_)].p : 0.0};
    SendHmd(CameraPoseMsg{tick, frame, *in.camera, ride}, in.now_ns, out);
    if (awaiting_head_since_ns_ < 0) awaiting_head_since_ns_ = in.now_ns;
    if (frame % config_.ping_every_frames == 0) SendHmd(PingMsg{in.now_ns}, in.now_ns, out);
  }

  for (const CanFrame& f : out->can) out->log.Line('c').Frame(f);
  for (const HmdDatagram& d : out->hmd) out->log.Line('h').Hex(d.bytes());
}

SessionReport SessionCore::Report() const {
  SessionReport r = report_;
  r.stop_reason = std::string(stop_reason_);
  r.ticks = last_tick_;
  r.steps = steps_;
  r.cycle_lateness_us = ComputePercentiles(lateness_us_);
  r.cycle_period_jitter_us = ComputePercentiles(period_jitter_us_);
  std::vector<double> skew;
  std::vector<double> abs_skew;
  for (std::size_t f = 0; f < frame_shown_ns_.size(); ++f) {
    if (frame_shown_ns_[f] < 0) continue;
    const std::int64_t tick = static_cast<std::int64_t>(f) * config_.frame_ticks;
    if (tick % config_.drive_cycle_ticks != 0) continue;
    const auto c = static_cast<std::size_t>(tick / config_.drive_cycle_ticks);
    if (c >= platform_rx_ns_.size() || platform_rx_ns_[c] < 0) continue;
    const double s = static_cast<double>(SaturatingSub(frame_shown_ns_[f], platform_rx_ns_[c])) / 1e6;
    skew.push_back(s);
    abs_skew.push_back(std::abs(s));
  }
  r.skew_ms = ComputePercentiles(skew);
  r.abs_skew_ms = ComputePercentiles(abs_skew);
  r.clock_offset_ns = offset_.offset_ns();
  r.clock_rtt_ns = offset_.rtt_ns();
  r.hmd_rx = hmd_filter_.counters();
  r.safety = supervisor_.counters();
  r.supervisor_state = SupervisorStateName(supervisor_.state());
  r.final_state = finishing_ ? final_state_ : FinalStateFromDrives();
  for (int i = 0; i < n_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const AxisStatus& a = master_.axis(i);
    AxisReport& x = r.axes[k];
    if (!x.measured) x.measured_min = x.measured_max = 0.0;
    if (!(x.command_min <= x.command_max)) x.command_min = x.command_max = 0.0;
    x.state = canopen::DriveStateName(a.drive);
    x.nmt = canopen::NmtStateName(a.nmt);
    x.statusword = a.statusword;
    x.position = a.position;
    x.velocity = a.velocity;
    x.feedback_age_ms = feedback_rx_ns_[k] < 0
                            ? -1.0
                            : static_cast<double>(SaturatingSub(last_now_ns_, feedback_rx_ns_[k])) / 1e6;
    x.last_emcy_code = a.last_emcy_code;
    x.restarts = a.restarts;
    x.returns = a.returns;
    x.readmissions = a.readmissions;
  }
  return r;
}

}  // namespace pwsim::hw
