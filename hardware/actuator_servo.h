#pragma once
// One actuator's servo drive in cyclic synchronous position mode (CiA 402 CSP), for any actuator
// of an mca::Mechanism: a prismatic leg, a linear rail or a rotary stage. Coordinate q [m | rad],
// rate v [m/s | rad/s], acceleration a [m/s² | rad/s²], effort F [N | N m]. Sampled every h
// (the substep) inside the drive cycle T:
//
//   reference      r(t) = r₀ + (t/T)(r₁ − r₀),  v_r = (r₁ − r₀)/T
//                  (the CSP target latched on SYNC, interpolated from the last one over the
//                  cycle; sampled at the start of each substep, where q is)
//   position loop  v* = v_r + K_p (r − q)                                  K_p = 2π f_p [1/s]
//   velocity loop  v⁺ = v + (h/T_v)(v* − v), clamped to the window
//                  W = [v − ā h, v + ā h] ∩ [−v_max, v_max] ∩ [−S(q − q_min), S(q_max − q)]
//   plant          q⁺ = q + v⁺ h (semi-implicit Euler),  a⁺ = (v⁺ − v)/h
//   effort         F = m a⁺ + F_load
//
// ā = min(a_max, (F_max − |F_load|)/m) is the acceleration the force limit leaves once the load
// is carried, and S(d) = mca::StoppableSpeed(d, ā, h) the largest rate from which braking at ā,
// tick by tick, stops within d. The window makes the limits hold by construction (the drive's
// software position limits 0x607D, maximum profile velocity 0x607F and maximum acceleration
// 0x60C5): |v| ≤ v_max, |a| ≤ ā ≤ a_max, q_min ≤ q ≤ q_max, |F| ≤ F_max. The stroke part of W
// meets the acceleration part whenever the last rate obeyed the last stroke bound and ā did
// not shrink (mca::StepLimiter's argument); when the load grows enough that it does not, the
// stroke wins over the acceleration, and the envelope records the excess.
// A load beyond the force limit (|F_load| ≥ F_max) leaves ā at a floor of 5 % of a_max: the
// drive then reports efforts beyond F_max, which the envelope records.
//
// K_p T_v = 1/4 makes the continuous cascade critically damped: the error e = r − q obeys
// T_v ë + ė + K_p e = T_v r̈, so a ramp is followed without lag and an acceleration A leaves
// T_v A / K_p. Disabled (drive not enabled: "disable operation" option 1, then the brake):
// v* = 0 through the same window, i.e. the axis ramps to rest at ā and holds.

#include <cmath>
#include <limits>

#include "mca/mechanism.h"

namespace pwsim::hw {

/// The extremes one axis reached, sampled on every substep of the simulation (not only at the
/// drive cycle): what the actuator really did.
struct AxisEnvelope {
  double q_min{std::numeric_limits<double>::infinity()};    ///< [m | rad]
  double q_max{-std::numeric_limits<double>::infinity()};   ///< [m | rad]
  double speed{0.0};    ///< max |v| [m/s | rad/s]
  double accel{0.0};    ///< max |a| [m/s² | rad/s²]
  double effort{0.0};   ///< max |F| [N | N m]
  long samples{0};

  void Add(double q, double v, double a, double effort_now) {
    q_min = std::fmin(q_min, q);
    q_max = std::fmax(q_max, q);
    speed = std::fmax(speed, std::abs(v));
    accel = std::fmax(accel, std::abs(a));
    effort = std::fmax(effort, std::abs(effort_now));
    ++samples;
  }
};

struct ServoParams {
  double position_bandwidth_hz{20.0};  ///< f_p: K_p = 2π f_p; T_v = 1/(4 K_p)
  double substep_s{0.0005};            ///< h [s]
};

struct ServoState {
  double q{0.0};        ///< [m | rad]
  double v{0.0};        ///< [m/s | rad/s]
  double a{0.0};        ///< last substep's acceleration [m/s² | rad/s²]
  double effort{0.0};   ///< last substep's effort [N | N m]
  bool operator==(const ServoState&) const = default;
};

class ActuatorServo {
 public:
  ActuatorServo() = default;
  /// `limits` from the mechanism's actuator (a free rotary may have ±inf stroke); `moving_mass`
  /// [kg | kg m²] > 0, the inertia the actuator accelerates.
  ActuatorServo(const mca::ActuatorLimits& limits, double moving_mass, ServoParams params = {});

  /// The static load the actuator carries (from the payload, per cycle) [N | N m], positive
  /// along the actuator's coordinate (a leg pushing), and the inertia it moves [kg | kg m²].
  void SetLoad(double load, double moving_mass);
  /// Starts the reference at `target` (when the drive becomes enabled).
  void ResetTarget(double target) { previous_target_ = target; }
  /// Advances `duration` [s] toward `target` (see the header comment); `enabled` false = brake.
  /// Each substep's state goes to `envelope` when given. No allocation.
  void Advance(double duration, double target, bool enabled, AxisEnvelope* envelope);

  const ServoState& state() const { return state_; }
  void set_state(const ServoState& s) { state_ = s; }
  const mca::ActuatorLimits& limits() const { return limits_; }
  double load() const { return load_; }
  double moving_mass() const { return mass_; }
  double kp() const { return kp_; }
  double velocity_time_constant() const { return tv_; }
  /// ā: the acceleration left after the load (see the header comment).
  double available_accel() const;

 private:
  mca::ActuatorLimits limits_{};
  double mass_{1.0};
  double load_{0.0};
  double kp_{0.0};
  double tv_{1.0};
  double substep_{0.0005};
  double previous_target_{0.0};
  ServoState state_;
};

}  // namespace pwsim::hw
