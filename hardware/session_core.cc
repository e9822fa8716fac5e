#include "hardware/session_core.h"

#include <algorithm>
#include <cmath>

#include "engine/interpolate.h"
#include "hardware/session_text.h"

namespace pwsim::hw {
SessionCore::SessionCore(SessionConfig config)
    : config_(config), supervisor_(config.safety), master_(config.master),
      hmd_filter_(config.hmd_timeout_ns, config.session_id) {
  measured_ns_.reserve(8192);
  measured_q_.reserve(8192);
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

std::array<double, 2> SessionCore::MeasuredAt(std::int64_t ns) const {
  if (measured_ns_.empty()) return {0.0, 0.0};
  // The times are whole nanoseconds below 2^53: exact as doubles, and so are their differences.
  const auto t = static_cast<double>(ns);
  if (t <= measured_ns_.front()) return measured_q_.front();
  if (t >= measured_ns_.back()) return measured_q_.back();
  const KnotSegment seg = FindKnotSegment(measured_ns_, t);
  const auto& a = measured_q_[seg.k];
  const auto& b = measured_q_[seg.k + 1];
  return {Lerp(a[0], b[0], seg.s), Lerp(a[1], b[1], seg.s)};
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
    const auto q = MeasuredAt(t_local);
    const Pose comp = CompensateHeadPose(head->head, q[0], q[1]);
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

void SessionCore::Step(std::int64_t tick, const SessionInputs& in, SessionOutputs* out) {
  const std::int64_t ns_per_tick = 1'000'000'000LL / config_.clock_rate_hz;
  ++steps_;
  last_tick_ = tick;
  lateness_us_.push_back(static_cast<double>(SaturatingSub(in.now_ns, in.scheduled_ns)) / 1000.0);
  if (in.stop_request && !stop_request_) {
    stop_request_ = true;
    out->log.Line('E').Int(tick).Word("stop requested");
  }

  for (const RxDatagram& d : in.hmd) HandleHmd(tick, d, out);
  const std::uint8_t rail_node = config_.master.axes[1].node;
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
    if (canopen::Classify(f, &node) == canopen::FrameKind::kTpdo1 && node == rail_node &&
        !platform_rx_ns_.empty() && platform_rx_ns_.back() < 0) {
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
    std::array<double, 2> measured{master_.axis(0).position, master_.axis(1).position};
    if (master_.axis(0).last_tpdo_cycle >= 0) {
      if (measured_ns_.size() >= 8192) {  // keep the newest half (capacity stays: no allocation)
        measured_ns_.erase(measured_ns_.begin(), measured_ns_.begin() + 4096);
        measured_q_.erase(measured_q_.begin(), measured_q_.begin() + 4096);
      }
      measured_ns_.push_back(static_cast<double>(in.now_ns));
      measured_q_.push_back(measured);
      for (std::size_t i = 0; i < 2; ++i)
        report_.peak_abs_measured[i] = std::max(report_.peak_abs_measured[i], std::abs(measured[i]));
    }
    const bool hmd_ok = !config_.hmd_required ||
                        (hmd_seen_ && !hmd_bye_ &&
                         (awaiting_head_since_ns_ < 0 ||
                          SaturatingSub(in.now_ns, awaiting_head_since_ns_) <= config_.hmd_timeout_ns));
    SafetyInputs si;
    si.setpoint = in.setpoint;
    si.measured = measured;
    si.drives_ready = master_.running() && (!config_.hmd_required || hmd_ok);
    si.heartbeats_ok = master_.heartbeats_ok();
    si.tpdos_fresh = master_.tpdos_fresh();
    si.drive_fault = master_.any_fault();
    si.bus_off = bus_off_;
    si.hmd_ok = hmd_ok;
    si.stop_requested = stop_request_ || tick >= config_.run_ticks;
    if (si.stop_requested && stop_since_tick_ < 0) stop_since_tick_ = tick;
    const std::array<double, 2> cmd = supervisor_.Step(cycle, si);

    // Independent check of what is streamed (finite differences, like the drive sees it).
    if (supervisor_.streaming()) {
      for (std::size_t i = 0; i < 2; ++i) {
        auto& h = last_cmd_[i];
        const double dt = config_.safety.dt;
        const double v = (cmd[i] - h[0]) / dt;
        const double a = (v - h[1]) / dt;
        const AxisLimits& lim = config_.safety.axes[i];
        report_.peak_abs_command[i] = std::max(report_.peak_abs_command[i], std::abs(cmd[i]));
        if (h[2] > 1.0) {  // two samples of history: v and a are meaningful
          report_.peak_abs_command_velocity[i] = std::max(report_.peak_abs_command_velocity[i], std::abs(v));
          if (h[2] > 2.0)
            report_.peak_abs_command_accel[i] = std::max(report_.peak_abs_command_accel[i], std::abs(a));
          if (std::abs(v) > lim.velocity * (1 + 1e-9) ||
              (h[2] > 2.0 && std::abs(a) > lim.accel * (1 + 1e-6)))
            report_.limits_ok = false;
        }
        if (std::abs(cmd[i]) > lim.workspace + 1e-12) report_.limits_ok = false;
        h = {cmd[i], v, h[2] + 1.0};
      }
    } else {
      for (std::size_t i = 0; i < 2; ++i) last_cmd_[i] = {cmd[i], 0.0, 0.0};
    }
    for (std::size_t i = 0; i < 2; ++i)
      if (report_.peak_abs_measured[i] > config_.safety.axes[i].hard_limit) report_.limits_ok = false;

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
      if (state == SupervisorState::kParked) report_.parked_tick = tick;
      last_state_ = state;
    }
    if (state == SupervisorState::kFault && supervisor_.parked_cycle() >= 0 && report_.parked_tick < 0)
      report_.parked_tick = supervisor_.parked_cycle() * config_.drive_cycle_ticks;

    // Finish: parked (or at rest in fault) -> disable the drives, say bye, stop after 10 cycles.
    const bool at_rest = state == SupervisorState::kParked ||
                         (state == SupervisorState::kFault && supervisor_.parked_cycle() >= 0);
    const bool never_started = state == SupervisorState::kIdle && si.stop_requested;
    const bool timed_out = stop_since_tick_ >= 0 && tick - stop_since_tick_ > config_.max_stop_ticks;
    if ((at_rest && (si.stop_requested || state == SupervisorState::kFault || stop_since_tick_ >= 0)) ||
        never_started || timed_out || (state == SupervisorState::kParked)) {
      if (disable_ticks_ == 0) {
        master_.RequestDisable();
        SendHmd(ByeMsg{}, in.now_ns, out);
        out->log.Line('E').Int(tick).Word("finishing");
        if (timed_out) out->log.Word("(timed out waiting for park)");
      }
      if (++disable_ticks_ > 10) done_ = true;
    }

    master_.Cycle(cycle, cmd, &out->can);
    if (master_.phase() != last_phase_) {
      last_phase_ = master_.phase();
      out->log.Line('E').Int(tick).Word("master").Word(MasterPhaseName(last_phase_));
    }
    const auto idx = static_cast<std::size_t>(cycle);
    if (platform_rx_ns_.size() <= idx) platform_rx_ns_.resize(idx + 1, -1);
    const std::array<double, 2> sp = in.setpoint.value_or(std::array<double, 2>{NAN, NAN});
    out->log.Line('S').Int(tick).Int(cycle).Num(sp[0]).Num(sp[1]).Num(cmd[0]).Num(cmd[1]);
    out->log.Num(measured[0]).Num(measured[1]).Word(SupervisorStateName(state));
    out->log.Word(MasterPhaseName(master_.phase()));
  }

  if (is_frame_tick(tick) && in.camera && !done_) {
    const std::int64_t frame = tick / config_.frame_ticks;
    const auto idx = static_cast<std::size_t>(frame);
    if (frame_shown_ns_.size() <= idx) frame_shown_ns_.resize(idx + 1, -1);
    const auto& m = supervisor_.motion();
    SendHmd(CameraPoseMsg{tick, frame, *in.camera, {m[0].p, m[1].p}}, in.now_ns, out);
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
  r.final_state = SupervisorStateName(supervisor_.state());
  return r;
}


}  // namespace pwsim::hw
