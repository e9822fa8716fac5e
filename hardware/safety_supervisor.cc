#include "hardware/safety_supervisor.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pwsim::hw {
namespace {

double Sign(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }

/// The braking policy: one step of a jerk-limited stop (a ramps to -A then back to 0 so that
/// v and a reach 0 together). Memoryless, so a state that stops inside keeps doing so.
void BrakeStep(const AxisLimits& lim, double dt, AxisMotion* m) {
  double s = Sign(m->v);
  if (s == 0.0) s = -Sign(m->a);  // at rest with an acceleration: remove it
  if (s == 0.0) return;
  const double j = lim.jerk;
  const double v_after_ramp = m->v + m->a * std::abs(m->a) / (2.0 * j);
  const double a_target = (s * v_after_ramp > 0.0) ? -s * lim.accel : 0.0;
  double a = m->a + std::clamp(a_target - m->a, -j * dt, j * dt);
  a = std::clamp(a, -lim.accel, lim.accel);
  m->a = a;
  m->v += a * dt;
  m->p += m->v * dt;
}

}  // namespace

bool StopsInside(const AxisLimits& lim, double dt, const AxisMotion& start) {
  AxisMotion m = start;
  auto outside = [&](double p) { return p < lim.min || p > lim.max; };
  if (outside(m.p)) return false;
  const double s0 = Sign(m.v) != 0.0 ? Sign(m.v) : -Sign(m.a);
  if (s0 == 0.0) return true;
  for (int k = 0; k < 100000; ++k) {
    BrakeStep(lim, dt, &m);
    if (outside(m.p)) return false;
    if (Sign(m.v) != s0 && std::abs(m.a) <= lim.jerk * dt) return true;
    if (Sign(m.v) != s0 && Sign(m.v) != 0.0 && k > 0) {
      // Reversing with residual acceleration: keep braking until it settles.
    }
    if (m.v == 0.0 && m.a == 0.0) return true;
  }
  return false;
}

bool LimitedStep(const AxisLimits& lim, const AxisLimits& space, double dt, double target,
                 AxisMotion* m, bool* braking, double target_velocity) {
  *braking = false;
  // 1. Pass-through when the target is reachable within every limit.
  {
    AxisMotion c;
    c.p = target;
    c.v = (target - m->p) / dt;
    c.a = (c.v - m->v) / dt;
    const double jerk = (c.a - m->a) / dt;
    if (c.p >= space.min && c.p <= space.max && std::abs(c.v) <= lim.velocity &&
        std::abs(c.a) <= lim.accel && std::abs(jerk) <= lim.jerk && StopsInside(space, dt, c)) {
      *m = c;
      return false;
    }
  }
  // 2. Jerk-limited tracking: desired velocity from the distance, desired acceleration from the
  // velocity error, then the tightest acceleration range allowed by jerk, accel and velocity.
  const double d = target - m->p;
  const double a_eff = 0.5 * lim.accel;
  const double lambda = std::min(4.0, 0.5 * lim.jerk / std::max(lim.accel, 1e-9));
  // the target's own velocity fed forward: a moving target is caught up with, not trailed by v/λ
  const double v_des = std::clamp(target_velocity + Sign(d) * std::min({lim.velocity, std::sqrt(2.0 * a_eff * std::abs(d)),
                                                                       lambda * std::abs(d)}),
                                  -lim.velocity, lim.velocity);
  const double a_des = std::clamp(2.0 * lambda * (v_des - m->v), -lim.accel, lim.accel);
  double lo = m->a - lim.jerk * dt;
  double hi = m->a + lim.jerk * dt;
  const double alo = std::max(lo, -lim.accel);
  const double ahi = std::min(hi, lim.accel);
  if (alo <= ahi) {
    lo = alo;
    hi = ahi;
  } else {
    lo = hi = (m->a > 0.0 ? lo : hi);  // beyond the accel bound: reduce as fast as jerk allows
  }
  const double vlo = (-lim.velocity - m->v) / dt;
  const double vhi = (lim.velocity - m->v) / dt;
  double a = std::clamp(a_des, lo, hi);
  a = std::clamp(a, std::max(lo, std::min(vlo, hi)), std::min(hi, std::max(vhi, lo)));
  AxisMotion c{m->p + (m->v + a * dt) * dt, m->v + a * dt, a};
  if (!StopsInside(space, dt, c)) {
    // 3. Brake: the policy's own step keeps the stop-inside invariant.
    c = *m;
    AxisLimits brake = space;
    brake.velocity = std::max(brake.velocity, lim.velocity);
    BrakeStep(brake, dt, &c);
    *braking = true;
  }
  *m = c;
  return true;
}

