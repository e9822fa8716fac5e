#include "hardware/safety_supervisor.h"

#include <algorithm>
#include <cmath>

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
  if (std::abs(m.p) > lim.workspace) return false;
  const double s0 = Sign(m.v) != 0.0 ? Sign(m.v) : -Sign(m.a);
  if (s0 == 0.0) return true;
  for (int k = 0; k < 100000; ++k) {
    BrakeStep(lim, dt, &m);
    if (std::abs(m.p) > lim.workspace) return false;
    if (Sign(m.v) != s0 && std::abs(m.a) <= lim.jerk * dt) return true;
    if (Sign(m.v) != s0 && Sign(m.v) != 0.0 && k > 0) {
      // Reversing with residual acceleration: keep braking until it settles.
    }
    if (m.v == 0.0 && m.a == 0.0) return true;
  }
  return false;
}

bool LimitedStep(const AxisLimits& lim, const AxisLimits& space, double dt, double target,
                 AxisMotion* m, bool* braking) {
  *braking = false;
  // 1. Pass-through when the target is reachable within every limit.
  {
    AxisMotion c;
    c.p = target;
    c.v = (target - m->p) / dt;
    c.a = (c.v - m->v) / dt;
    const double jerk = (c.a - m->a) / dt;
    if (std::abs(c.p) <= space.workspace && std::abs(c.v) <= lim.velocity &&
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
  const double v_des = Sign(d) * std::min({lim.velocity, std::sqrt(2.0 * a_eff * std::abs(d)),
                                           lambda * std::abs(d)});
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
  for (std::size_t i = 0; i < 2; ++i) {
    const AxisLimits& a = c.axes[i];
    const std::string axis = i == 0 ? "yaw" : "rail";
    if (!(a.workspace > 0.0 && a.workspace <= a.hard_limit))
      return axis + ".workspace: expected in (0, hard_limit]";
    if (!(a.velocity > 0.0 && a.accel > 0.0 && a.jerk > 0.0))
      return axis + ": velocity, accel and jerk limits must be > 0";
    const AxisLimits& s = c.soft_stop[i];
    if (!(s.velocity > 0.0 && s.velocity <= a.velocity && s.accel > 0.0 && s.accel <= a.accel &&
          s.jerk > 0.0 && s.jerk <= a.jerk))
      return axis + " soft stop: limits must be > 0 and within the axis limits";
    if (std::abs(c.neutral[i]) > a.workspace) return axis + ".neutral: outside the workspace";
  }
  if (c.stale_setpoint_cycles < 1) return "stale_setpoint_cycles: expected >= 1";
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
  if (next == SupervisorState::kFault && state_ == SupervisorState::kParked) {
    state_ = next;
    reason_ = why;
    event_cycle_ = cycle;
    return;
  }
  state_ = next;
  reason_ = why;
  event_cycle_ = cycle;
}

std::array<double, 2> SafetySupervisor::Step(std::int64_t cycle, const SafetyInputs& in) {
  // Validate the setpoint.
  std::optional<std::array<double, 2>> target;
  if (in.setpoint) {
    bool finite = true;
    for (double v : *in.setpoint) finite = finite && std::isfinite(v);
    if (!finite) {
      ++counters_.nonfinite;
    } else {
      std::array<double, 2> t = *in.setpoint;
      for (std::size_t i = 0; i < 2; ++i) {
        const double w = config_.axes[i].workspace;
        if (std::abs(t[i]) > w) {
          t[i] = std::clamp(t[i], -w, w);
          ++counters_.clamped;
        }
      }
      target = t;
    }
  }
  if (target) {
    missing_run_ = 0;
    last_setpoint_ = *target;
  } else {
    ++missing_run_;
    ++counters_.missing;
  }

  if (state_ == SupervisorState::kIdle) {
    for (std::size_t i = 0; i < 2; ++i) motion_[i] = {in.measured[i], 0.0, 0.0};
    if (in.drives_ready && target && !in.stop_requested && !in.drive_fault && !in.bus_off) {
      state_ = SupervisorState::kRunning;  // start from where the platform is
    } else {
      return in.measured;
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
    else if (!in.hmd_ok)
      BeginStop(cycle, SupervisorState::kSoftStop, "HMD link stale");
    else if (in.stop_requested)
      BeginStop(cycle, SupervisorState::kSoftStop, "stop requested");
  }

  std::array<double, 2> out{};
  const bool running = state_ == SupervisorState::kRunning;
  bool at_rest = true;
  for (std::size_t i = 0; i < 2; ++i) {
    AxisMotion& m = motion_[i];
    bool braking = false;
    if (running) {
      const double t = target ? (*target)[i] : last_setpoint_[i];  // hold through short gaps
      if (LimitedStep(config_.axes[i], config_.axes[i], config_.dt, t, &m, &braking))
        ++counters_.rate_limited;
    } else if (state_ == SupervisorState::kParked) {
      // hold
    } else {
      AxisLimits lim = config_.soft_stop[i];
      // Start from the running state's limits if it is moving harder than comfort allows.
      lim.accel = std::max(lim.accel, std::min(std::abs(m.a), config_.axes[i].accel));
      lim.velocity = std::max(lim.velocity, std::min(std::abs(m.v), config_.axes[i].velocity));
      lim.jerk = std::abs(m.a) > config_.soft_stop[i].accel ? config_.axes[i].jerk
                                                            : config_.soft_stop[i].jerk;
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
