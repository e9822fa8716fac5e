#include "mca/platform.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

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

std::optional<Dof> DofFromName(const std::string& name) {
  for (Dof dof : kAllDofs) {
    if (DofName(dof) == name) return dof;
  }
  return std::nullopt;
}

/// Six significant digits (a figure in a message, not a round trip).
std::string Short(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

std::string Pair(double a, double b, const char* unit) { return "[" + Short(a) + ", " + Short(b) + "] " + unit; }

/// One entry of `actuators:`, with where it came from (for errors found after parsing).
struct ParsedActuator {
  Actuator actuator;
  int line{0};
  std::string field;
  std::string stroke_key;
};

ParsedActuator ParseActuator(const YAML::Node& node, const std::filesystem::path& file, const std::string& field,
                             int parent_line) {
  YamlMap e(node, file, field, parent_line);
  ParsedActuator parsed;
  parsed.line = e.line();
  parsed.field = field;
  Actuator& a = parsed.actuator;
  a.name = e.String("name");
  const std::string kind = e.Choice("kind", {"leg", "rail", "rotary"});
  a.kind = kind == "leg" ? ActuatorKind::kLeg : kind == "rail" ? ActuatorKind::kRail : ActuatorKind::kRotary;
  const bool rotary = a.kind == ActuatorKind::kRotary;
  if (a.kind == ActuatorKind::kLeg) {
    const std::vector<double> base = e.Numbers("base_m", Range::Closed(-10.0, 10.0, "m"), 3, 3);
    const std::vector<double> plate = e.Numbers("plate_m", Range::Closed(-10.0, 10.0, "m"), 3, 3);
    a.base_anchor = Eigen::Vector3d(base[0], base[1], base[2]);
    a.plate_anchor = Eigen::Vector3d(plate[0], plate[1], plate[2]);
  } else {
    const std::string axis = rotary ? e.Choice("dof", {"roll", "pitch", "yaw"})
                                    : e.Choice("dof", {"surge", "sway", "heave"});
    a.dof = *DofFromName(axis);
  }
  // stroke: a leg's length range, a rail's position range, a stage's angle range (absent: free)
  parsed.stroke_key = rotary ? "stroke_deg" : "stroke_m";
  const double to_si = rotary ? kDegToRad : 1.0;
  if (rotary && !e.Has("stroke_deg")) {
    a.limits.min = -kUnlimited;
    a.limits.max = kUnlimited;
  } else {
    const Range range = a.kind == ActuatorKind::kLeg ? Range::Positive(20.0, "m")
                        : rotary                      ? Range::Closed(-3600.0, 3600.0, "deg")
                                                      : Range::Closed(-20.0, 20.0, "m");
    const std::vector<double> stroke = e.Numbers(parsed.stroke_key, range, 2, 2);
    if (!(stroke[0] < stroke[1])) {
      e.Fail(parsed.stroke_key, "[min, max] with min < max", Pair(stroke[0], stroke[1], rotary ? "deg" : "m"));
    }
    a.limits.min = to_si * stroke[0];
    a.limits.max = to_si * stroke[1];
  }
  a.limits.speed = to_si * (rotary ? e.Number("speed_degps", Range::Positive(3600.0, "deg/s"))
                                   : e.Number("speed_mps", Range::Positive(50.0, "m/s")));
  a.limits.accel = to_si * (rotary ? e.Number("accel_degps2", Range::Positive(1e5, "deg/s^2"))
                                   : e.Number("accel_mps2", Range::Positive(1e3, "m/s^2")));
  a.limits.force = rotary ? e.Number("torque_Nm", Range::Positive(1e7, "N m"))
                          : e.Number("force_N", Range::Positive(1e7, "N"));
  e.Finish();
  return parsed;
}

/// The mechanism keys of a platform mapping; `p.dofs` already read.
Mechanism ParseMechanism(YamlMap& map, const PlatformSpec& p) {
  const double pivot_height = map.NumberOr("pivot_height_m", 0.0, Range::Closed(-5.0, 5.0, "m"));
  Payload payload;
  if (map.Has("payload")) {
    YamlMap load = map.Map("payload");
    payload.mass = load.Number("mass_kg", Range::Closed(0.0, 1e5, "kg"));
    const std::vector<double> com = load.Numbers("com_from_pivot_m", Range::Closed(-10.0, 10.0, "m"), 3, 3);
    payload.com_from_pivot = Eigen::Vector3d(com[0], com[1], com[2]);
    load.Finish();
  }
  if (!map.Has("actuators")) {
    if (map.Has("leg_dofs")) map.Fail("leg_dofs", "leg_dofs only beside an actuators: list", "leg_dofs alone");
    return MechanismFromAxisBoxes(p.dofs, pivot_height, payload);
  }

  const YAML::Node list = map.Sequence("actuators");
  const std::string list_field = map.FieldName("actuators");
  const int list_line = map.LineOfKey("actuators");
  if (list.size() < 1 || list.size() > static_cast<std::size_t>(kMaxActuators)) {
    throw InputError(map.file().string(), list_line, list_field,
                     "1.." + std::to_string(kMaxActuators) + " actuators", std::to_string(list.size()));
  }
  std::vector<ParsedActuator> parsed;
  DofMask stage_axes{};
  bool any_leg = false;
  for (std::size_t i = 0; i < list.size(); ++i) {
    ParsedActuator entry = ParseActuator(list[i], map.file(), list_field + "[" + std::to_string(i) + "]", list_line);
    const Actuator& a = entry.actuator;
    for (const ParsedActuator& before : parsed) {
      if (before.actuator.name == a.name) {
        throw InputError(map.file().string(), entry.line, entry.field + ".name", "a name no other actuator has",
                         "\"" + a.name + "\" again (also " + before.field + ")");
      }
    }
    if (a.kind == ActuatorKind::kLeg) {
      any_leg = true;
    } else {
      if (stage_axes[static_cast<std::size_t>(Index(a.dof))]) {
        throw InputError(map.file().string(), entry.line, entry.field + ".dof", "an axis no other stage drives",
                         std::string(DofName(a.dof)) + " again");
      }
      stage_axes[static_cast<std::size_t>(Index(a.dof))] = true;
    }
    parsed.push_back(std::move(entry));
  }

  // the axes the legs move relative to the stages (the rest held by a passive guide)
  DofMask leg_axes{};
  if (map.Has("leg_dofs")) {
    if (!any_leg) map.Fail("leg_dofs", "leg_dofs only when there are legs", "leg_dofs without a leg");
    const YAML::Node axes = map.Sequence("leg_dofs");
    const std::string field = map.FieldName("leg_dofs");
    for (std::size_t i = 0; i < axes.size(); ++i) {
      const std::string item = field + "[" + std::to_string(i) + "]";
      const int line = LineOf(axes[i]) > 0 ? LineOf(axes[i]) : map.LineOfKey("leg_dofs");
      const std::optional<Dof> dof = axes[i].IsScalar() ? DofFromName(axes[i].Scalar()) : std::nullopt;
      if (!dof) {
        throw InputError(map.file().string(), line, item, "one of surge, sway, heave, roll, pitch, yaw",
                         axes[i].IsScalar() ? "\"" + axes[i].Scalar() + "\"" : "not a name");
      }
      const std::size_t k = static_cast<std::size_t>(Index(*dof));
      if (leg_axes[k]) throw InputError(map.file().string(), line, item, "each axis once", axes[i].Scalar() + " again");
      if (stage_axes[k]) {
        throw InputError(map.file().string(), line, item, "an axis no stage drives (legs move the plate above the stages)",
                         axes[i].Scalar() + ", which a stage drives");
      }
      leg_axes[k] = true;
    }
  } else if (any_leg) {
    for (std::size_t k = 0; k < leg_axes.size(); ++k) leg_axes[k] = !stage_axes[k];
  }

  std::vector<Actuator> actuators;
  for (const ParsedActuator& entry : parsed) actuators.push_back(entry.actuator);
  Mechanism mechanism(pivot_height, std::move(actuators), leg_axes, payload);
  // every stroke contains the neutral position (named at the actuator's own line)
  ActuatorVector neutral;
  if (!mechanism.Inverse(DofArray{}, &neutral)) {
    map.Fail("actuators", "legs of positive length at the neutral pose", "a leg of zero length");
  }
  for (std::size_t i = 0; i < parsed.size(); ++i) {
    const Actuator& a = parsed[i].actuator;
    const double q = neutral[static_cast<Eigen::Index>(i)];
    if (q > a.limits.min && q < a.limits.max) continue;
    const bool rotary = a.kind == ActuatorKind::kRotary;
    const double scale = rotary ? 1.0 / kDegToRad : 1.0;
    const char* unit = rotary ? "deg" : "m";
    const std::string what = a.kind == ActuatorKind::kLeg ? "the leg's neutral length " : "the neutral position ";
    throw InputError(map.file().string(), parsed[i].line, parsed[i].field + "." + parsed[i].stroke_key,
                     "a stroke containing " + what + Short(q * scale) + " " + unit +
                         (a.kind == ActuatorKind::kLeg ? " (|plate anchor at pivot_height_m − base anchor|)" : ""),
                     Pair(a.limits.min * scale, a.limits.max * scale, unit));
  }
  if (const std::string problem = mechanism.Validate(); !problem.empty()) {
    map.Fail("actuators", "a consistent mechanism", problem);
  }
  // the axis boxes and the mechanism agree on which axes exist
  for (Dof dof : kAllDofs) {
    const std::string axis(DofName(dof));
    if (p.Has(dof) && !mechanism.Moves(dof)) {
      map.Fail("dofs", "boxes only on axes the actuators move", axis + " has a box but no actuator moves it");
    }
    if (!p.Has(dof) && mechanism.Moves(dof)) {
      map.Fail("dofs", "a box on every axis the actuators move", "the actuators move " + axis + " but dofs: has no " + axis);
    }
  }
  return mechanism;
}

}  // namespace

