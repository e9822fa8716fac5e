#pragma once
// ChairSimulator: the chair model of seed 000 run on the engine's ticks. Each tick takes the
// longitudinal motion (x, v, a) of O_V, finds the wheel contact heights on the terrain, runs
// the geometric model (1)-(2) and advances the lumped model (3)-(5) exactly.
//
//   ChairSimulator sim(chair, terrain, /*load_kg=*/100, clock.dt());
//   ChairSample s = sim.Start(EvaluateDrive(profile, 0.0));
//   for (tick = 1; ...) s = sim.Advance(EvaluateDrive(profile, clock.TimeAt(tick)));

#include <array>
#include <cstdint>

#include "engine/chair.h"
#include "engine/drive_profile.h"
#include "engine/geometric_model.h"
#include "engine/lumped_model.h"
#include "engine/terrain.h"

namespace pwsim {

/// External pitch torque Γ_θ of eq. (3): Γ_θ = constant + per_accel · a_x [N m].
struct PitchTorqueParams {
  double constant{0.0};   ///< [N m]
  double per_accel{0.0};  ///< [N m / (m/s^2)] = [kg m]; e.g. -M d_CM for a rigid load
  bool operator==(const PitchTorqueParams&) const = default;
};

/// Everything known about the chair at one tick.
struct ChairSample {
  std::int64_t tick{0};
  Longitudinal drive;                       ///< O_V along the path
  std::array<double, kMaxWheels> z_O{};     ///< [m] contact heights, wheel_count() used
  GeometricOutput gm;                       ///< X_GM
  double z_gm_rate{0.0};                    ///< [m/s] over the last step
  double pitch_gm_rate{0.0};                ///< [rad/s] over the last step
  LumpedState lm;                           ///< X_M and its rate
  LumpedAcceleration lm_acc;                ///< [m/s^2], [rad/s^2]
  double pitch_torque{0.0};                 ///< Γ_θ [N m] held over the last step
};

class ChairSimulator {
 public:
  /// @pre chair has gm and lm; dt > 0.
  ChairSimulator(const Chair& chair, const Terrain& terrain, double load_kg, double dt,
                 PitchTorqueParams torque = {});

  /// Places the chair at rest in static equilibrium at `drive.x` (tick 0).
  const ChairSample& Start(const Longitudinal& drive);
  /// Advances one tick to the longitudinal state `drive`. No allocation.
  const ChairSample& Advance(const Longitudinal& drive);

  const ChairSample& sample() const { return sample_; }
  int wheel_count() const { return gm_.wheel_count(); }
  const DiscreteLumpedModel& lumped() const { return lumped_; }
  double dt() const { return lumped_.dt; }

 private:
  const Terrain& terrain_;
  GeometricModel gm_;
  DiscreteLumpedModel lumped_;
  PitchTorqueParams torque_;
  ChairSample sample_;
  std::array<std::size_t, kMaxWheels> hints_{};  ///< terrain segment of each wheel (search start)
};

}  // namespace pwsim
