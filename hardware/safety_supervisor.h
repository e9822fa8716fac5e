#pragma once
// Safety supervisor between the MCA and the CiA 402 master, run once per drive cycle, in the
// drives' own coordinates: one axis per actuator (leg length, rail position, stage angle), N of
// them (drive_axes.h). Software is not the e-stop (that is hard-wired to the drives' STO); this
// layer adds soft limits, watchdogs and a controlled stop. Every output satisfies, per axis and
// by construction:
//   min <= p <= max,  |v| <= v_max,  |a| <= a_max,  |a - a_prev| <= j_max dt
// (v, a, j being the finite differences of the streamed positions), and from every output
// state a jerk-limited stop stays inside [min, max] (checked each cycle, so the invariant
// carries over to the next one).
//
// Documented reactions (tests/hardware/safety_supervisor_test.cc checks each one):
//   setpoint NaN/Inf               -> rejected, counted, treated as missing
//   setpoint outside [min, max]    -> clamped, counted
//   step beyond v/a/j limits       -> rate-limited (jerk-limited tracking), counted
//   no valid setpoint for > stale_setpoint_cycles cycles   -> SOFT_STOP (same cycle)
//   drive heartbeat lost / TPDOs stale                      -> SOFT_STOP (same cycle)
//   a drive restarted (boot-up) / in quick stop / no longer
//   operation enabled                                       -> SOFT_STOP (same cycle)
//   HMD link stale                                          -> SOFT_STOP (same cycle)
//   drive fault (statusword, EMCY)                          -> FAULT, latched; soft stop path
//   bus-off                                                 -> FAULT, latched; soft stop path
//   stop request (end of session)                           -> SOFT_STOP
//   SOFT_STOP reaches neutral at rest, drives enabled       -> PARKED (holds neutral)
//
// Drives that do not follow. While the master does not stream these positions (drives_enabled
// false: a drive restarted, quick-stopped or faulted and the master walks it back, holding each
// drive where it is), the supervisor follows the measured positions at rest (v = a = 0) and
// neither moves nor parks. When the drives follow again it ramps from there: never a jump to
// where its own trajectory had got to.
//
// The soft stop is a jerk-limited path to neutral under the (lower) comfort limits, the axes
// synchronised: each cycle of the stop, with distances d_i = |p_i - neutral_i|, every axis gets
// the same normalised limits
//   v_n = min_i v_i / d_i,  a_n = min_i a_i / d_i,  j_n = min_i j_i / d_i
// (axis i moves under d_i v_n <= v_i, d_i a_n <= a_i, d_i j_n <= j_i). The tracking law is
// invariant under scaling distance and limits together, so from rest every axis follows the
// same normalised profile: q(t) = neutral + (q(0) - neutral) u(t), a straight line in actuator
// space (along it d_i shrinks by one factor, so each cycle's plan gives the same limits; an axis
// that overshoots while braking from motion gets the room its new distance needs). The legs of a parallel platform then stay close to a consistent pose all the way
// (they need not: legs stopped independently at different times would strain a redundant
// plate against itself).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "hardware/drive_axes.h"