Mechanism MechanismFromAxisBoxes(const std::array<DofLimits, kDofCount>& dofs, double pivot_height_m,
                                 Payload payload) {
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
  return Mechanism(pivot_height_m, std::move(actuators), DofMask{}, payload);
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
  // the mechanism of scenes/platforms/pw4dof.yaml (every number assumed, docs/platforms.md)
  std::vector<Actuator> actuators;
  Actuator yaw;
  yaw.name = "yaw";
  yaw.kind = ActuatorKind::kRotary;
  yaw.dof = Dof::kYaw;
  yaw.limits = {.min = -28.0 * kDegToRad, .max = 28.0 * kDegToRad, .speed = 45.0 * kDegToRad,
                .accel = 320.0 * kDegToRad, .force = 400.0};
  actuators.push_back(yaw);
  for (const auto& [name, x, y] : {std::tuple{"leg_front_left", 1.0, 1.0}, std::tuple{"leg_front_right", 1.0, -1.0},
                                   std::tuple{"leg_rear_left", -1.0, 1.0}, std::tuple{"leg_rear_right", -1.0, -1.0}}) {
    Actuator leg;
    leg.name = name;
    leg.kind = ActuatorKind::kLeg;
    leg.base_anchor = Eigen::Vector3d(0.32 * x, 0.27 * y, 0.05);
    leg.plate_anchor = Eigen::Vector3d(0.30 * x, 0.25 * y, -0.05);
    leg.limits = {.min = 0.37, .max = 0.63, .speed = 0.45, .accel = 10.0, .force = 2000.0};
    actuators.push_back(leg);
  }
  DofMask legs{};
  legs[Index(Dof::kHeave)] = legs[Index(Dof::kRoll)] = legs[Index(Dof::kPitch)] = true;
  p.mechanism = Mechanism(0.60, std::move(actuators), legs,
                          Payload{.mass = 180.0, .com_from_pivot = Eigen::Vector3d(0.0, 0.0, 0.45)});
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
  // the mechanism of scenes/platforms/car2dof.yaml: the rail on the turntable
  Actuator rail_stage;
  rail_stage.name = "rail";
  rail_stage.kind = ActuatorKind::kRail;
  rail_stage.dof = Dof::kSurge;
  rail_stage.limits = {.min = -0.6, .max = 0.6, .speed = 2.45, .accel = rail.accel, .force = 5161.0};
  Actuator yaw_stage;
  yaw_stage.name = "yaw";
  yaw_stage.kind = ActuatorKind::kRotary;
  yaw_stage.dof = Dof::kYaw;
  yaw_stage.limits = {.min = -kUnlimited, .max = kUnlimited, .speed = yaw.speed, .accel = yaw.accel, .force = 1252.8};
  // yaw first, then the rail: the drives' nodes follow this order (node 1 = yaw, node 2 = rail)
  p.mechanism = Mechanism(0.5, {yaw_stage, rail_stage}, DofMask{},
                          Payload{.mass = 430.0, .com_from_pivot = Eigen::Vector3d(0.0, 0.0, 0.3)});
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
  p.mechanism = ParseMechanism(map, p);
  return p;
}

