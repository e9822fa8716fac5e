#pragma once
// Safety supervisor between the MCA and the CiA 402 master, run once per drive cycle.
// Software is not the e-stop (that is hard-wired to the drives' STO); this layer adds soft
// limits, watchdogs and a controlled stop. Every output satisfies, per axis and by construction:
//   |p| <= workspace, |v| <= v_max, |a| <= a_max, |a - a_prev| <= j_max dt
// (v, a, j being the finite differences of the streamed positions), and from every output
// state a jerk-limited stop stays inside the workspace (checked each cycle, so the invariant
// carries over to the next one).
//
// Documented reactions (tests/hardware/safety_supervisor_test.cc checks each one):
//   setpoint NaN/Inf               -> rejected, counted, treated as missing
//   setpoint outside workspace     -> clamped to the workspace, counted
//   step beyond v/a/j limits       -> rate-limited (jerk-limited tracking), counted
//   no valid setpoint for > stale_setpoint_cycles cycles   -> SOFT_STOP (same cycle)
//   drive heartbeat lost / TPDOs stale                      -> SOFT_STOP (same cycle)
//   HMD link stale                                          -> SOFT_STOP (same cycle)
//   drive fault (statusword, EMCY)                          -> FAULT, latched; soft stop path
//   bus-off                                                 -> FAULT, latched; soft stop path
//   stop request (end of session)                           -> SOFT_STOP
//   SOFT_STOP reaches neutral at rest                       -> PARKED (holds neutral)
// The soft stop is a jerk-limited path to neutral under the (lower) comfort limits.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace pwsim::hw {

struct AxisLimits {
  double workspace{0.55};   ///< |p| allowed for setpoints and outputs [m] or [rad]
  double hard_limit{0.6};   ///< the mechanical end (for reports; never reached)
  double velocity{2.45};    ///< [m/s] or [rad/s]
  double accel{12.0};       ///< [m/s^2] or [rad/s^2]
  double jerk{120.0};       ///< [m/s^3] or [rad/s^3]
};

struct SafetyConfig {
  double dt{0.004};  ///< drive cycle [s]
  /// q1 yaw, q2 rail. Seed 001: rail +-0.6 m, 2.45 m/s, 1.224 g peak; yaw 29.075 deg/s,
  /// 58.151 deg/s^2; the yaw workspace (+-30 deg) and both jerks are this project's choices.
  std::array<AxisLimits, 2> axes{{
      {0.5061, 0.5236, 0.50745, 1.01493, 10.0},
      {0.55, 0.6, 2.45, 12.005, 120.0},
  }};
  /// Comfort limits of the soft stop (velocity, accel, jerk; workspace unused).
  std::array<AxisLimits, 2> soft_stop{{
      {0.5061, 0.5236, 0.25, 0.3, 1.0},
      {0.55, 0.6, 0.5, 1.0, 8.0},
  }};
  int stale_setpoint_cycles{3};
  std::array<double, 2> neutral{0.0, 0.0};
  double park_position_tolerance{1e-4};  ///< [m]/[rad]
};

/// Returns "" when consistent, else which field is wrong.
std::string ValidateSafetyConfig(const SafetyConfig& config);

enum class SupervisorState { kIdle, kRunning, kSoftStop, kParked, kFault };
const char* SupervisorStateName(SupervisorState state);

struct SafetyInputs {
  std::optional<std::array<double, 2>> setpoint;  ///< from the MCA; empty = none this cycle
  std::array<double, 2> measured{};               ///< drive feedback
  bool drives_ready{false};   ///< master running (all drives operation enabled)
  bool heartbeats_ok{true};
  bool tpdos_fresh{true};
  bool drive_fault{false};
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
};

/// One axis, one cycle: the jerk-limited step toward `target` under `lim` (workspace from
/// `space`). Returns true when the output is not exactly the target (limited).
bool LimitedStep(const AxisLimits& lim, const AxisLimits& space, double dt, double target,
                 AxisMotion* m, bool* braking);
/// True when a jerk-limited stop from `m` keeps |p| <= lim.workspace.
bool StopsInside(const AxisLimits& lim, double dt, const AxisMotion& m);

class SafetySupervisor {
 public:
  explicit SafetySupervisor(SafetyConfig config = {});

  /// One drive cycle. Returns the positions to stream (valid in every state).
  std::array<double, 2> Step(std::int64_t cycle, const SafetyInputs& in);
  /// Operator reset from FAULT or PARKED back to IDLE.
  void Reset();

  SupervisorState state() const { return state_; }
  /// Why SOFT_STOP/FAULT began: a static text (valid for the program's life), "" before.
  std::string_view reason() const { return reason_; }
  std::int64_t event_cycle() const { return event_cycle_; }
  std::int64_t parked_cycle() const { return parked_cycle_; }
  const SafetyCounters& counters() const { return counters_; }
  const std::array<AxisMotion, 2>& motion() const { return motion_; }
  /// Streaming active: the master should send these positions (Running/SoftStop/Parked/Fault).
  bool streaming() const { return state_ != SupervisorState::kIdle; }
  const SafetyConfig& config() const { return config_; }

 private:
  void BeginStop(std::int64_t cycle, SupervisorState next, std::string_view why);  // why: a literal

  SafetyConfig config_;
  SupervisorState state_{SupervisorState::kIdle};
  std::array<AxisMotion, 2> motion_{};
  std::array<double, 2> last_setpoint_{};
  int missing_run_{0};
  std::string_view reason_;
  std::int64_t event_cycle_{-1};
  std::int64_t parked_cycle_{-1};
  SafetyCounters counters_;
};

}  // namespace pwsim::hw
