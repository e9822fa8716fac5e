#pragma once
// Motion platforms as data (`pwsim-platform/1` files under scenes/platforms/): which of the six
// axes the platform has, each axis's symmetric travel, speed and acceleration limits, and where
// the occupant's head sits above the centre of rotation. Also the limiter that makes every
// command stream respect those limits for any input.
//
//   PlatformSpec pw = ReadPlatformFile("scenes/platforms/pw4dof.yaml");
//   LimiterState s;  s = StepLimiter(pw.dofs[Index(Dof::kHeave)], s, target, target_rate, cap, dt);

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "engine/yaml_reader.h"
#include "mca/dof.h"
#include "mca/mechanism.h"

namespace pwsim::mca {

inline constexpr double kUnlimited = std::numeric_limits<double>::infinity();

/// Limits of one axis, symmetric about neutral; translations in m, rotations in rad.
struct DofLimits {
  bool present{false};
  double travel{kUnlimited};   ///< |pose| <= travel [m | rad]; kUnlimited for a free axis
  double speed{0.0};           ///< |rate| <= speed [m/s | rad/s], > 0 when present
  double accel{0.0};           ///< |acceleration| <= accel (peak) [m/s^2 | rad/s^2]
  /// Sustained acceleration [m/s^2 | rad/s^2] (the drive's continuous current); kUnlimited =
  /// none. Above it the axis draws on a budget of (accel - steady_accel)·peak_time, refilled
  /// below it: the peak acceleration can be held for peak_time, then only steady_accel.
  double steady_accel{kUnlimited};
  double peak_time{1.0};       ///< [s] how long the peak acceleration can be held
  bool operator==(const DofLimits&) const = default;

  /// The acceleration the limiter plans braking with: min(accel, steady_accel).
  double brake_accel() const { return steady_accel < accel ? steady_accel : accel; }
};

struct PlatformSpec {
  std::string name{"platform"};
  std::string description;
  std::array<DofLimits, kDofCount> dofs{};
  /// p_PH: the occupant's head from the centre of rotation, in the platform frame at neutral [m].
  std::array<double, 3> head_from_pivot{0.0, 0.0, 1.0};
  /// The actuators (mca/mechanism.h): from the file's `actuators:` list, or, for a file with axis
  /// boxes only, one rail per present translation and one rotary stage per present rotation
  /// (MechanismFromAxisBoxes). Always valid for a spec from ReadPlatformFile / Make*Platform.
  Mechanism mechanism;

