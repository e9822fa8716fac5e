#include "engine/drive_profile.h"

#include <cmath>

namespace pwsim {

std::string DriveProfile::Validate() const {
  if (!(speed > 0.0)) return "speed_mps must be > 0";
  if (!(accel > 0.0)) return "accel_mps2 must be > 0";
  if (!(decel > 0.0)) return "decel_mps2 must be > 0";
  if (!(start_delay >= 0.0)) return "start_delay_s must be >= 0";
  const double needed = speed * speed / (2.0 * accel) + speed * speed / (2.0 * decel);
  if (stop_x - start_x < needed) {
    return "stop_x_m - start_x_m must be at least " + std::to_string(needed) +
           " m to reach the programmed speed and stop again";
  }
  return "";
}

double DriveProfile::AccelEndTime() const { return start_delay + speed / accel; }

double DriveProfile::DecelStartTime() const {
  const double cruise_distance =
      (stop_x - start_x) - speed * speed / (2.0 * accel) - speed * speed / (2.0 * decel);
  return AccelEndTime() + cruise_distance / speed;
}

double DriveProfile::StopTime() const { return DecelStartTime() + speed / decel; }

Longitudinal EvaluateDrive(const DriveProfile& p, double t) {
  const double t1 = p.AccelEndTime();
  const double t2 = p.DecelStartTime();
  const double t3 = p.StopTime();
  if (t <= p.start_delay) return {p.start_x, 0.0, 0.0};
  if (t < t1) {
    const double tau = t - p.start_delay;
    return {p.start_x + 0.5 * p.accel * tau * tau, p.accel * tau, p.accel};
  }
  const double x1 = p.start_x + p.speed * p.speed / (2.0 * p.accel);
  if (t < t2) return {x1 + p.speed * (t - t1), p.speed, 0.0};
  if (t < t3) {
    const double tau = t - t2;
    const double x2 = x1 + p.speed * (t2 - t1);
    return {x2 + p.speed * tau - 0.5 * p.decel * tau * tau, p.speed - p.decel * tau, -p.decel};
  }
  return {p.stop_x, 0.0, 0.0};
}

DrivePhase PhaseAt(const DriveProfile& p, double t) {
  if (t <= p.start_delay) return DrivePhase::kStill;
  if (t < p.AccelEndTime()) return DrivePhase::kAccelerate;
  if (t < p.DecelStartTime()) return DrivePhase::kCruise;
  if (t < p.StopTime()) return DrivePhase::kDecelerate;
  return DrivePhase::kStopped;
}

const char* PhaseName(DrivePhase phase) {
  switch (phase) {
    case DrivePhase::kStill: return "still";
    case DrivePhase::kAccelerate: return "accelerate";
    case DrivePhase::kCruise: return "cruise";
    case DrivePhase::kDecelerate: return "decelerate";
    case DrivePhase::kStopped: return "stopped";
  }
  return "unknown";
}

}  // namespace pwsim