namespace {

/// A pose entry in display units: m, or deg for a rotation.
double Display(Dof dof, double value) { return IsRotational(dof) ? value / kDegToRad : value; }
const char* DisplayUnit(Dof dof) { return IsRotational(dof) ? "deg" : "m"; }

std::string Fixed(double value, int digits) {
  if (std::abs(value) < 0.5 * std::pow(10.0, -digits)) value = 0.0;  // no "-0.0"
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value);
  return buffer;
}

std::string Padded(std::string text, std::size_t width) {
  if (text.size() < width) text.append(width - text.size(), ' ');
  return text;
}

/// The largest stroke use at q and its actuator.
std::pair<double, int> LargestUse(const Mechanism& m, const ActuatorVector& q) {
  ActuatorVector use;
  m.StrokeUse(q, &use);
  int worst = -1;
  double largest = 0.0;
  for (int i = 0; i < m.actuator_count(); ++i) {
    if (use[i] > largest) {
      largest = use[i];
      worst = i;
    }
  }
  return {largest, worst};
}

std::string PoseText(const DofArray& x) {
  std::string text;
  for (Dof dof : kAllDofs) {
    const double v = x[static_cast<std::size_t>(Index(dof))];
    if (v == 0.0) continue;
    text += (text.empty() ? "" : ", ") + std::string(DofName(dof)) + " " + (v > 0 ? "+" : "") +
            Short(Display(dof, v)) + " " + DisplayUnit(dof);
  }
  return text.empty() ? "neutral" : text;
}

}  // namespace

