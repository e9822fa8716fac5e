#include "mca/platform.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"
#include "engine/input_error.h"

namespace pwsim::mca {
namespace {

DofLimits Translation(double travel, double speed, double accel) {
  return {.present = true, .travel = travel, .speed = speed, .accel = accel};
}

DofLimits RotationDeg(double travel_deg, double speed_degps, double accel_degps2) {
  return {.present = true,
          .travel = travel_deg * kDegToRad,
          .speed = speed_degps * kDegToRad,
          .accel = accel_degps2 * kDegToRad};
}

DofLimits ParseDof(YamlMap& map, Dof dof) {
  DofLimits limits;
  limits.present = true;
  const bool rotational = IsRotational(dof);
  const double to_si = rotational ? kDegToRad : 1.0;
  const std::string pose_unit = rotational ? "deg" : "m";
  const std::string rate_unit = rotational ? "deg/s" : "m/s";
  const std::string accel_unit = rotational ? "deg/s^2" : "m/s^2";
  const std::string travel_key = rotational ? "travel_deg" : "travel_m";
  const std::string speed_key = rotational ? "speed_degps" : "speed_mps";
  const std::string accel_key = rotational ? "accel_degps2" : "accel_mps2";
  const std::string steady_key = rotational ? "steady_accel_degps2" : "steady_accel_mps2";
  // An axis without travel_* is unlimited in pose (e.g. the car platform's yaw turntable).
  if (map.Has(travel_key)) {
    limits.travel = to_si * map.Number(travel_key, Range::Positive(rotational ? 180.0 : 10.0, pose_unit));
  }
  limits.speed = to_si * map.Number(speed_key, Range::Positive(rotational ? 3600.0 : 50.0, rate_unit));
  limits.accel = to_si * map.Number(accel_key, Range::Positive(rotational ? 1e5 : 1e3, accel_unit));
  if (map.Has(steady_key)) {
    limits.steady_accel =
        to_si * map.Number(steady_key, Range::Positive(rotational ? 1e5 : 1e3, accel_unit));
    if (limits.steady_accel > limits.accel) {
      map.Fail(steady_key, "a sustained acceleration no larger than the peak " + accel_key,
               std::to_string(limits.steady_accel / to_si));
    }
    limits.peak_time = map.NumberOr("peak_time_s", 1.0, Range::Positive(60.0, "s"));
  }
  return limits;
}

}  // namespace

Mechanism MechanismFromAxisBoxes(const std::array<DofLimits, kDofCount>& dofs, double pivot_height_m) {
  std::vector<Actuator> actuators;
  for (Dof dof : kAllDofs) {
    const DofLimits& box = dofs[static_cast<std::size_t>(Index(dof))];
    if (!box.present) continue;
    Actuator a;
    a.name = std::string(DofName(dof));
    a.kind = IsRotational(dof) ? ActuatorKind::kRotary : ActuatorKind::kRail;
    a.dof = dof;
    a.limits = {.min = -box.travel, .max = box.travel, .speed = box.speed, .accel = box.accel, .force = kUnlimited};
    actuators.push_back(std::move(a));
  }
  return Mechanism(pivot_height_m, std::move(actuators), DofMask{});
}

std::string_view DofName(Dof dof) {
  switch (dof) {
    case Dof::kSurge: return "surge";
    case Dof::kSway: return "sway";
    case Dof::kHeave: return "heave";
    case Dof::kRoll: return "roll";
    case Dof::kPitch: return "pitch";
    case Dof::kYaw: return "yaw";
  }
  return "?";
}

std::string PlatformSpec::Validate() const {
  bool any = false;
  for (Dof dof : kAllDofs) {
    const DofLimits& l = limits(dof);
    if (!l.present) continue;
    any = true;
    const std::string axis(DofName(dof));
    if (!(l.travel > 0.0)) return axis + ": travel must be > 0";
    if (!(l.speed > 0.0) || !std::isfinite(l.speed)) return axis + ": speed must be finite and > 0";
    if (!(l.accel > 0.0) || !std::isfinite(l.accel)) return axis + ": accel must be finite and > 0";
    if (!(l.steady_accel > 0.0) || (std::isfinite(l.steady_accel) && l.steady_accel > l.accel)) {
      return axis + ": steady accel must be in (0, accel]";
    }
    if (!(l.peak_time > 0.0)) return axis + ": peak time must be > 0";
  }
  if (!any) return "a platform needs at least one degree of freedom";
  return {};
}

PlatformSpec MakePw4DofPlatform() {
  PlatformSpec p;
  p.name = "pw4dof";
  p.description = "4-DoF PW simulator platform of seed 000 (heave, pitch, roll, yaw); limits assumed";
  p.dofs[Index(Dof::kHeave)] = Translation(0.10, 0.40, 8.0);
  p.dofs[Index(Dof::kRoll)] = RotationDeg(15.0, 40.0, 300.0);
  p.dofs[Index(Dof::kPitch)] = RotationDeg(15.0, 40.0, 300.0);
  p.dofs[Index(Dof::kYaw)] = RotationDeg(25.0, 40.0, 300.0);
  p.head_from_pivot = {0.05, 0.0, 0.95};
  p.mechanism = MechanismFromAxisBoxes(p.dofs);
  return p;
}

PlatformSpec MakeCar2DofPlatform() {
  PlatformSpec p;
  p.name = "car2dof";
  p.description = "2-DoF car platform of seed 001: 1.2 m rail (surge) and yaw turntable";
  DofLimits rail = Translation(0.6, 2.45, 1.224 * kGravity);
  rail.steady_accel = 0.408 * kGravity;
  p.dofs[Index(Dof::kSurge)] = rail;
  DofLimits yaw = RotationDeg(0.0, 29.075, 58.151);
  yaw.travel = kUnlimited;
  yaw.steady_accel = 3.971 * kDegToRad;
  p.dofs[Index(Dof::kYaw)] = yaw;
  p.head_from_pivot = {0.0, 0.0, 0.8};
  p.mechanism = MechanismFromAxisBoxes(p.dofs);
  return p;
}

PlatformSpec ParsePlatform(YamlMap& map) {
  PlatformSpec p;
  p.name = map.String("name");
  p.description = map.StringOr("description", "");
  if (map.Has("head_from_pivot_m")) {
    const std::vector<double> head =
        map.Numbers("head_from_pivot_m", Range::Closed(-3.0, 3.0, "m"), 3, 3);
    std::copy(head.begin(), head.end(), p.head_from_pivot.begin());
  }
  YamlMap dofs = map.Map("dofs");
  for (Dof dof : kAllDofs) {
    const std::string key(DofName(dof));
    if (!dofs.Has(key)) continue;
    YamlMap axis = dofs.Map(key);
    p.dofs[static_cast<std::size_t>(Index(dof))] = ParseDof(axis, dof);
    axis.Finish();
  }
  dofs.Finish();
  if (const std::string problem = p.Validate(); !problem.empty()) {
    map.Fail("dofs", "a consistent platform (" + problem + ")", "an inconsistent one");
  }
  p.mechanism = MechanismFromAxisBoxes(p.dofs);
  return p;
}

PlatformSpec ReadPlatformFile(const std::filesystem::path& file) {
  return ReadTaggedYamlFile(file, "pwsim-platform/1", ParsePlatform);
}

}  // namespace pwsim::mca
