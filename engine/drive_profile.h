#pragma once
// Longitudinal motion of the chair along the path, as a PW power module programs it (seed 000
// §IV: accelerate on the flat floor, hold the programmed speed over the cushion, decelerate).
// A trapezoidal speed profile in closed form: x(t), v(t), a(t) for any t.

#include <string>

namespace pwsim {

struct DriveProfile {
  double start_x{0.0};      ///< [m] O_V at rest at the start
  double start_delay{0.5};  ///< [s] standing still before the power module starts
  double speed{1.2};        ///< [m/s] programmed cruise speed
  double accel{0.8};        ///< [m/s^2] programmed acceleration
  double decel{0.8};        ///< [m/s^2] programmed deceleration (positive)
  double stop_x{7.0};       ///< [m] O_V at rest at the end

  /// Empty when consistent; otherwise which field is wrong and why.
  std::string Validate() const;
  double AccelEndTime() const;   ///< [s] cruise speed reached
  double DecelStartTime() const; ///< [s] deceleration starts
  double StopTime() const;       ///< [s] at rest at stop_x
};

struct Longitudinal {
  double x{0.0};  ///< [m]
  double v{0.0};  ///< [m/s]
  double a{0.0};  ///< [m/s^2]
};

enum class DrivePhase { kStill, kAccelerate, kCruise, kDecelerate, kStopped };

Longitudinal EvaluateDrive(const DriveProfile& profile, double t);
DrivePhase PhaseAt(const DriveProfile& profile, double t);
const char* PhaseName(DrivePhase phase);

}  // namespace pwsim