std::string ValidateSafetyConfig(const SafetyConfig& c) {
  if (!(c.dt > 0.0 && c.dt < 0.1)) return "dt: expected a drive cycle in (0, 0.1) s";
  if (c.axis_count < 1 || c.axis_count > kMaxDriveAxes)
    return "axis_count: expected 1.." + std::to_string(kMaxDriveAxes);
  for (std::size_t i = 0; i < static_cast<std::size_t>(c.axis_count); ++i) {
    const AxisLimits& a = c.axes[i];
    const std::string axis = "axis " + std::to_string(i + 1);
    if (!(std::isfinite(a.hard_min) && std::isfinite(a.hard_max) && a.hard_min <= a.min && a.min < a.max &&
          a.max <= a.hard_max))
      return axis + ": expected finite hard_min <= min < max <= hard_max";
    if (!(a.velocity > 0.0 && a.accel > 0.0 && a.jerk > 0.0 && std::isfinite(a.velocity) &&
          std::isfinite(a.accel) && std::isfinite(a.jerk)))
      return axis + ": velocity, accel and jerk limits must be finite and > 0";
    const AxisLimits& s = c.soft_stop[i];
    if (!(s.velocity > 0.0 && s.velocity <= a.velocity && s.accel > 0.0 && s.accel <= a.accel &&
          s.jerk > 0.0 && s.jerk <= a.jerk))
      return axis + " soft stop: limits must be > 0 and within the axis limits";
    if (!(c.neutral[i] >= a.min && c.neutral[i] <= a.max)) return axis + ".neutral: outside [min, max]";
  }
  if (c.stale_setpoint_cycles < 1) return "stale_setpoint_cycles: expected >= 1";
  if (!(c.park_position_tolerance > 0.0)) return "park_position_tolerance: expected > 0";
  return "";
}

const char* SupervisorStateName(SupervisorState state) {
  switch (state) {
    case SupervisorState::kIdle: return "idle";
    case SupervisorState::kRunning: return "running";
    case SupervisorState::kSoftStop: return "soft-stop";
    case SupervisorState::kParked: return "parked";
    case SupervisorState::kFault: return "fault";
  }
  return "?";
}

SafetySupervisor::SafetySupervisor(SafetyConfig config) : config_(config) {}

void SafetySupervisor::Reset() {
  if (state_ == SupervisorState::kFault || state_ == SupervisorState::kParked) {
    state_ = SupervisorState::kIdle;
    reason_ = {};
    event_cycle_ = -1;
    parked_cycle_ = -1;
    missing_run_ = 0;
  }
}

void SafetySupervisor::BeginStop(std::int64_t cycle, SupervisorState next, std::string_view why) {
  if (state_ == SupervisorState::kFault) return;  // latched: first cause kept
  if (next == SupervisorState::kSoftStop &&
      (state_ == SupervisorState::kSoftStop || state_ == SupervisorState::kParked))
    return;
  state_ = next;
  reason_ = why;
  event_cycle_ = cycle;
}

void SafetySupervisor::PlanStop() {
  const auto n = static_cast<std::size_t>(config_.axis_count);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double vn = kInf, an = kInf, jn = kInf;  // normalised limits [1/s, 1/s^2, 1/s^3]
  for (std::size_t i = 0; i < n; ++i) {
    const double d = std::abs(motion_[i].p - config_.neutral[i]);
    if (d <= config_.park_position_tolerance) continue;
    const AxisLimits& s = config_.soft_stop[i];
    vn = std::min(vn, s.velocity / d);
    an = std::min(an, s.accel / d);
    jn = std::min(jn, s.jerk / d);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const AxisLimits& s = config_.soft_stop[i];
    AxisLimits& l = stop_limits_[i];
    l = s;
    const double d = std::abs(motion_[i].p - config_.neutral[i]);
    if (d > config_.park_position_tolerance) {
      // never below a millionth of the axis's own comfort limits (a zero limit cannot move)
      l.velocity = std::clamp(d * vn, 1e-6 * s.velocity, s.velocity);
      l.accel = std::clamp(d * an, 1e-6 * s.accel, s.accel);
      l.jerk = std::clamp(d * jn, 1e-6 * s.jerk, s.jerk);
    }
  }
}

