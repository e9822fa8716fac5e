#include "hardware/session.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "engine/number_format.h"

namespace pwsim::hw {
namespace {

std::string F(double v) { return FormatDouble(v); }

std::string PoseText(const Pose& p) {
  std::string s;
  for (double v : p.p) s += " " + F(v);
  for (double v : p.q) s += " " + F(v);
  return s;
}

bool ParseI64(std::string_view s, std::int64_t* v) {
  if (s.empty()) return false;
  std::int64_t x = 0;
  bool neg = false;
  std::size_t i = 0;
  if (s[0] == '-') {
    neg = true;
    i = 1;
  }
  if (i >= s.size()) return false;
  if (s.size() - i > 18) return false;  // keeps x inside int64
  for (; i < s.size(); ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    x = x * 10 + (s[i] - '0');
  }
  *v = neg ? -x : x;
  return true;
}

bool ParseF64(const std::string& s, double* v) {
  try {
    std::size_t used = 0;
    *v = std::stod(s, &used);
    return used == s.size();
  } catch (...) {
    return s == "nan" ? (*v = NAN, true) : false;
  }
}

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> parts;
  std::istringstream in(line);
  std::string w;
  while (in >> w) parts.push_back(w);
  return parts;
}

}  // namespace

// --- config ---------------------------------------------------------------------------------
std::string SessionConfig::Validate() const {
  if (clock_rate_hz < 100 || clock_rate_hz > 100000) return "clock_rate_hz: expected 100..100000";
  if (drive_cycle_ticks < 1) return "drive_cycle_ticks: expected >= 1";
  if (frame_ticks < 1) return "frame_ticks: expected >= 1";
  if (ping_every_frames < 1) return "ping_every_frames: expected >= 1";
  if (run_ticks < 0 || max_stop_ticks < 1) return "run_ticks/max_stop_ticks: expected >= 0 / >= 1";
  if (hmd_timeout_ns < 1'000'000) return "hmd_timeout_ns: expected >= 1 ms";
  const double dt = static_cast<double>(drive_cycle_ticks) / clock_rate_hz;
  if (std::abs(dt - safety.dt) > 1e-12) return "safety.dt: must equal the drive cycle";
  return ValidateSafetyConfig(safety);
}

std::string SessionConfig::ToHeader() const {
  std::ostringstream s;
  s << "clock_rate_hz=" << clock_rate_hz << " drive_cycle_ticks=" << drive_cycle_ticks
    << " frame_ticks=" << frame_ticks << " ping_every_frames=" << ping_every_frames
    << " run_ticks=" << run_ticks << " max_stop_ticks=" << max_stop_ticks
    << " hmd_timeout_ns=" << hmd_timeout_ns << " hmd_required=" << (hmd_required ? 1 : 0)
    << " session_id=" << session_id;
  // Everything else the core's behaviour depends on, so a replay rebuilds the same core.
  s << " safety=" << F(safety.dt);
  for (const auto* set : {&safety.axes, &safety.soft_stop})
    for (const AxisLimits& a : *set)
      s << "," << F(a.workspace) << "," << F(a.hard_limit) << "," << F(a.velocity) << ","
        << F(a.accel) << "," << F(a.jerk);
  s << "," << safety.stale_setpoint_cycles << "," << F(safety.neutral[0]) << ","
    << F(safety.neutral[1]) << "," << F(safety.park_position_tolerance);
  s << " master=" << master.heartbeat_period_cycles << "," << master.heartbeat_timeout_cycles
    << "," << master.tpdo_timeout_cycles << "," << master.boot_timeout_cycles << ","
    << static_cast<int>(master.master_node);
  for (const AxisConfig& a : master.axes) s << "," << static_cast<int>(a.node) << "," << F(a.counts_per_unit);
  return s.str();
}