double BoxShareReachable(const PlatformSpec& p, double margin_fraction, int points_per_axis) {
  std::vector<Dof> axes;
  for (Dof dof : kAllDofs) {
    if (p.Has(dof) && p.mechanism.Moves(dof) && std::isfinite(p.limits(dof).travel)) axes.push_back(dof);
  }
  const int n = std::max(2, points_per_axis);
  std::vector<int> index(axes.size(), 0);
  long total = 0, reached = 0;
  while (true) {
    DofArray x{};
    for (std::size_t k = 0; k < axes.size(); ++k) {
      const double travel = p.limits(axes[k]).travel;
      x[static_cast<std::size_t>(Index(axes[k]))] = -travel + 2.0 * travel * index[k] / (n - 1);
    }
    ++total;
    if (p.mechanism.Reachability(x, margin_fraction).empty()) ++reached;
    std::size_t k = 0;
    while (k < axes.size() && ++index[k] == n) index[k++] = 0;
    if (k == axes.size()) break;
  }
  return static_cast<double>(reached) / static_cast<double>(total);
}

std::vector<WorkspacePoint> WorkspaceSlice(const PlatformSpec& p, Dof a, Dof b, const DofArray& base,
                                           double extent, int points, double margin_fraction) {
  std::vector<WorkspacePoint> out;
  const int n = std::max(2, points);
  const double ta = extent * p.limits(a).travel, tb = extent * p.limits(b).travel;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      WorkspacePoint w;
      w.pose = base;
      w.pose[static_cast<std::size_t>(Index(a))] = -ta + 2.0 * ta * i / (n - 1);
      w.pose[static_cast<std::size_t>(Index(b))] = -tb + 2.0 * tb * j / (n - 1);
      w.reachable = p.mechanism.Reachability(w.pose, margin_fraction).empty();
      ActuatorVector q;
      if (p.mechanism.Inverse(w.pose, &q)) std::tie(w.stroke_use, w.actuator) = LargestUse(p.mechanism, q);
      out.push_back(w);
    }
  }
  return out;
}