AxisValues SafetySupervisor::Step(std::int64_t cycle, const SafetyInputs& in) {
  const auto n = static_cast<std::size_t>(config_.axis_count);
  // Validate the setpoint.
  std::optional<AxisValues> target;
  if (in.setpoint) {
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) finite = finite && std::isfinite((*in.setpoint)[i]);
    if (!finite) {
      ++counters_.nonfinite;
    } else {
      AxisValues t{};
      for (std::size_t i = 0; i < n; ++i) {
        const AxisLimits& l = config_.axes[i];
        t[i] = (*in.setpoint)[i];
        if (t[i] < l.min || t[i] > l.max) {
          t[i] = std::clamp(t[i], l.min, l.max);
          ++counters_.clamped;
        }
      }
      target = t;
    }
  }
  // the target's velocity (finite difference of consecutive valid setpoints), fed forward by
  // the tracking
  AxisValues target_velocity{};
  if (target && missing_run_ == 0 && state_ == SupervisorState::kRunning)
    for (std::size_t i = 0; i < n; ++i) target_velocity[i] = ((*target)[i] - last_setpoint_[i]) / config_.dt;
  if (target) {
    missing_run_ = 0;
    last_setpoint_ = *target;
  } else {
    ++missing_run_;
    ++counters_.missing;
  }

  AxisValues measured{};
  for (std::size_t i = 0; i < n; ++i) measured[i] = in.measured[i];
  holding_ = false;
  if (state_ == SupervisorState::kIdle) {
    for (std::size_t i = 0; i < n; ++i) motion_[i] = {measured[i], 0.0, 0.0};
    if (in.drives_ready && target && !in.stop_requested && !in.drive_fault && !in.bus_off) {
      state_ = SupervisorState::kRunning;  // start from where the platform is
    } else {
      return measured;
    }
  }

  // Watchdogs: faults first (latched), then soft-stop causes.
  if (in.bus_off) BeginStop(cycle, SupervisorState::kFault, "bus-off");
  if (in.drive_fault) BeginStop(cycle, SupervisorState::kFault, "drive fault");
  if (state_ == SupervisorState::kRunning) {
    if (missing_run_ > config_.stale_setpoint_cycles)
      BeginStop(cycle, SupervisorState::kSoftStop, "stale setpoint");
    else if (!in.heartbeats_ok)
      BeginStop(cycle, SupervisorState::kSoftStop, "drive heartbeat lost");
    else if (!in.tpdos_fresh)
      BeginStop(cycle, SupervisorState::kSoftStop, "drive feedback stale");
    else if (in.drive_restarted)
      BeginStop(cycle, SupervisorState::kSoftStop, "drive restarted");
    else if (in.drive_quick_stop)
      BeginStop(cycle, SupervisorState::kSoftStop, "drive quick stop");
    else if (!in.drives_enabled)
      BeginStop(cycle, SupervisorState::kSoftStop, "drive not operation enabled");
    else if (!in.hmd_ok)
      BeginStop(cycle, SupervisorState::kSoftStop, "HMD link stale");
    else if (in.stop_requested)
      BeginStop(cycle, SupervisorState::kSoftStop, "stop requested");
  }

  // Drives that do not follow: track the measured positions at rest, move nothing, park not.
  if (!in.drives_enabled) {
    holding_ = true;
    ++counters_.held;
    for (std::size_t i = 0; i < n; ++i) motion_[i] = {measured[i], 0.0, 0.0};
    if (state_ == SupervisorState::kParked) state_ = SupervisorState::kSoftStop;
    return measured;
  }

  AxisValues out{};
  const bool running = state_ == SupervisorState::kRunning;
  // Planned again every cycle from the current distances: along the straight line the limits
  // come out the same each cycle (d_i·min_j v_j/d_j is constant when every d shrinks by the same
  // factor), and an axis that overshot (braking from motion) gets the room it now needs.
  if (!running && state_ != SupervisorState::kParked) PlanStop();
  bool at_rest = true;
  for (std::size_t i = 0; i < n; ++i) {
    AxisMotion& m = motion_[i];
    bool braking = false;
    if (running) {
      const double t = target ? (*target)[i] : last_setpoint_[i];  // hold through short gaps
      if (LimitedStep(config_.axes[i], config_.axes[i], config_.dt, t, &m, &braking, target_velocity[i]))
        ++counters_.rate_limited;
    } else if (state_ == SupervisorState::kParked) {
      // hold
    } else {
      AxisLimits lim = stop_limits_[i];
      // Start from the running state's limits if it is moving harder than comfort allows.
      lim.accel = std::max(lim.accel, std::min(std::abs(m.a), config_.axes[i].accel));
      lim.velocity = std::max(lim.velocity, std::min(std::abs(m.v), config_.axes[i].velocity));
      // (beyond rounding: the plan's limits move by ulps from cycle to cycle)
      lim.jerk = std::abs(m.a) > stop_limits_[i].accel * (1.0 + 1e-9) ? config_.axes[i].jerk : stop_limits_[i].jerk;
      const AxisLimits& space = config_.axes[i];  // the stop-inside check keeps full limits
      LimitedStep(lim, space, config_.dt, config_.neutral[i], &m, &braking);
      if (std::abs(m.p - config_.neutral[i]) > config_.park_position_tolerance ||
          std::abs(m.v) > 1e-4 || std::abs(m.a) > 1e-3)
        at_rest = false;
    }
    if (braking) ++counters_.braking;
    out[i] = m.p;
  }
  if (state_ == SupervisorState::kSoftStop && at_rest) {
    state_ = SupervisorState::kParked;
    parked_cycle_ = cycle;
  }
  if (state_ == SupervisorState::kFault && at_rest && parked_cycle_ < 0) parked_cycle_ = cycle;
  return out;
}

}  // namespace pwsim::hw