std::optional<SessionConfig> SessionConfig::FromHeader(const std::string& header,
                                                       std::string* error) {
  SessionConfig c;
  std::map<std::string, std::int64_t> kv;
  std::vector<double> safety_values;
  std::vector<double> master_values;
  for (const std::string& w : Split(header)) {
    const std::size_t eq = w.find('=');
    if (eq == std::string::npos) continue;
    if (w.compare(0, eq, "safety") == 0 || w.compare(0, eq, "master") == 0) {
      auto& values = w[0] == 's' ? safety_values : master_values;
      std::string item;
      std::istringstream list(w.substr(eq + 1));
      while (std::getline(list, item, ',')) {
        double v = 0.0;
        if (!ParseF64(item, &v) || !std::isfinite(v)) {
          *error = "bad header value: " + w;
          return std::nullopt;
        }
        values.push_back(v);
      }
      continue;
    }
    std::int64_t v = 0;
    if (!ParseI64(w.substr(eq + 1), &v)) {
      *error = "bad header value: " + w;
      return std::nullopt;
    }
    kv[w.substr(0, eq)] = v;
  }
  auto get = [&](const char* key, std::int64_t* v) {
    const auto it = kv.find(key);
    if (it == kv.end()) return false;
    *v = it->second;
    return true;
  };
  std::int64_t v = 0;
  const char* keys[] = {"clock_rate_hz", "drive_cycle_ticks", "frame_ticks", "ping_every_frames",
                        "run_ticks", "max_stop_ticks", "hmd_timeout_ns", "hmd_required",
                        "session_id"};
  for (const char* key : keys) {
    if (!get(key, &v)) {
      *error = std::string("log header lacks ") + key;
      return std::nullopt;
    }
  }
  get("clock_rate_hz", &v);
  c.clock_rate_hz = static_cast<int>(v);
  get("drive_cycle_ticks", &v);
  c.drive_cycle_ticks = static_cast<int>(v);
  get("frame_ticks", &v);
  c.frame_ticks = static_cast<int>(v);
  get("ping_every_frames", &v);
  c.ping_every_frames = static_cast<int>(v);
  get("run_ticks", &c.run_ticks);
  get("max_stop_ticks", &c.max_stop_ticks);
  get("hmd_timeout_ns", &c.hmd_timeout_ns);
  get("hmd_required", &v);
  c.hmd_required = v != 0;
  get("session_id", &v);
  c.session_id = static_cast<std::uint32_t>(v);
  c.safety.dt = static_cast<double>(c.drive_cycle_ticks) / c.clock_rate_hz;
  if (safety_values.size() != 25 || master_values.size() != 9) {
    *error = "log header lacks the safety= (25 values) or master= (9 values) configuration";
    return std::nullopt;
  }
  std::size_t k = 0;
  c.safety.dt = safety_values[k++];
  for (auto* set : {&c.safety.axes, &c.safety.soft_stop})
    for (AxisLimits& a : *set) {
      a.workspace = safety_values[k++];
      a.hard_limit = safety_values[k++];
      a.velocity = safety_values[k++];
      a.accel = safety_values[k++];
      a.jerk = safety_values[k++];
    }
  if (!(safety_values[k] >= 1 && safety_values[k] <= 1e6)) {
    *error = "safety= stale setpoint cycles must be in 1..10^6";
    return std::nullopt;
  }
  c.safety.stale_setpoint_cycles = static_cast<int>(safety_values[k++]);
  c.safety.neutral = {safety_values[k], safety_values[k + 1]};
  c.safety.park_position_tolerance = safety_values[k + 2];
  auto in_range = [](double x, double lo, double hi) { return x >= lo && x <= hi && x == std::floor(x); };
  for (std::size_t i = 0; i < 4; ++i)
    if (!in_range(master_values[i], 1, 1e6)) {
      *error = "master= timing values must be whole numbers in 1..10^6";
      return std::nullopt;
    }
  if (!in_range(master_values[4], 1, 127) || !in_range(master_values[5], 1, 127) ||
      !in_range(master_values[7], 1, 127) || !(master_values[6] > 0) || !(master_values[8] > 0)) {
    *error = "master= node ids must be 1..127 and counts per unit > 0";
    return std::nullopt;
  }
  c.master.heartbeat_period_cycles = static_cast<int>(master_values[0]);
  c.master.heartbeat_timeout_cycles = static_cast<int>(master_values[1]);
  c.master.tpdo_timeout_cycles = static_cast<int>(master_values[2]);
  c.master.boot_timeout_cycles = static_cast<int>(master_values[3]);
  c.master.master_node = static_cast<std::uint8_t>(master_values[4]);
  c.master.axes[0] = {static_cast<std::uint8_t>(master_values[5]), master_values[6]};
  c.master.axes[1] = {static_cast<std::uint8_t>(master_values[7]), master_values[8]};
  const std::string bad = c.Validate();
  if (!bad.empty()) {
    *error = bad;
    return std::nullopt;
  }
  return c;
}

