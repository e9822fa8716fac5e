#pragma once
// Motion platforms as data (`pwsim-platform/1` files under scenes/platforms/): which of the six
// axes the platform has, each axis's symmetric travel, speed and acceleration limits, and where
// the occupant's head sits above the centre of rotation. Also the limiter that makes every
// command stream respect those limits for any input.
//
//   PlatformSpec pw = ReadPlatformFile("scenes/platforms/pw4dof.yaml");
//   LimiterState s;  s = StepLimiter(pw.dofs[Index(Dof::kHeave)], s, target, target_rate, cap, dt);

#include <array>
#include <filesystem>
#include <limits>
#include <string>

#include "engine/yaml_reader.h"
#include "mca/dof.h"

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

  bool Has(Dof dof) const { return dofs[static_cast<std::size_t>(Index(dof))].present; }
  const DofLimits& limits(Dof dof) const { return dofs[static_cast<std::size_t>(Index(dof))]; }
  /// Empty when consistent, else which field is wrong and why.
  std::string Validate() const;
};

/// The 4-DoF PW simulator platform of seed 000 (heave, pitch, roll, yaw); the paper gives no
/// limits, so these are the defaults documented in scenes/platforms/pw4dof.yaml.
PlatformSpec MakePw4DofPlatform();
/// The 2-DoF car platform of seed 001: rail ±0.6 m, 2.45 m/s, 1.224 g peak, 0.408 g steady;
/// yaw unlimited travel, 29.075 deg/s, 58.151 deg/s² peak, 3.971 deg/s² steady.
PlatformSpec MakeCar2DofPlatform();

/// Reads the fields of a platform (everything but `format`) from an open mapping.
PlatformSpec ParsePlatform(YamlMap& map);
/// Reads a `pwsim-platform/1` file. @throws InputError.
PlatformSpec ReadPlatformFile(const std::filesystem::path& file);

/// One axis of the command stream: the discrete pose sequence p_k and its differences.
struct LimiterState {
  double pose{0.0};    ///< p_k [m | rad]
  double rate{0.0};    ///< (p_k - p_(k-1)) / dt
  double accel{0.0};   ///< (rate_k - rate_(k-1)) / dt
  double heat{0.0};    ///< ∫ (|accel| - steady_accel) dt, floored at 0 [m/s | rad/s]
  bool operator==(const LimiterState&) const = default;
};

/// Moves one tick towards `target` (a pose) that itself moves at `target_rate`, staying inside
/// the limits whatever the target: the rate window is [rate ± a·dt] ∩ [±min(speed, speed_cap)],
/// and the rate is also small enough that braking at brake_accel() stops inside the travel.
/// Tracks the target exactly (dead-beat) whenever that is feasible. No allocation.
/// @pre state within limits (it stays so); dt > 0.
LimiterState StepLimiter(const DofLimits& limits, const LimiterState& state, double target,
                         double target_rate, double speed_cap, double dt);

/// Largest speed from which braking at `brake` over discrete ticks stops within `distance`.
double StoppableSpeed(double distance, double brake, double dt);

}  // namespace pwsim::mca