namespace pwsim::hw {

/// One drive axis, in its own coordinate [m | rad].
struct AxisLimits {
  double min{-0.55};        ///< setpoints and outputs stay in [min, max]
  double max{0.55};
  double hard_min{-0.6};    ///< the mechanical ends (for reports; never reached)
  double hard_max{0.6};
  double velocity{2.45};    ///< [m/s] or [rad/s]
  double accel{12.0};       ///< [m/s^2] or [rad/s^2]
  double jerk{120.0};       ///< [m/s^3] or [rad/s^3]
  bool operator==(const AxisLimits&) const = default;
};

struct SafetyConfig {
  double dt{0.004};  ///< drive cycle [s]
  int axis_count{2};
  /// Default: seed 001's car, q1 yaw, q2 rail: rail +-0.6 m, 2.45 m/s, 1.224 g peak; yaw
  /// 29.075 deg/s, 58.151 deg/s^2; the yaw range (+-30 deg) and both jerks are this project's
  /// choices. A platform's own come from its mechanism (SafetyConfigFor, session_config.h).
  std::array<AxisLimits, kMaxDriveAxes> axes{{
      {-0.5061, 0.5061, -0.5236, 0.5236, 0.50745, 1.01493, 10.0},
      {-0.55, 0.55, -0.6, 0.6, 2.45, 12.005, 120.0},
  }};
  /// Comfort limits of the soft stop (velocity, accel, jerk; the ranges are unused).
  std::array<AxisLimits, kMaxDriveAxes> soft_stop{{
      {-0.5061, 0.5061, -0.5236, 0.5236, 0.25, 0.3, 1.0},
      {-0.55, 0.55, -0.6, 0.6, 0.5, 1.0, 8.0},
  }};
  AxisValues neutral{};                   ///< where the soft stop parks, inside [min, max]
  int stale_setpoint_cycles{3};
  double park_position_tolerance{1e-4};  ///< [m]/[rad]
};

/// Returns "" when consistent, else which field is wrong.
std::string ValidateSafetyConfig(const SafetyConfig& config);

enum class SupervisorState { kIdle, kRunning, kSoftStop, kParked, kFault };
const char* SupervisorStateName(SupervisorState state);

struct SafetyInputs {
  std::optional<AxisValues> setpoint;  ///< from the MCA (inverse kinematics); empty = none
  AxisValues measured{};               ///< drive feedback
  bool drives_ready{false};   ///< may start: master running (all drives operation enabled)
  bool drives_enabled{true};  ///< the master streams these positions (false: it holds the drives)
  bool heartbeats_ok{true};
  bool tpdos_fresh{true};
  bool drive_fault{false};
  bool drive_quick_stop{false};  ///< a drive is in quick stop active
  bool drive_restarted{false};   ///< a drive booted again (boot-up) after the start-up
  bool bus_off{false};
  bool hmd_ok{true};
  bool stop_requested{false};
};

struct AxisMotion {
  double p{0.0};
  double v{0.0};
  double a{0.0};
  bool operator==(const AxisMotion&) const = default;
};

struct SafetyCounters {
  std::uint64_t nonfinite{0};
  std::uint64_t clamped{0};
  std::uint64_t rate_limited{0};
  std::uint64_t braking{0};       ///< cycles where the stop-inside check forced braking
  std::uint64_t missing{0};       ///< cycles without a valid setpoint
  std::uint64_t held{0};          ///< cycles following the measured positions (drives not enabled)
};

/// One axis, one cycle: the jerk-limited step toward `target` moving at `target_velocity` (fed
/// forward, so that a moving target is caught up with rather than trailed by v/λ) under `lim`
/// (range [min, max] from `space`). Returns true when the output is not exactly the target.
bool LimitedStep(const AxisLimits& lim, const AxisLimits& space, double dt, double target,
                 AxisMotion* m, bool* braking, double target_velocity = 0.0);
/// True when a jerk-limited stop from `m` keeps lim.min <= p <= lim.max.
bool StopsInside(const AxisLimits& lim, double dt, const AxisMotion& m);

class SafetySupervisor {
 public:
  explicit SafetySupervisor(SafetyConfig config = {});

  /// One drive cycle. Returns the positions to stream (valid in every state; entries from
  /// axis_count on are 0).
  AxisValues Step(std::int64_t cycle, const SafetyInputs& in);
  /// Operator reset from FAULT or PARKED back to IDLE.
  void Reset();

  SupervisorState state() const { return state_; }
  /// Why SOFT_STOP/FAULT began: a static text (valid for the program's life), "" before.
  std::string_view reason() const { return reason_; }
  std::int64_t event_cycle() const { return event_cycle_; }
  std::int64_t parked_cycle() const { return parked_cycle_; }
  const SafetyCounters& counters() const { return counters_; }
  const std::array<AxisMotion, kMaxDriveAxes>& motion() const { return motion_; }
  /// Streaming active: the master should send these positions (Running/SoftStop/Parked/Fault).
  bool streaming() const { return state_ != SupervisorState::kIdle; }
  /// True while the last Step followed the measured positions (drives not enabled).
  bool holding() const { return holding_; }
  const SafetyConfig& config() const { return config_; }

 private:
  void BeginStop(std::int64_t cycle, SupervisorState next, std::string_view why);  // why: a literal
  /// The synchronised stop's per-axis limits from the current positions (header comment).
  void PlanStop();

  SafetyConfig config_;
  SupervisorState state_{SupervisorState::kIdle};
  std::array<AxisMotion, kMaxDriveAxes> motion_{};
  AxisValues last_setpoint_{};
  std::array<AxisLimits, kMaxDriveAxes> stop_limits_{};  ///< this stop's comfort limits
  bool holding_{false};
  int missing_run_{0};
  std::string_view reason_;
  std::int64_t event_cycle_{-1};
  std::int64_t parked_cycle_{-1};
  SafetyCounters counters_;
};

}  // namespace pwsim::hw