Percentiles ComputePercentiles(std::vector<double> v) {
  Percentiles p;
  p.n = v.size();
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {
    const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size()))) - 1;
    return v[std::min(i, v.size() - 1)];
  };
  p.p50 = at(0.5);
  p.p99 = at(0.99);
  p.max = v.back();
  double sum = 0.0;
  for (double x : v) sum += x;
  p.mean = sum / static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - p.mean) * (x - p.mean);
  p.stddev = std::sqrt(ss / static_cast<double>(v.size()));
  return p;
}

// --- core -----------------------------------------------------------------------------------
SessionCore::SessionCore(SessionConfig config)
    : config_(config), supervisor_(config.safety), master_(config.master),
      hmd_filter_(config.hmd_timeout_ns) {
  measured_.reserve(8192);
}

void SessionCore::SendHmd(HmdBody body, std::int64_t now_ns, SessionOutputs* out) {
  HmdMessage m;
  m.header.seq = hmd_seq_++;
  m.header.session = config_.session_id;
  m.header.t_send_ns = now_ns;
  m.header.type = static_cast<HmdType>(body.index() + 1);
  m.body = std::move(body);
  std::vector<std::uint8_t> bytes(kHmdMaxSize);
  bytes.resize(EncodeHmd(m, bytes));
  out->hmd.push_back(std::move(bytes));
}

std::array<double, 2> SessionCore::MeasuredAt(std::int64_t ns) const {
  if (measured_.empty()) return {0.0, 0.0};
  if (ns <= measured_.front().ns) return measured_.front().q;
  if (ns >= measured_.back().ns) return measured_.back().q;
  const auto it = std::lower_bound(measured_.begin(), measured_.end(), ns,
                                   [](const Measured& m, std::int64_t t) { return m.ns < t; });
  const Measured& b = *it;
  const Measured& a = *(it - 1);
  const double w = b.ns == a.ns ? 1.0 : static_cast<double>(ns - a.ns) / static_cast<double>(b.ns - a.ns);
  return {a.q[0] + w * (b.q[0] - a.q[0]), a.q[1] + w * (b.q[1] - a.q[1])};
}

void SessionCore::HandleHmd(std::int64_t tick, const RxDatagram& d, SessionOutputs* out) {
  HmdMessage m;
  if (DecodeHmd(d.bytes, &m) != CodecError::kOk) {
    hmd_filter_.CountMalformed();
    return;
  }
  if (!hmd_filter_.Accept(m, d.rx_ns, offset_)) return;
  if (const auto* pong = std::get_if<PongMsg>(&m.body)) {
    offset_.AddSample(pong->t0, pong->t1, pong->t2, d.rx_ns);
  } else if (const auto* head = std::get_if<HeadPoseMsg>(&m.body)) {
    hmd_seen_ = true;
    last_head_rx_ns_ = d.rx_ns;
    const std::int64_t t_local = SaturatingSub(head->t_sample_ns, offset_.offset_ns());
    const auto q = MeasuredAt(t_local);
    const Pose comp = CompensateHeadPose(head->head, q[0], q[1]);
    out->log.push_back("P " + std::to_string(tick) + " " + std::to_string(t_local) +
                       PoseText(head->head) + PoseText(comp));
    if (head->last_frame >= 0 &&
        static_cast<std::size_t>(head->last_frame) < frame_shown_ns_.size() &&
        frame_shown_ns_[static_cast<std::size_t>(head->last_frame)] < 0) {
      frame_shown_ns_[static_cast<std::size_t>(head->last_frame)] =
          SaturatingSub(head->t_frame_rx_ns, offset_.offset_ns());
    }
  } else if (std::holds_alternative<ByeMsg>(m.body)) {
    hmd_bye_ = true;
    out->log.push_back("E " + std::to_string(tick) + " hmd said bye");
  }
}

