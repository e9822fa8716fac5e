#include "hardware/session_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/number_format.h"

namespace pwsim::hw {
namespace {

std::string F(double v) { return FormatDouble(v); }

}  // namespace

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

int SessionReport::ExitStatus() const {
  if (final_state == "feedback-lost" || final_state == "quick-stop") return 5;
  if (final_state == "fault") return 4;
  if (final_state != "parked" || !limits_ok || !within_limits) return 3;
  return drive_events.total() > 0 ? 6 : 0;
}

std::string SessionReport::ToJson() const {
  auto pct = [](const Percentiles& p) {
    return "{\"n\": " + std::to_string(p.n) + ", \"p50\": " + F(p.p50) + ", \"p99\": " + F(p.p99) +
           ", \"max\": " + F(p.max) + ", \"mean\": " + F(p.mean) + ", \"stddev\": " + F(p.stddev) + "}";
  };
  std::ostringstream s;
  s << "{\n  \"format\": \"pwsim-session-report/2\",\n"
    << "  \"ticks\": " << ticks << ",\n  \"steps\": " << steps << ",\n"
    << "  \"cycle_lateness_us\": " << pct(cycle_lateness_us) << ",\n"
    << "  \"cycle_period_jitter_us\": " << pct(cycle_period_jitter_us) << ",\n"
    << "  \"schedule_slips\": " << schedule_slips << ",\n"
    << "  \"schedule_slip_ms\": " << F(schedule_slip_ms) << ",\n"
    << "  \"refused_datagrams\": {\"can\": " << can_rx_refused << ", \"hmd\": " << hmd_rx_refused << "},\n";
  if (has_live_input) {
    s << "  \"joystick_to_platform_command_ms\": " << pct(input_to_platform_ms) << ",\n"
      << "  \"joystick_to_hmd_frame_ms\": " << pct(input_to_hmd_ms) << ",\n";
  }
  s << "  \"visual_platform_skew_ms\": " << pct(skew_ms) << ",\n"
    << "  \"abs_visual_platform_skew_ms\": " << pct(abs_skew_ms) << ",\n"
    << "  \"clock_offset_ns\": " << clock_offset_ns << ",\n  \"clock_rtt_ns\": " << clock_rtt_ns << ",\n"
    << "  \"hmd_rx\": {\"accepted\": " << hmd_rx.accepted << ", \"out_of_order\": " << hmd_rx.out_of_order
    << ", \"stale\": " << hmd_rx.stale << ", \"malformed\": " << hmd_rx.malformed << "},\n"
    << "  \"safety\": {\"nonfinite\": " << safety.nonfinite << ", \"clamped\": " << safety.clamped
    << ", \"rate_limited\": " << safety.rate_limited << ", \"braking\": " << safety.braking
    << ", \"missing\": " << safety.missing << ", \"held\": " << safety.held << "},\n"
    << "  \"platform\": \"" << platform << "\",\n"
    << "  \"final_state\": \"" << final_state << "\",\n"
    << "  \"exit_status\": " << ExitStatus() << ",\n"
    << "  \"supervisor_state\": \"" << supervisor_state << "\",\n"
    << "  \"stop_reason\": \"" << stop_reason << "\",\n"
    << "  \"stop_tick\": " << stop_tick << ",\n  \"parked_tick\": " << parked_tick << ",\n"
    << "  \"drive_events\": {\"feedback_lost\": " << drive_events.feedback_lost
    << ", \"heartbeat_lost\": " << drive_events.heartbeat_lost << ", \"restarts\": " << drive_events.restarts
    << ", \"returns\": " << drive_events.returns << ", \"readmissions\": " << drive_events.readmissions
    << ", \"quick_stops\": " << drive_events.quick_stops << ", \"faults\": " << drive_events.faults << "},\n"
    << "  \"drives\": [";
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const AxisReport& a = axes[i];
    s << (i == 0 ? "\n" : ",\n") << "    {\"node\": " << a.node << ", \"actuator\": \"" << a.actuator
      << "\", \"unit\": \"" << a.unit << "\", \"stroke\": [" << F(a.stroke_min) << ", " << F(a.stroke_max)
      << "], \"speed\": " << F(a.speed) << ",\n     \"command\": {\"min\": " << F(a.command_min)
      << ", \"max\": " << F(a.command_max) << ", \"peak_velocity\": " << F(a.peak_command_velocity)
      << ", \"peak_accel\": " << F(a.peak_command_accel) << "},\n     \"measured\": {\"min\": "
      << F(a.measured_min) << ", \"max\": " << F(a.measured_max) << ", \"peak_velocity\": "
      << F(a.peak_measured_velocity) << "},\n     \"last\": {\"state\": \"" << a.state << "\", \"nmt\": \""
      << a.nmt << "\", \"statusword\": " << a.statusword << ", \"position\": " << F(a.position)
      << ", \"velocity\": " << F(a.velocity) << ", \"feedback_age_ms\": " << F(a.feedback_age_ms)
      << ", \"last_emcy_code\": " << a.last_emcy_code << ", \"restarts\": " << a.restarts
      << ", \"returns\": " << a.returns << ", \"readmissions\": " << a.readmissions << "}}";
  }
  s << "\n  ],\n  \"peak_abs_measured_pose\": {";
  const char* dofs[6] = {"surge", "sway", "heave", "roll", "pitch", "yaw"};
  for (std::size_t k = 0; k < 6; ++k)
    s << (k == 0 ? "" : ", ") << "\"" << dofs[k] << "\": " << F(peak_abs_measured_pose[k]);
  s << "},\n  \"fk_residual_max\": " << F(fk_residual_max) << ",\n"
    << "  \"fk_residual_tracking_max\": " << F(fk_residual_tracking_max) << ",\n"
    << "  \"ik_failures\": " << ik_failures << ",\n"
    << "  \"limits_ok\": " << (limits_ok ? "true" : "false") << ",\n"
    << "  \"within_limits\": " << (within_limits ? "true" : "false") << ",\n"
    << "  \"within_limits_tolerance\": {\"position\": 0, \"velocity_fraction\": " << F(velocity_tolerance)
    << "}\n}\n";
  return s.str();
}

}  // namespace pwsim::hw
