#include "hardware/session_config.h"

#include <cmath>
#include <map>
#include <sstream>

#include "engine/number_format.h"
#include "hardware/session_text.h"

namespace pwsim::hw {
namespace {

std::string F(double v) { return FormatDouble(v); }

}  // namespace

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
  for (const std::string& w : SplitWords(header)) {
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

}  // namespace pwsim::hw