void SessionCore::Step(std::int64_t tick, const SessionInputs& in, SessionOutputs* out) {
  const std::int64_t ns_per_tick = 1'000'000'000LL / config_.clock_rate_hz;
  ++steps_;
  last_tick_ = tick;
  lateness_us_.push_back(static_cast<double>(SaturatingSub(in.now_ns, in.scheduled_ns)) / 1000.0);
  if (in.stop_request && !stop_request_) {
    stop_request_ = true;
    out->log.push_back("E " + std::to_string(tick) + " stop requested");
  }

  for (const RxDatagram& d : in.hmd) HandleHmd(tick, d, out);
  const std::uint8_t rail_node = config_.master.axes[1].node;
  for (const RxFrame& r : in.can) {
    const CanFrame& f = r.frame;
    if (f.error()) {
      if ((f.id & kCanErrBusOff) != 0 && !bus_off_) {
        bus_off_ = true;
        out->log.push_back("E " + std::to_string(tick) + " bus-off error frame");
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
      if (measured_.size() >= 8192) measured_.erase(measured_.begin(), measured_.begin() + 4096);
      measured_.push_back({in.now_ns, measured});
      for (std::size_t i = 0; i < 2; ++i)
        report_.peak_abs_measured[i] = std::max(report_.peak_abs_measured[i], std::abs(measured[i]));
    }
    const bool hmd_ok = !config_.hmd_required ||
                        (hmd_seen_ && !hmd_bye_ &&
                         SaturatingSub(in.now_ns, last_head_rx_ns_) <= config_.hmd_timeout_ns);
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
      out->log.push_back("E " + std::to_string(tick) + " supervisor " + SupervisorStateName(state) +
                         (supervisor_.reason().empty() ? "" : " (" + supervisor_.reason() + ")"));
      if ((state == SupervisorState::kSoftStop || state == SupervisorState::kFault) &&
          report_.stop_tick < 0) {
        report_.stop_tick = tick;
        report_.stop_reason = supervisor_.reason();
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
        out->log.push_back("E " + std::to_string(tick) + " finishing" +
                           (timed_out ? " (timed out waiting for park)" : ""));
      }
      if (++disable_ticks_ > 10) done_ = true;
    }

    master_.Cycle(cycle, cmd, &out->can);
    if (master_.phase() != last_phase_) {
      last_phase_ = master_.phase();
      out->log.push_back("E " + std::to_string(tick) + " master " + MasterPhaseName(last_phase_));
    }
    const auto idx = static_cast<std::size_t>(cycle);
    if (platform_rx_ns_.size() <= idx) platform_rx_ns_.resize(idx + 1, -1);
    sync_sent_tick_.push_back(tick);
    const std::array<double, 2> sp = in.setpoint.value_or(std::array<double, 2>{NAN, NAN});
    out->log.push_back("S " + std::to_string(tick) + " " + std::to_string(cycle) + " " + F(sp[0]) +
                       " " + F(sp[1]) + " " + F(cmd[0]) + " " + F(cmd[1]) + " " + F(measured[0]) +
                       " " + F(measured[1]) + " " + SupervisorStateName(state) + " " +
                       MasterPhaseName(master_.phase()));
  }

  if (is_frame_tick(tick) && in.camera && !done_) {
    const std::int64_t frame = tick / config_.frame_ticks;
    const auto idx = static_cast<std::size_t>(frame);
    if (frame_shown_ns_.size() <= idx) frame_shown_ns_.resize(idx + 1, -1);
    const auto& m = supervisor_.motion();
    SendHmd(CameraPoseMsg{tick, frame, *in.camera, {m[0].p, m[1].p}}, in.now_ns, out);
    if (frame % config_.ping_every_frames == 0) SendHmd(PingMsg{in.now_ns}, in.now_ns, out);
  }

  for (const CanFrame& f : out->can) out->log.push_back("c " + FormatFrameText(f));
  for (const auto& b : out->hmd) out->log.push_back("h " + HexEncode(b));
}

