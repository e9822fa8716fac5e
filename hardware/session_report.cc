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
    << "  \"schedule_slips\": " << schedule_slips << ",\n"
    << "  \"schedule_slip_ms\": " << F(schedule_slip_ms) << ",\n"
    << "  \"refused_datagrams\": {\"can\": " << can_rx_refused << ", \"hmd\": " << hmd_rx_refused << "},\n";
  if (has_live_input) {
    s << "  \"joystick_to_platform_command_ms\": " << pct(input_to_platform_ms) << ",\n"
      << "  \"joystick_to_hmd_frame_ms\": " << pct(input_to_hmd_ms) << ",\n";
  }
  s
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

}  // namespace pwsim::hw