  bool Has(Dof dof) const { return dofs[static_cast<std::size_t>(Index(dof))].present; }
  const DofLimits& limits(Dof dof) const { return dofs[static_cast<std::size_t>(Index(dof))]; }
  /// Empty when consistent, else which field is wrong and why.
  std::string Validate() const;
};

/// One rail per present translation and one rotary stage per present rotation, each with the
/// box's travel as stroke (a free axis: ±inf), its speed and peak acceleration; force +inf.
Mechanism MechanismFromAxisBoxes(const std::array<DofLimits, kDofCount>& dofs, double pivot_height_m = 0.0,
                                 Payload payload = {});

/// The 4-DoF PW simulator platform of seed 000 (heave, pitch, roll, yaw); the paper gives no
/// limits, so these are the defaults documented in scenes/platforms/pw4dof.yaml.
PlatformSpec MakePw4DofPlatform();
/// The 2-DoF car platform of seed 001: rail ±0.6 m, 2.45 m/s, 1.224 g peak, 0.408 g steady;
/// yaw unlimited travel, 29.075 deg/s, 58.151 deg/s² peak, 3.971 deg/s² steady.
PlatformSpec MakeCar2DofPlatform();

/// Reads the fields of a platform (everything but `format`) from an open mapping: the axis boxes
/// (`dofs:`) and, optionally, the mechanism (`pivot_height_m`, `payload`, `leg_dofs`,
/// `actuators:`; docs/platforms.md). With actuators, the axes they move must be exactly the
/// boxes' axes, every stroke must contain the actuator's neutral position and the mechanism must
/// move every axis independently at neutral; each violation names the line and field.
PlatformSpec ParsePlatform(YamlMap& map);
/// Reads a `pwsim-platform/1` file. @throws InputError.
PlatformSpec ReadPlatformFile(const std::filesystem::path& file);

/// Share of the axis box reached by the mechanism: a regular grid of `points_per_axis` values
/// (ends included) on every moved axis with a finite travel, the share of grid poses for which
/// Reachability(pose, margin_fraction) is empty. 1 for an axis-box mechanism.
double BoxShareReachable(const PlatformSpec& p, double margin_fraction, int points_per_axis);

/// One pose of a workspace slice: reachable with the margin asked for, and the largest stroke
/// use over the actuators (Mechanism::StrokeUse) with the actuator it belongs to.
struct WorkspacePoint {
  DofArray pose{};
  bool reachable{false};
  double stroke_use{0.0};
  int actuator{-1};
};
/// The grid `a` × `b` (each over ±`extent`·travel of its box, `points` values, ends included)
/// with every other axis at `base`.
std::vector<WorkspacePoint> WorkspaceSlice(const PlatformSpec& p, Dof a, Dof b, const DofArray& base,
                                           double extent, int points, double margin_fraction);

/// A text report of the mechanism: actuators (kind, axis, stroke, neutral position, limits),
/// the stroke use at each axis box's ends one axis at a time, the share of the box reachable
/// with `margin_fraction`, and the static actuator forces holding the payload at a few poses.
std::string DescribePlatform(const PlatformSpec& p, double margin_fraction);

/// One axis of the command stream: the discrete pose sequence p_k and its differences.
struct LimiterState {
  double pose{0.0};    ///< p_k [m | rad]
  double rate{0.0};    ///< (p_k - p_(k-1)) / dt
  double accel{0.0};   ///< (rate_k - rate_(k-1)) / dt
  double heat{0.0};    ///< ∫ (|accel| - steady_accel) dt, floored at 0 [m/s | rad/s]
  bool operator==(const LimiterState&) const = default;
};

/// An extra window on the rate [m/s | rad/s], lo ≤ 0 ≤ hi (e.g. the MPC's tilt band).
struct RateWindow {
  double lo{-kUnlimited};
  double hi{kUnlimited};
};

/// Moves one tick towards `target` (a pose) that itself moves at `target_rate`, staying inside
/// the limits whatever the target: the rate window is [rate ± a·dt] ∩ [±speed] ∩ `window`,
/// and the rate is also small enough that braking at brake_accel() stops inside the travel.
/// Tracks the target exactly (dead-beat) whenever that is feasible. No allocation.
/// The acceleration, travel and speed limits always hold; `window` holds whenever it meets the
/// acceleration window [rate ± a·dt] — guaranteed when the last rate lay in the last window
/// and neither edge of the window moved by more than brake_accel()·dt since (the windows, the
/// travel window [−StoppableSpeed(T+p), StoppableSpeed(T−p)] and [±speed] all contain 0, so
/// they meet pairwise, hence all together: intervals on a line). Otherwise the rate is the
/// point of the acceleration window nearest to `window`.
/// @pre state within limits (it stays so); dt > 0; window.lo ≤ 0 ≤ window.hi.
LimiterState StepLimiter(const DofLimits& limits, const LimiterState& state, double target,
                         double target_rate, RateWindow window, double dt);
/// The same with the symmetric window [±speed_cap].
LimiterState StepLimiter(const DofLimits& limits, const LimiterState& state, double target,
                         double target_rate, double speed_cap, double dt);

/// Largest speed from which braking at `brake` over discrete ticks stops within `distance`.
double StoppableSpeed(double distance, double brake, double dt);

// Inline definitions: the limiter runs on every tick for every degree of freedom.

inline double StoppableSpeed(double distance, double brake, double dt) {
  if (!(distance > 0.0)) return 0.0;
  // Braking at `brake` each tick covers at most v²/(2 brake) after this tick's v·dt
  // (a right Riemann sum of a decreasing ramp): v·dt + v²/(2 brake) <= distance.
  return brake * (std::sqrt(dt * dt + 2.0 * distance / brake) - dt);
}

inline LimiterState StepLimiter(const DofLimits& limits, const LimiterState& state, double target,
                         double target_rate, RateWindow window, double dt) {
  const double brake = limits.brake_accel();
  const double accel = std::isfinite(limits.steady_accel) &&
                               state.heat >= (limits.accel - limits.steady_accel) * limits.peak_time
                           ? limits.steady_accel
                           : limits.accel;
  const double inv_dt = 1.0 / dt;
  const double half_inv_brake = 0.5 / brake;
  // v·dt + v²/(2 brake) <= distance, i.e. v <= StoppableSpeed(distance): checked without sqrt
  auto stoppable = [&](double v, double distance) {
    return v <= 0.0 || v * dt + v * v * half_inv_brake <= distance;
  };

  // desired rate: follow the target's motion and close the remaining gap as fast as braking
  // allows (StoppableSpeed(d) < d/dt, and ≈ d/dt for a rounding-sized gap)
  double desired = 0.0;
  if (std::isfinite(target) && std::isfinite(target_rate)) {
    const double gap = (target - target_rate * dt) - state.pose;
    const double size = std::abs(gap);
    const double close = size < 1e-12 ? size * inv_dt : StoppableSpeed(size, brake, dt);
    desired = target_rate + std::copysign(close, gap);
  }

  // feasible window: acceleration, then travel (always compatible), then speed and `window`
  double lo = state.rate - accel * dt;
  double hi = state.rate + accel * dt;
  if (std::isfinite(limits.travel)) {
    if (!stoppable(hi, limits.travel - state.pose)) {
      hi = std::min(hi, StoppableSpeed(limits.travel - state.pose, brake, dt));
    }
    if (!stoppable(-lo, limits.travel + state.pose)) {
      lo = std::max(lo, -StoppableSpeed(limits.travel + state.pose, brake, dt));
    }
    if (lo > hi) lo = hi = 0.5 * (lo + hi);  // rounding only
  }
  const double lo_cap = std::max(-limits.speed, window.lo);
  const double hi_cap = std::min(limits.speed, window.hi);
  if (hi < lo_cap) {
    lo = hi;
  } else if (lo > hi_cap) {
    hi = lo;
  } else {
    lo = std::max(lo, lo_cap);
    hi = std::min(hi, hi_cap);
  }
  const double rate = std::clamp(desired, lo, hi);

  LimiterState next;
  next.pose = state.pose + rate * dt;
  if (std::isfinite(limits.travel)) next.pose = std::clamp(next.pose, -limits.travel, limits.travel);
  next.rate = (next.pose - state.pose) * inv_dt;
  next.accel = (next.rate - state.rate) * inv_dt;
  if (std::isfinite(limits.steady_accel)) {
    next.heat = std::max(0.0, state.heat + (std::abs(next.accel) - limits.steady_accel) * dt);
  }
  return next;
}

inline LimiterState StepLimiter(const DofLimits& limits, const LimiterState& state, double target,
                         double target_rate, double speed_cap, double dt) {
  return StepLimiter(limits, state, target, target_rate, RateWindow{-speed_cap, speed_cap}, dt);
}

}  // namespace pwsim::mca
