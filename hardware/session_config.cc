#include "hardware/session_config.h"

#include <cmath>
#include <map>
#include <sstream>
#include <vector>

#include "engine/number_format.h"
#include "hardware/session_text.h"
#include "mca/platform.h"

namespace pwsim::hw {
namespace {

std::string F(double v) { return FormatDouble(v); }

/// "a,b,c" -> numbers (each finite); false on any bad item.
bool ParseList(const std::string& text, std::vector<double>* values) {
  std::string item;
  std::istringstream list(text);
  while (std::getline(list, item, ',')) {
    double v = 0.0;
    if (!ParseF64(item, &v) || !std::isfinite(v)) return false;
    values->push_back(v);
  }
  return true;
}

bool WholeIn(double x, double lo, double hi) { return x >= lo && x <= hi && x == std::floor(x); }

/// A name as one header word item: no separators.
std::string HeaderName(const std::string& name) {
  std::string out = name.empty() ? "-" : name;
  for (char& ch : out)
    if (ch == ',' || ch == '=' || ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r') ch = '_';
  return out;
}

constexpr double kUnlimitedRotaryRange = 30.0 * mca::kDegToRad;  ///< the session's range of a free stage
constexpr double kUnlimitedRotaryMargin = 1.0 * mca::kDegToRad;

}  // namespace

static_assert(kMaxDriveAxes == mca::kMaxActuators, "one drive axis per actuator");

SafetyConfig SafetyConfigFor(const mca::Mechanism& mechanism, double dt) {
  SafetyConfig c;
  c.dt = dt;
  c.axis_count = mechanism.actuator_count();
  const mca::ActuatorVector neutral = mechanism.Neutral();
  for (int i = 0; i < mechanism.actuator_count(); ++i) {
    const mca::Actuator& a = mechanism.actuator(i);
    const auto k = static_cast<std::size_t>(i);
    const double q0 = i < neutral.size() ? neutral(i) : 0.0;
    AxisLimits& l = c.axes[k];
    if (std::isfinite(a.limits.min) && std::isfinite(a.limits.max)) {
      const double margin = (a.limits.max - a.limits.min) / 24.0;
      l.hard_min = a.limits.min;
      l.hard_max = a.limits.max;
      l.min = a.limits.min + margin;
      l.max = a.limits.max - margin;
    } else {
      l.hard_min = q0 - kUnlimitedRotaryRange;
      l.hard_max = q0 + kUnlimitedRotaryRange;
      l.min = l.hard_min + kUnlimitedRotaryMargin;
      l.max = l.hard_max - kUnlimitedRotaryMargin;
    }
    l.velocity = a.limits.speed;
    l.accel = a.limits.accel;
    l.jerk = 2.0 * a.limits.accel / dt;  // the acceleration may swing across its range in a cycle
    AxisLimits& s = c.soft_stop[k];
    s = l;
    s.velocity = 0.25 * l.velocity;
    s.accel = 0.1 * l.accel;
    s.jerk = a.limits.accel * 1.0;  // [1/s]: the soft stop's acceleration swings in 0.1 s
    c.neutral[k] = q0;
  }
  return c;
}

MasterConfig MasterConfigFor(const mca::Mechanism& mechanism) {
  MasterConfig m;
  m.axis_count = mechanism.actuator_count();
  for (std::size_t k = 0; k < m.axes.size(); ++k) m.axes[k] = {static_cast<std::uint8_t>(k + 1), 1e6};
  return m;
}

mca::Mechanism SessionConfig::DefaultMechanism() { return mca::MakeCar2DofPlatform().mechanism; }

void SessionConfig::SetPlatform(const std::string& name, const mca::Mechanism& m) {
  platform = name;
  mechanism = m;
  safety = SafetyConfigFor(mechanism, static_cast<double>(drive_cycle_ticks) / clock_rate_hz);
  MasterConfig drives = MasterConfigFor(mechanism);
  drives.master_node = master.master_node;
  drives.heartbeat_period_cycles = master.heartbeat_period_cycles;
  drives.heartbeat_timeout_cycles = master.heartbeat_timeout_cycles;
  drives.tpdo_timeout_cycles = master.tpdo_timeout_cycles;
  drives.boot_timeout_cycles = master.boot_timeout_cycles;
  master = drives;
}

std::string SessionConfig::Validate() const {
  if (clock_rate_hz < 100 || clock_rate_hz > 100000) return "clock_rate_hz: expected 100..100000";
  if (drive_cycle_ticks < 1) return "drive_cycle_ticks: expected >= 1";
  if (frame_ticks < 1) return "frame_ticks: expected >= 1";
  if (ping_every_frames < 1) return "ping_every_frames: expected >= 1";
  if (run_ticks < 0 || max_stop_ticks < 1) return "run_ticks/max_stop_ticks: expected >= 0 / >= 1";
  if (drive_return_ticks < 1) return "drive_return_ticks: expected >= 1";
  if (hmd_timeout_ns < 1'000'000) return "hmd_timeout_ns: expected >= 1 ms";
  const double dt = static_cast<double>(drive_cycle_ticks) / clock_rate_hz;
  if (std::abs(dt - safety.dt) > 1e-12) return "safety.dt: must equal the drive cycle";
  if (const std::string bad = mechanism.Validate(); !bad.empty()) return "mechanism: " + bad;
  if (mechanism.actuator_count() != master.axis_count)
    return "master.axis_count: must equal the mechanism's actuator count (" +
           std::to_string(mechanism.actuator_count()) + ")";
  if (!(park_measured_tolerance > 0.0 && rest_velocity_tolerance > 0.0 && velocity_tolerance >= 0.0))
    return "park_measured_tolerance, rest_velocity_tolerance: expected > 0, velocity_tolerance >= 0";
  if (master.axis_count < 1 || master.axis_count > kMaxDriveAxes)
    return "master.axis_count: expected 1.." + std::to_string(kMaxDriveAxes);
  if (safety.axis_count != master.axis_count) return "safety.axis_count: must equal master.axis_count";
  for (int i = 0; i < master.axis_count; ++i) {
    const AxisConfig& a = master.axes[static_cast<std::size_t>(i)];
    if (a.node < 1 || a.node > 127 || !(a.counts_per_unit > 0.0))
      return "master axis " + std::to_string(i + 1) + ": node id 1..127 and counts per unit > 0 expected";
    for (int j = 0; j < i; ++j)
      if (master.axes[static_cast<std::size_t>(j)].node == a.node)
        return "master axis " + std::to_string(i + 1) + ": node id " + std::to_string(a.node) + " used twice";
  }
  if (master.heartbeat_period_cycles < 1 || master.heartbeat_timeout_cycles < 1 || master.tpdo_timeout_cycles < 1 ||
      master.boot_timeout_cycles < 1)
    return "master: timing values must be >= 1";
  return ValidateSafetyConfig(safety);
}

std::string SessionConfig::ToHeader() const {
  std::ostringstream s;
  s << "clock_rate_hz=" << clock_rate_hz << " drive_cycle_ticks=" << drive_cycle_ticks
    << " frame_ticks=" << frame_ticks << " ping_every_frames=" << ping_every_frames
    << " run_ticks=" << run_ticks << " max_stop_ticks=" << max_stop_ticks
    << " drive_return_ticks=" << drive_return_ticks
    << " hmd_timeout_ns=" << hmd_timeout_ns << " hmd_required=" << (hmd_required ? 1 : 0)
    << " session_id=" << session_id;
  // Everything else the core's behaviour depends on, so a replay rebuilds the same core.
  s << " axes=" << master.axis_count;
  s << " tolerances=" << F(park_measured_tolerance) << "," << F(rest_velocity_tolerance) << ","
    << F(velocity_tolerance);
  s << " safety=" << F(safety.dt) << "," << safety.stale_setpoint_cycles << "," << F(safety.park_position_tolerance);
  s << " master=" << master.heartbeat_period_cycles << "," << master.heartbeat_timeout_cycles << ","
    << master.tpdo_timeout_cycles << "," << master.boot_timeout_cycles << "," << static_cast<int>(master.master_node);
  for (std::size_t i = 0; i < static_cast<std::size_t>(master.axis_count); ++i) {
    const AxisLimits& a = safety.axes[i];
    const AxisLimits& b = safety.soft_stop[i];
    s << " axis" << (i + 1) << "=" << static_cast<int>(master.axes[i].node) << "," << F(master.axes[i].counts_per_unit)
      << "," << F(a.min) << "," << F(a.max) << "," << F(a.hard_min) << "," << F(a.hard_max) << "," << F(a.velocity)
      << "," << F(a.accel) << "," << F(a.jerk) << "," << F(b.velocity) << "," << F(b.accel) << "," << F(b.jerk)
      << "," << F(safety.neutral[i]);
  }
  // The mechanism: pivot height, the legs' axes (bit k = pose axis k), one actuator= per actuator
  // (name, kind, pose axis, base anchor, plate anchor, stroke, speed, accel, force).
  s << " platform=" << HeaderName(platform) << " mechanism=" << F(mechanism.pivot_height()) << ",";
  int legs = 0;
  for (int k = 0; k < mca::kDofCount; ++k)
    if (mechanism.leg_axes()[static_cast<std::size_t>(k)]) legs |= 1 << k;
  s << legs;
  for (int i = 0; i < mechanism.actuator_count(); ++i) {
    const mca::Actuator& a = mechanism.actuator(i);
    s << " actuator" << (i + 1) << "=" << HeaderName(a.name) << "," << static_cast<int>(a.kind) << ","
      << mca::Index(a.dof);
    for (const Eigen::Vector3d* v : {&a.base_anchor, &a.plate_anchor})
      for (int k = 0; k < 3; ++k) s << "," << F((*v)(k));
    s << "," << F(a.limits.min) << "," << F(a.limits.max) << "," << F(a.limits.speed) << "," << F(a.limits.accel)
      << "," << F(a.limits.force);
  }
  return s.str();
}

std::optional<SessionConfig> SessionConfig::FromHeader(const std::string& header, std::string* error) {
  SessionConfig c;
  std::map<std::string, std::int64_t> kv;
  std::map<std::string, std::vector<double>> lists;
  std::map<std::string, std::string> words;
  for (const std::string& w : SplitWords(header)) {
    const std::size_t eq = w.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = w.substr(0, eq);
    if (key == "platform" || key.rfind("actuator", 0) == 0) {
      words[key] = w.substr(eq + 1);
      continue;
    }
    if (key == "safety" || key == "master" || key == "tolerances" || key == "mechanism" ||
        key.rfind("axis", 0) == 0) {
      std::vector<double>& values = lists[key];
      values.clear();
      if (!ParseList(w.substr(eq + 1), &values)) {
        *error = "bad header value: " + w;
        return std::nullopt;
      }
      continue;
    }
    std::int64_t v = 0;
    if (!ParseI64(w.substr(eq + 1), &v)) {
      *error = "bad header value: " + w;
      return std::nullopt;
    }
    kv[key] = v;
  }
  auto get = [&](const char* key, std::int64_t* v) {
    const auto it = kv.find(key);
    if (it == kv.end()) return false;
    *v = it->second;
    return true;
  };
  std::int64_t v = 0;
  const char* keys[] = {"clock_rate_hz", "drive_cycle_ticks", "frame_ticks", "ping_every_frames", "run_ticks",
                        "max_stop_ticks", "drive_return_ticks", "hmd_timeout_ns", "hmd_required", "session_id",
                        "axes"};
  for (const char* key : keys) {
    if (!get(key, &v)) {
      *error = std::string("log header lacks ") + key;
      return std::nullopt;
    }
  }
  auto small = [](std::int64_t x) { return x >= -1'000'000'000 && x <= 1'000'000'000; };
  for (const char* key : {"clock_rate_hz", "drive_cycle_ticks", "frame_ticks", "ping_every_frames"}) {
    get(key, &v);
    if (!small(v)) {
      *error = std::string("log header: ") + key + " out of range";
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
  get("drive_return_ticks", &c.drive_return_ticks);
  get("hmd_timeout_ns", &c.hmd_timeout_ns);
  get("hmd_required", &v);
  c.hmd_required = v != 0;
  get("session_id", &v);
  c.session_id = static_cast<std::uint32_t>(v);
  std::int64_t axes = 0;
  get("axes", &axes);
  if (axes < 1 || axes > kMaxDriveAxes) {
    *error = "log header: axes must be 1.." + std::to_string(kMaxDriveAxes);
    return std::nullopt;
  }
  const std::vector<double>& safety = lists["safety"];
  const std::vector<double>& master = lists["master"];
  if (safety.size() != 3 || master.size() != 5) {
    *error = "log header lacks the safety= (3 values) or master= (5 values) configuration";
    return std::nullopt;
  }
  c.safety.dt = safety[0];
  if (!WholeIn(safety[1], 1, 1e6)) {
    *error = "safety= stale setpoint cycles must be in 1..10^6";
    return std::nullopt;
  }
  c.safety.stale_setpoint_cycles = static_cast<int>(safety[1]);
  c.safety.park_position_tolerance = safety[2];
  for (std::size_t i = 0; i < 4; ++i)
    if (!WholeIn(master[i], 1, 1e6)) {
      *error = "master= timing values must be whole numbers in 1..10^6";
      return std::nullopt;
    }
  if (!WholeIn(master[4], 1, 127)) {
    *error = "master= the master's node id must be 1..127";
    return std::nullopt;
  }
  c.master.heartbeat_period_cycles = static_cast<int>(master[0]);
  c.master.heartbeat_timeout_cycles = static_cast<int>(master[1]);
  c.master.tpdo_timeout_cycles = static_cast<int>(master[2]);
  c.master.boot_timeout_cycles = static_cast<int>(master[3]);
  c.master.master_node = static_cast<std::uint8_t>(master[4]);
  c.master.axis_count = static_cast<int>(axes);
  c.safety.axis_count = static_cast<int>(axes);
  for (std::size_t i = 0; i < static_cast<std::size_t>(axes); ++i) {
    const std::string key = "axis" + std::to_string(i + 1);
    const std::vector<double>& a = lists[key];
    if (a.size() != 13) {
      *error = "log header lacks " + key + "= (13 values: node, counts per unit, min, max, hard min, hard max, "
               "velocity, accel, jerk, soft-stop velocity, accel, jerk, neutral)";
      return std::nullopt;
    }
    if (!WholeIn(a[0], 1, 127)) {
      *error = key + "= node id must be 1..127";
      return std::nullopt;
    }
    c.master.axes[i] = {static_cast<std::uint8_t>(a[0]), a[1]};
    AxisLimits& l = c.safety.axes[i];
    l = {a[2], a[3], a[4], a[5], a[6], a[7], a[8]};
    AxisLimits& s = c.safety.soft_stop[i];
    s = l;
    s.velocity = a[9];
    s.accel = a[10];
    s.jerk = a[11];
    c.safety.neutral[i] = a[12];
  }
  const std::vector<double>& tolerances = lists["tolerances"];
  if (tolerances.size() != 3) {
    *error = "log header lacks tolerances= (3 values)";
    return std::nullopt;
  }
  c.park_measured_tolerance = tolerances[0];
  c.rest_velocity_tolerance = tolerances[1];
  c.velocity_tolerance = tolerances[2];
  // The mechanism.
  const std::vector<double>& mech = lists["mechanism"];
  if (mech.size() != 2 || !WholeIn(mech[1], 0, 63) || words.count("platform") == 0) {
    *error = "log header lacks platform= or mechanism= (pivot height, legs' axes bits)";
    return std::nullopt;
  }
  c.platform = words["platform"];
  mca::DofMask legs{};
  for (int k = 0; k < mca::kDofCount; ++k) legs[static_cast<std::size_t>(k)] = ((static_cast<int>(mech[1]) >> k) & 1) != 0;
  std::vector<mca::Actuator> actuators;
  for (std::int64_t i = 0; i < axes; ++i) {
    const std::string key = "actuator" + std::to_string(i + 1);
    const auto it = words.find(key);
    std::vector<std::string> items;
    if (it != words.end()) {
      std::string item;
      std::istringstream list(it->second);
      while (std::getline(list, item, ',')) items.push_back(item);
    }
    std::vector<double> num;
    for (std::size_t k = 1; k < items.size(); ++k) {
      double x = 0.0;
      if (!ParseF64(items[k], &x) || std::isnan(x)) break;
      num.push_back(x);
    }
    if (items.size() != 14 || num.size() != 13 || !WholeIn(num[0], 0, 2) || !WholeIn(num[1], 0, 5)) {
      *error = "log header lacks " + key + "= (name, kind 0..2, pose axis 0..5, base anchor, plate anchor, "
               "stroke min, max, speed, accel, force)";
      return std::nullopt;
    }
    for (std::size_t k = 2; k < 8; ++k)
      if (!std::isfinite(num[k])) {
        *error = key + "= anchors must be finite";
        return std::nullopt;
      }
    mca::Actuator a;
    a.name = items[0];
    a.kind = static_cast<mca::ActuatorKind>(static_cast<int>(num[0]));
    a.dof = static_cast<mca::Dof>(static_cast<int>(num[1]));
    a.base_anchor = {num[2], num[3], num[4]};
    a.plate_anchor = {num[5], num[6], num[7]};
    a.limits = {num[8], num[9], num[10], num[11], num[12]};
    actuators.push_back(std::move(a));
  }
  if (!std::isfinite(mech[0])) {
    *error = "mechanism= pivot height must be finite";
    return std::nullopt;
  }
  c.mechanism = mca::Mechanism(mech[0], std::move(actuators), legs);
  const std::string bad = c.Validate();
  if (!bad.empty()) {
    *error = bad;
    return std::nullopt;
  }
  return c;
}

}  // namespace pwsim::hw