SessionReport SessionCore::Report() const {
  SessionReport r = report_;
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

std::string SessionReport::ToJson() const {
  auto pct = [](const Percentiles& p) {
    return "{\"n\": " + std::to_string(p.n) + ", \"p50\": " + F(p.p50) + ", \"p99\": " + F(p.p99) +
           ", \"max\": " + F(p.max) + ", \"mean\": " + F(p.mean) + ", \"stddev\": " + F(p.stddev) + "}";
  };
  auto arr = [](const std::array<double, 2>& a) { return "[" + F(a[0]) + ", " + F(a[1]) + "]"; };
  std::ostringstream s;
  s << "{\n  \"format\": \"pwsim-session-report/1\",\n"
    << "  \"ticks\": " << ticks << ",\n  \"steps\": " << steps << ",\n"
    << "  \"cycle_lateness_us\": " << pct(cycle_lateness_us) << ",\n"
    << "  \"cycle_period_jitter_us\": " << pct(cycle_period_jitter_us) << ",\n"
    << "  \"visual_platform_skew_ms\": " << pct(skew_ms) << ",\n"
    << "  \"abs_visual_platform_skew_ms\": " << pct(abs_skew_ms) << ",\n"
    << "  \"clock_offset_ns\": " << clock_offset_ns << ",\n  \"clock_rtt_ns\": " << clock_rtt_ns << ",\n"
    << "  \"hmd_rx\": {\"accepted\": " << hmd_rx.accepted << ", \"out_of_order\": " << hmd_rx.out_of_order
    << ", \"stale\": " << hmd_rx.stale << ", \"malformed\": " << hmd_rx.malformed << "},\n"
    << "  \"safety\": {\"nonfinite\": " << safety.nonfinite << ", \"clamped\": " << safety.clamped
    << ", \"rate_limited\": " << safety.rate_limited << ", \"braking\": " << safety.braking
    << ", \"missing\": " << safety.missing << "},\n"
    << "  \"final_state\": \"" << final_state << "\",\n  \"stop_reason\": \"" << stop_reason << "\",\n"
    << "  \"stop_tick\": " << stop_tick << ",\n  \"parked_tick\": " << parked_tick << ",\n"
    << "  \"peak_abs_command\": " << arr(peak_abs_command) << ",\n"
    << "  \"peak_abs_command_velocity\": " << arr(peak_abs_command_velocity) << ",\n"
    << "  \"peak_abs_command_accel\": " << arr(peak_abs_command_accel) << ",\n"
    << "  \"peak_abs_measured\": " << arr(peak_abs_measured) << ",\n"
    << "  \"limits_ok\": " << (limits_ok ? "true" : "false") << "\n}\n";
  return s.str();
}

// --- log ------------------------------------------------------------------------------------
std::string HexEncode(std::span<const std::uint8_t> bytes) {
  static const char* kHex = "0123456789abcdef";
  std::string s;
  s.reserve(bytes.size() * 2);
  for (std::uint8_t b : bytes) {
    s.push_back(kHex[b >> 4]);
    s.push_back(kHex[b & 0xF]);
  }
  return s;
}

bool HexDecode(std::string_view hex, std::vector<std::uint8_t>* bytes) {
  if (hex.size() % 2 != 0) return false;
  bytes->clear();
  auto val = [](char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  for (std::size_t i = 0; i < hex.size(); i += 2) {
    const int hi = val(hex[i]);
    const int lo = val(hex[i + 1]);
    if (hi < 0 || lo < 0) return false;
    bytes->push_back(static_cast<std::uint8_t>(hi * 16 + lo));
  }
  return true;
}

void AppendInputLines(std::int64_t tick, const SessionInputs& in, std::vector<std::string>* lines) {
  lines->push_back("T " + std::to_string(tick) + " " + std::to_string(in.now_ns) + " " +
                   std::to_string(in.scheduled_ns));
  if (in.setpoint)
    lines->push_back("M " + std::to_string(tick) + " " + F((*in.setpoint)[0]) + " " + F((*in.setpoint)[1]));
  if (in.camera) lines->push_back("K " + std::to_string(tick) + PoseText(*in.camera));
  if (in.stop_request) lines->push_back("X " + std::to_string(tick));
  for (const RxFrame& r : in.can)
    lines->push_back("C " + std::to_string(r.rx_ns) + " " + FormatFrameText(r.frame));
  for (const RxDatagram& d : in.hmd)
    lines->push_back("H " + std::to_string(d.rx_ns) + " " + HexEncode(d.bytes));
}

ReplayResult ReplaySessionLog(std::istream& log) {
  ReplayResult result;
  std::string line;
  std::int64_t number = 0;
  std::optional<SessionCore> core;
  SessionInputs in;
  std::int64_t tick = -1;
  std::vector<std::string> expected;
  std::vector<std::int64_t> expected_line;
  SessionOutputs out;
  auto fail = [&](std::int64_t at, const std::string& why) {
    result.ok = false;
    result.message = "line " + std::to_string(at) + ": " + why;
    return result;
  };
  auto flush = [&]() -> bool {
    if (tick < 0) return true;
    out.Clear();
    core->Step(tick, in, &out);
    ++result.steps;
    const std::size_t n = std::min(out.log.size(), expected.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (out.log[i] != expected[i]) {
        result.message = "line " + std::to_string(expected_line[i]) + ": replay gives '" +
                         out.log[i] + "', log has '" + expected[i] + "'";
        return false;
      }
      ++result.lines_compared;
    }
    if (out.log.size() != expected.size()) {
      result.message = "tick " + std::to_string(tick) + ": replay gives " +
                       std::to_string(out.log.size()) + " output lines, log has " +
                       std::to_string(expected.size());
      return false;
    }
    in = SessionInputs{};
    expected.clear();
    expected_line.clear();
    return true;
  };
  while (std::getline(log, line)) {
    ++number;
    if (line.empty()) continue;
    if (line[0] == '#') {
      if (!core && line.rfind("# pwsim-session-log/1", 0) == 0) {
        std::string error;
        auto config = SessionConfig::FromHeader(line, &error);
        if (!config) return fail(number, error);
        core.emplace(*config);
      }
      continue;
    }
    if (!core) return fail(number, "no '# pwsim-session-log/1' header before the first record");
    const auto parts = Split(line);
    const char kind = line[0];
    if (line.size() < 2 || line[1] != ' ') return fail(number, "expected '<kind> ...'");
    switch (kind) {
      case 'T': {
        if (!flush()) {
          result.ok = false;
          return result;
        }
        std::int64_t t = 0;
        if (parts.size() != 4 || !ParseI64(parts[1], &t) || !ParseI64(parts[2], &in.now_ns) ||
            !ParseI64(parts[3], &in.scheduled_ns))
          return fail(number, "bad T record");
        // Ticks increase, by at most 10^6 at a time (the runner steps every drive cycle).
        if (t <= tick || t > tick + 1'000'000) return fail(number, "tick out of sequence");
        tick = t;
        break;
      }
      case 'M': {
        std::array<double, 2> sp{};
        if (parts.size() != 4 || !ParseF64(parts[2], &sp[0]) || !ParseF64(parts[3], &sp[1]))
          return fail(number, "bad M record");
        in.setpoint = sp;
        break;
      }
      case 'K': {
        Pose p;
        if (parts.size() != 9) return fail(number, "bad K record");
        for (std::size_t i = 0; i < 3; ++i)
          if (!ParseF64(parts[2 + i], &p.p[i])) return fail(number, "bad K record");
        for (std::size_t i = 0; i < 4; ++i)
          if (!ParseF64(parts[5 + i], &p.q[i])) return fail(number, "bad K record");
        in.camera = p;
        break;
      }
      case 'X': in.stop_request = true; break;
      case 'C': {
        RxFrame r;
        if (parts.size() != 3 || !ParseI64(parts[1], &r.rx_ns) ||
            ParseFrameText(parts[2], &r.frame) != CodecError::kOk)
          return fail(number, "bad C record");
        in.can.push_back(r);
        break;
      }
      case 'H': {
        RxDatagram d;
        if (parts.size() != 3 || !ParseI64(parts[1], &d.rx_ns) || !HexDecode(parts[2], &d.bytes))
          return fail(number, "bad H record");
        in.hmd.push_back(std::move(d));
        break;
      }
      case 'c': case 'h': case 'S': case 'P': case 'E':
        expected.push_back(line);
        expected_line.push_back(number);
        break;
      default:
        return fail(number, std::string("unknown record kind '") + kind + "'");
    }
  }
  if (!core) return fail(number, "empty log");
  if (!flush()) {
    result.ok = false;
    return result;
  }
  result.ok = true;
  result.report = core->Report();
  result.message = "replayed " + std::to_string(result.steps) + " steps, " +
                   std::to_string(result.lines_compared) + " output lines identical";
  return result;
}

}  // namespace pwsim::hw