std::string DescribePlatform(const PlatformSpec& p, double margin_fraction) {
  const Mechanism& m = p.mechanism;
  std::string moved;
  for (Dof dof : kAllDofs) {
    if (m.Moves(dof)) moved += (moved.empty() ? "" : ", ") + std::string(DofName(dof));
  }
  std::string out = "platform " + p.name + ": " + std::to_string(m.actuator_count()) + " actuators move " + moved +
                    " (" + std::to_string(m.moved_axis_count()) + " axes";
  out += m.redundancy() > 0 ? "; redundant by " + std::to_string(m.redundancy()) +
                                  ": static forces are the minimum-norm choice)\n"
                            : ")\n";
  out += "pivot " + Short(m.pivot_height()) + " m above the base; payload " + Short(m.payload().mass) +
         " kg at (" + Short(m.payload().com_from_pivot.x()) + ", " + Short(m.payload().com_from_pivot.y()) + ", " +
         Short(m.payload().com_from_pivot.z()) + ") m from the pivot\n";
  out += "actuators (stroke, neutral position, speed, acceleration, force limits):\n";
  const ActuatorVector q0 = m.Neutral();
  for (int i = 0; i < m.actuator_count(); ++i) {
    const Actuator& a = m.actuator(i);
    const bool rotary = a.kind == ActuatorKind::kRotary;
    const double k = rotary ? 1.0 / kDegToRad : 1.0;
    const std::string u = rotary ? "deg" : "m";
    std::string drives = a.kind == ActuatorKind::kLeg ? "legs' axes" : std::string(DofName(a.dof));
    out += "  " + Padded(a.name, 17) + Padded(ActuatorKindName(a.kind), 7) + Padded(drives, 11);
    out += Padded(std::isfinite(a.limits.min) ? "[" + Short(a.limits.min * k) + ", " + Short(a.limits.max * k) + "] " + u
                                              : std::string("free"),
                  20);
    out += Padded("neutral " + Short(q0[i] * k) + " " + u, 20);
    out += Padded(Short(a.limits.speed * k) + " " + u + "/s", 13) + Padded(Short(a.limits.accel * k) + " " + u + "/s^2", 15);
    out += std::isfinite(a.limits.force) ? Short(a.limits.force) + (rotary ? " N m" : " N") : std::string("force unlimited");
    out += "\n";
  }

  out += "axis boxes one axis at a time (largest stroke use: share of the half-stroke from neutral):\n";
  for (Dof dof : kAllDofs) {
    if (!p.Has(dof)) continue;
    const double travel = p.limits(dof).travel;
    if (!std::isfinite(travel)) {
      out += "  " + Padded(std::string(DofName(dof)), 6) + " free\n";
      continue;
    }
    out += "  " + Padded(std::string(DofName(dof)), 6);
    for (double sign : {1.0, -1.0}) {
      DofArray x{};
      x[static_cast<std::size_t>(Index(dof))] = sign * travel;
      ActuatorVector q;
      std::string cell = (sign > 0 ? "+" : "-") + Short(Display(dof, travel)) + " " + DisplayUnit(dof) + ": ";
      if (m.Inverse(x, &q)) {
        const auto [use, who] = LargestUse(m, q);
        cell += Fixed(100.0 * use, 1) + " % (" + (who >= 0 ? m.actuator(who).name : std::string("-")) + ")";
        if (!m.Reachability(x, margin_fraction).empty()) cell += " beyond the margin";
      } else {
        cell += "not computable";
      }
      out += Padded(cell, 44);
    }
    out += "\n";
  }
  std::string axes;
  int count = 0;
  for (Dof dof : kAllDofs) {
    if (p.Has(dof) && m.Moves(dof) && std::isfinite(p.limits(dof).travel)) {
      axes += (axes.empty() ? "" : " x ") + std::string(DofName(dof));
      ++count;
    }
  }
  const int points = count <= 4 ? 11 : 7;
  out += "workspace: " + Fixed(100.0 * BoxShareReachable(p, margin_fraction, points), 1) + " % of the axis box (" +
         axes + ", " + std::to_string(points) + " points per axis) is reachable with a " +
         Short(100.0 * margin_fraction) + " % stroke margin\n";

  if (m.payload().mass > 0.0) {
    out += "static actuator forces holding the payload (share of the force limit):\n";
    std::vector<DofArray> poses{DofArray{}};
    for (Dof dof : kAllDofs) {
      if (!m.leg_axes()[static_cast<std::size_t>(Index(dof))] || !p.Has(dof)) continue;
      DofArray x{};
      x[static_cast<std::size_t>(Index(dof))] = p.limits(dof).travel;
      poses.push_back(x);
    }
    for (const DofArray& x : poses) {
      ActuatorVector f;
      out += "  " + Padded(PoseText(x) + ":", 22);
      if (!m.ActuatorForces(x, m.PayloadWrench(x), &f)) {
        out += " singular\n";
        continue;
      }
      for (int i = 0; i < m.actuator_count(); ++i) {
        const Actuator& a = m.actuator(i);
        out += " " + a.name + " " + Fixed(f[i], 1) + (a.kind == ActuatorKind::kRotary ? " N m" : " N");
        if (std::isfinite(a.limits.force)) out += " (" + Fixed(100.0 * std::abs(f[i]) / a.limits.force, 0) + " %)";
      }
      out += "\n";
    }
  }
  return out;
}

PlatformSpec ReadPlatformFile(const std::filesystem::path& file) {
  return ReadTaggedYamlFile(file, "pwsim-platform/1", ParsePlatform);
}

}  // namespace pwsim::mca
