#include "engine/circuit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "engine/check.h"
#include "engine/input_error.h"
#include "engine/interpolate.h"
#include "engine/number_format.h"
#include "engine/numeric_csv.h"

namespace pwsim {

double PointSegmentDistance(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double length2 = dx * dx + dy * dy;
  const double t = length2 > 0.0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / length2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
using Quad = std::array<Point2, 4>;

double Cross(Point2 o, Point2 a, Point2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

/// Parameters (ta, tb) of the crossing of segments a0-a1 and b0-b1; false when parallel.
bool SegmentCrossing(Point2 a0, Point2 a1, Point2 b0, Point2 b1, double& ta, double& tb) {
  const double rx = a1.x - a0.x, ry = a1.y - a0.y, sx = b1.x - b0.x, sy = b1.y - b0.y;
  const double denominator = rx * sy - ry * sx;
  if (std::abs(denominator) <= 1e-12 * (rx * rx + ry * ry + sx * sx + sy * sy)) return false;
  const double qx = b0.x - a0.x, qy = b0.y - a0.y;
  ta = (qx * sy - qy * sx) / denominator;
  tb = (qx * ry - qy * rx) / denominator;
  return true;
}

bool SegmentsCross(Point2 a0, Point2 a1, Point2 b0, Point2 b1) {
  double ta = 0.0, tb = 0.0;
  return SegmentCrossing(a0, a1, b0, b1, ta, tb) && ta >= 0.0 && ta <= 1.0 && tb >= 0.0 && tb <= 1.0;
}

Quad Rectangle(Point2 centre, double yaw, double front, double rear, double half_width) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const auto at = [&](double lx, double ly) { return Point2{centre.x + c * lx - s * ly, centre.y + s * lx + c * ly}; };
  return {at(front, half_width), at(rear, half_width), at(rear, -half_width), at(front, -half_width)};
}

Quad WallQuad(const Wall& wall) {
  const double dx = wall.to.x - wall.from.x, dy = wall.to.y - wall.from.y;
  const double length = std::hypot(dx, dy);
  const Point2 centre{0.5 * (wall.from.x + wall.to.x), 0.5 * (wall.from.y + wall.to.y)};
  return Rectangle(centre, std::atan2(dy, dx), 0.5 * length, -0.5 * length, 0.5 * wall.thickness);
}

/// Separating-axis test of two convex quadrilaterals.
bool QuadsOverlap(const Quad& a, const Quad& b) {
  for (const Quad* shape : {&a, &b}) {
    for (int i = 0; i < 4; ++i) {
      const Point2 p = (*shape)[i], q = (*shape)[(i + 1) % 4];
      const double nx = -(q.y - p.y), ny = q.x - p.x;
      double a_min = INFINITY, a_max = -INFINITY, b_min = INFINITY, b_max = -INFINITY;
      for (const Point2& v : a) {
        const double d = nx * v.x + ny * v.y;
        a_min = std::min(a_min, d);
        a_max = std::max(a_max, d);
      }
      for (const Point2& v : b) {
        const double d = nx * v.x + ny * v.y;
        b_min = std::min(b_min, d);
        b_max = std::max(b_max, d);
      }
      if (a_max < b_min || b_max < a_min) return false;
    }
  }
  return true;
}

bool QuadCircleOverlap(const Quad& quad, Point2 centre, double radius) {
  bool inside = true;
  for (int i = 0; i < 4; ++i) {
    if (PointSegmentDistance(centre, quad[i], quad[(i + 1) % 4]) <= radius) return true;
    if (Cross(quad[i], quad[(i + 1) % 4], centre) < 0.0) inside = false;
  }
  return inside;
}

Quad Footprint(const PlanarLayout& layout, const PlanarState& pose, double margin) {
  return Rectangle({pose.x, pose.y}, pose.yaw, layout.footprint_front + margin, layout.footprint_rear - margin,
                   layout.footprint_half_width + margin);
}

Point2 ReadPoint(YamlMap& map, const std::string& key) {
  const std::vector<double> p = map.Numbers(key, Range::Closed(-1000.0, 1000.0, "m"), 2, 2);
  return {p[0], p[1]};
}

std::string Describe(Point2 p) { return "[" + FormatDouble(p.x) + ", " + FormatDouble(p.y) + "]"; }

std::vector<Point2> ReadPointList(YamlMap& map, const std::string& key) {
  YAML::Node list = map.Sequence(key);
  const std::string field = map.FieldName(key);
  if (list.size() < 2) {
    throw InputError(map.file().string(), map.LineOfKey(key), field, "at least 2 [x_m, y_m] points",
                     std::to_string(list.size()) + " points");
  }
  std::vector<Point2> points;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string item = field + "[" + std::to_string(i) + "]";
    if (!list[i].IsSequence() || list[i].size() != 2) {
      throw InputError(map.file().string(), LineOf(list[i]), item, "a pair [x_m, y_m]", "something else");
    }
    points.push_back({ScalarNumber(list[i][0], map.file(), item + "[0]", Range::Closed(-1000.0, 1000.0, "m")),
                      ScalarNumber(list[i][1], map.file(), item + "[1]", Range::Closed(-1000.0, 1000.0, "m"))});
  }
  return points;
}

/// Inverse of ShapeDeflection: the deflection whose shaped value is `shaped` in [-1, 1].
double DeflectionFor(const ControllerProfile& profile, double shaped) {
  shaped = std::clamp(shaped, -1.0, 1.0);
  if (shaped == 0.0) return 0.0;
  double magnitude = std::abs(shaped);
  if (profile.exponent != 1.0) magnitude = std::pow(magnitude, 1.0 / profile.exponent);
  const double deflection = profile.deadband + (1.0 - profile.deadband) * magnitude;
  return shaped < 0.0 ? -deflection : deflection;
}

}  // namespace

JoystickInput JoystickSource::At(double time) const {
  if (t.empty()) return {};
  if (time <= t.front()) return {forward.front(), turn.front()};
  if (time >= t.back()) return {forward.back(), turn.back()};
  const KnotSegment segment = FindKnotSegment(t, time);
  if (hold) return {forward[segment.k], turn[segment.k]};
  return {Lerp(forward[segment.k], forward[segment.k + 1], segment.s),
          Lerp(turn[segment.k], turn[segment.k + 1], segment.s)};
}

JoystickInput DriveAlongPath(const JoystickSource& source, const ControllerProfile& profile,
                             DriverState& state, const FullChairSample& sample) {
  const std::vector<Point2>& path = source.path;
  if (state.finished || path.size() < 2) return {};
  const PlanarState& pose = sample.planar;
  const Point2 here{pose.x, pose.y};
  // Nearest point on the next few segments (the index never goes back).
  double best = INFINITY;
  std::size_t best_segment = state.segment;
  double best_t = 0.0;
  const std::size_t last = std::min(path.size() - 1, state.segment + 8);
  for (std::size_t k = state.segment; k < last; ++k) {
    const Point2 a = path[k], b = path[k + 1];
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double length2 = dx * dx + dy * dy;
    const double t = std::clamp(((here.x - a.x) * dx + (here.y - a.y) * dy) / length2, 0.0, 1.0);
    const double d = std::hypot(here.x - a.x - t * dx, here.y - a.y - t * dy);
    if (d < best) {
      best = d;
      best_segment = k;
      best_t = t;
    }
  }
  state.segment = best_segment;
  // Walk the look-ahead along the path; measure what is left.
  double remaining_lookahead = source.lookahead;
  std::size_t k = best_segment;
  double t = best_t;
  Point2 target = path.back();
  double remaining_path = 0.0;
  bool target_found = false;
  for (; k + 1 < path.size(); ++k, t = 0.0) {
    const Point2 a = path[k], b = path[k + 1];
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    const double left = (1.0 - t) * length;
    if (!target_found && left >= remaining_lookahead) {
      const double s = t + remaining_lookahead / length;
      target = {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)};
      target_found = true;
    } else if (!target_found) {
      remaining_lookahead -= left;
    }
    remaining_path += left;
  }
  double done = 0.0;
  for (std::size_t j = 0; j < best_segment; ++j) done += std::hypot(path[j + 1].x - path[j].x, path[j + 1].y - path[j].y);
  state.progress = done + best_t * std::hypot(path[best_segment + 1].x - path[best_segment].x,
                                              path[best_segment + 1].y - path[best_segment].y);
  if (remaining_path < 0.05) {
    state.finished = true;
    return {};
  }
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  const double dx = target.x - pose.x, dy = target.y - pose.y;
  const double ahead = c * dx + s * dy, left = -s * dx + c * dy;
  const double distance = std::max(std::hypot(ahead, left), 1e-6);
  const double bearing = std::atan2(left, ahead);
  const double curvature = 2.0 * std::sin(bearing) / distance;
  // Slow down for the end of the path and for large heading errors.
  const double brake = std::sqrt(2.0 * profile.forward_decel * 0.5 * remaining_path);
  double v_ref = std::min(source.speed, brake) * std::clamp(std::cos(bearing), 0.2, 1.0);
  v_ref = std::min(v_ref, profile.max_forward_speed);
  const double f_shaped = (v_ref + source.speed_gain * (v_ref - pose.v)) / profile.max_forward_speed;
  const double w_cmd = curvature * std::max(pose.v, 0.5 * v_ref);
  const double w_avail =
      profile.max_turn_rate * (1.0 - (1.0 - profile.turn_rate_at_speed) * std::min(1.0, v_ref / profile.max_forward_speed));
  JoystickInput input;
  input.forward = DeflectionFor(profile, std::clamp(f_shaped, 0.0, 1.0));
  input.turn = DeflectionFor(profile, w_cmd / (w_avail * profile.turn_gain));
  return input;
}

JoystickSource ReadRecordedJoystick(const std::filesystem::path& file) {
  const NumericCsv csv = ReadNumericCsv(
      file, {"t_s", "forward", "turn"}, [](std::size_t k, double value, const NumericCsv& so_far) -> std::string {
        const std::vector<double>& t = so_far.columns[0];
        if (k == 0 && value < 0.0) return "t_s >= 0";
        if (k == 0 && !t.empty() && !(value > t.back())) return "t_s rising strictly";
        if (k > 0 && (value < -1.0 || value > 1.0)) return "a deflection in [-1, 1]";
        return "";
      });
  JoystickSource source;
  source.kind = JoystickSource::Kind::kRecorded;
  source.recorded_file = file;
  source.t = csv.columns[0];
  source.forward = csv.columns[1];
  source.turn = csv.columns[2];
  source.end_time = source.t.back();
  return source;
}

int FootprintHit(const CircuitSpec& circuit, const PlanarState& pose, double margin) {
  const Quad footprint = Footprint(circuit.layout, pose, margin);
  for (std::size_t i = 0; i < circuit.walls.size(); ++i) {
    if (QuadsOverlap(footprint, WallQuad(circuit.walls[i]))) return static_cast<int>(i);
  }
  for (std::size_t i = 0; i < circuit.obstacles.size(); ++i) {
    const Obstacle& o = circuit.obstacles[i];
    const bool hit = o.shape == Obstacle::Shape::kCircle
                         ? QuadCircleOverlap(footprint, o.centre, o.radius)
                         : QuadsOverlap(footprint, Rectangle(o.centre, o.yaw, o.half_length, -o.half_length, o.half_width));
    if (hit) return static_cast<int>(circuit.walls.size() + i);
  }
  return -1;
}

CircuitSpec ParseCircuit(YamlMap& map, const Chair& chair, double load_kg) {
  CircuitSpec circuit;
  (void)load_kg;
  const std::string file = map.file().string();
  circuit.duration = map.Number("duration_s", Range::Positive(3600.0, "s"));
  if (map.Has("start")) {
    YamlMap start = map.Map("start");
    const Point2 p = ReadPoint(start, "position_m");
    circuit.start.x = p.x;
    circuit.start.y = p.y;
    circuit.start.yaw = kDeg * start.NumberOr("yaw_deg", 0.0, Range::Closed(-360.0, 360.0, "deg"));
    circuit.start_caster_angle = kDeg * start.NumberOr("caster_deg", 0.0, Range::Closed(-180.0, 180.0, "deg"));
    start.Finish();
  }
  if (map.Has("chair_layout")) {
    YamlMap layout = map.Map("chair_layout");
    circuit.layout = ParsePlanarLayout(layout, chair);
    layout.Finish();
  } else {
    circuit.layout = DefaultPlanarLayout(chair);
  }
  if (map.Has("controller")) {  // the profile may also sit at the circuit's top level
    YamlMap controller = map.Map("controller");
    circuit.layout.controller = ParseControllerProfile(controller);
    controller.Finish();
  }
  if (map.Has("roll_torque")) {
    YamlMap roll = map.Map("roll_torque");
    const bool rigid = roll.BoolOr("rigid_load", true);
    const double lever = MovingMass(chair, load_kg) * chair.cm_height;
    circuit.roll_torque.gravity_lever = rigid ? lever : 0.0;
    circuit.roll_torque.per_lateral_accel = rigid ? lever : 0.0;
    circuit.roll_torque.constant = roll.NumberOr("constant_nm", 0.0, Range::Closed(-1e4, 1e4, "N m"));
    roll.Finish();
  } else {
    const double lever = MovingMass(chair, load_kg) * chair.cm_height;
    circuit.roll_torque.gravity_lever = lever;
    circuit.roll_torque.per_lateral_accel = lever;
  }
  if (map.Has("floor")) {
    YamlMap floor = map.Map("floor");
    circuit.floor = ParseFloorMap(floor);
    floor.Finish();
  }
  if (map.Has("walls")) {
    YAML::Node list = map.Sequence("walls");
    for (std::size_t i = 0; i < list.size(); ++i) {
      YamlMap w(list[i], map.file(), map.FieldName("walls") + "[" + std::to_string(i) + "]", LineOf(list[i]));
      Wall wall;
      wall.name = w.StringOr("name", "wall " + std::to_string(i));
      wall.from = ReadPoint(w, "from_m");
      wall.to = ReadPoint(w, "to_m");
      wall.thickness = w.NumberOr("thickness_m", 0.1, Range::Closed(0.02, 2.0, "m"));
      if (std::hypot(wall.to.x - wall.from.x, wall.to.y - wall.from.y) < 0.01) {
        w.Fail("to_m", "a wall at least 0.01 m long", Describe(wall.to) + " = from_m");
      }
      w.Finish();
      // Overlapping walls: crossing inside both, or collinear and sharing a stretch.
      for (std::size_t j = 0; j < circuit.walls.size(); ++j) {
        const Wall& other = circuit.walls[j];
        double ta = 0.0, tb = 0.0;
        const double la = std::hypot(wall.to.x - wall.from.x, wall.to.y - wall.from.y);
        const double lb = std::hypot(other.to.x - other.from.x, other.to.y - other.from.y);
        const double margin_a = 0.5 * other.thickness / la, margin_b = 0.5 * wall.thickness / lb;
        bool overlap = false;
        if (SegmentCrossing(wall.from, wall.to, other.from, other.to, ta, tb)) {
          overlap = ta > margin_a && ta < 1.0 - margin_a && tb > margin_b && tb < 1.0 - margin_b;
        } else {
          const double gap = PointSegmentDistance(wall.from, other.from, other.to);
          const double ux = (other.to.x - other.from.x) / lb, uy = (other.to.y - other.from.y) / lb;
          const double p0 = (wall.from.x - other.from.x) * ux + (wall.from.y - other.from.y) * uy;
          const double p1 = (wall.to.x - other.from.x) * ux + (wall.to.y - other.from.y) * uy;
          const double shared = std::min(std::max(p0, p1), lb) - std::max(std::min(p0, p1), 0.0);
          const double line_gap = std::abs(-(wall.from.x - other.from.x) * uy + (wall.from.y - other.from.y) * ux);
          overlap = line_gap < 0.5 * (wall.thickness + other.thickness) && shared > 0.5 * (wall.thickness + other.thickness);
          (void)gap;
        }
        if (overlap) {
          throw InputError(file, LineOf(list[i]), map.FieldName("walls") + "[" + std::to_string(i) + "]",
                           "walls that meet only at their ends (no wall overlapping another)",
                           "'" + wall.name + "' overlaps '" + other.name + "'");
        }
      }
      circuit.walls.push_back(wall);
    }
  }
  if (map.Has("obstacles")) {
    YAML::Node list = map.Sequence("obstacles");
    for (std::size_t i = 0; i < list.size(); ++i) {
      YamlMap o(list[i], map.file(), map.FieldName("obstacles") + "[" + std::to_string(i) + "]", LineOf(list[i]));
      Obstacle obstacle;
      obstacle.name = o.StringOr("name", "obstacle " + std::to_string(i));
      obstacle.centre = ReadPoint(o, "centre_m");
      obstacle.height = o.NumberOr("height_m", obstacle.height, Range::Positive(5.0, "m"));
      const std::string shape = o.Choice("shape", {"circle", "box"});
      if (shape == "circle") {
        obstacle.shape = Obstacle::Shape::kCircle;
        obstacle.radius = o.Number("radius_m", Range::Positive(10.0, "m"));
      } else {
        obstacle.shape = Obstacle::Shape::kBox;
        const std::vector<double> size = o.Numbers("size_m", Range::Positive(50.0, "m"), 2, 2);
        obstacle.half_length = 0.5 * size[0];
        obstacle.half_width = 0.5 * size[1];
        obstacle.yaw = kDeg * o.NumberOr("yaw_deg", 0.0, Range::Closed(-360.0, 360.0, "deg"));
      }
      o.Finish();
      circuit.obstacles.push_back(obstacle);
    }
  }
  if (map.Has("gates")) {
    YAML::Node list = map.Sequence("gates");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string field = map.FieldName("gates") + "[" + std::to_string(i) + "]";
      YamlMap g(list[i], map.file(), field, LineOf(list[i]));
      Gate gate;
      gate.name = g.StringOr("name", "gate " + std::to_string(i + 1));
      gate.left = ReadPoint(g, "left_m");
      gate.right = ReadPoint(g, "right_m");
      g.Finish();
      for (const Wall& wall : circuit.walls) {
        if (SegmentsCross(gate.left, gate.right, wall.from, wall.to)) {
          throw InputError(file, LineOf(list[i]), field, "a gate whose posts do not span a wall",
                           "'" + gate.name + "' crosses '" + wall.name + "'");
        }
      }
      // the route: start, then each gate's middle; no leg may pass through a wall
      const Point2 from = circuit.gates.empty()
                              ? Point2{circuit.start.x, circuit.start.y}
                              : Point2{0.5 * (circuit.gates.back().left.x + circuit.gates.back().right.x),
                                       0.5 * (circuit.gates.back().left.y + circuit.gates.back().right.y)};
      const Point2 to{0.5 * (gate.left.x + gate.right.x), 0.5 * (gate.left.y + gate.right.y)};
      for (const Wall& wall : circuit.walls) {
        if (SegmentsCross(from, to, wall.from, wall.to)) {
          throw InputError(file, LineOf(list[i]), field,
                           "a route whose legs (start, then gate middles in order) pass no wall",
                           "the leg " + Describe(from) + " to " + Describe(to) + " goes through '" + wall.name + "'");
        }
      }
      circuit.gates.push_back(gate);
    }
  }

  YamlMap joystick = map.Map("joystick");
  const int sources = joystick.Has("table") + joystick.Has("csv") + joystick.Has("driver");
  if (sources != 1) {
    joystick.Fail(joystick.Has("table") ? "table" : "driver", "exactly one of table, csv or driver",
                  std::to_string(sources) + " of them");
  }
  JoystickSource& source = circuit.joystick;
  if (joystick.Has("table")) {
    source.kind = JoystickSource::Kind::kTable;
    source.hold = joystick.BoolOr("hold", false);
    YAML::Node rows = joystick.Sequence("table");
    const std::string field = joystick.FieldName("table");
    if (rows.size() < 1) throw InputError(file, joystick.LineOfKey("table"), field, "at least one [t_s, forward, turn] row", "none");
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::string item = field + "[" + std::to_string(i) + "]";
      if (!rows[i].IsSequence() || rows[i].size() != 3) {
        throw InputError(file, LineOf(rows[i]), item, "a row [t_s, forward, turn]", "something else");
      }
      const double t = ScalarNumber(rows[i][0], map.file(), item + "[0]", Range::Closed(0.0, 3600.0, "s"));
      if (!source.t.empty() && !(t > source.t.back())) {
        throw InputError(file, LineOf(rows[i]), item + "[0]", "t_s rising strictly", FormatDouble(t));
      }
      source.t.push_back(t);
      source.forward.push_back(ScalarNumber(rows[i][1], map.file(), item + "[1]", Range::Closed(-1.0, 1.0, "(deflection)")));
      source.turn.push_back(ScalarNumber(rows[i][2], map.file(), item + "[2]", Range::Closed(-1.0, 1.0, "(deflection)")));
    }
    source.end_time = source.t.back();
  } else if (joystick.Has("csv")) {
    const std::string relative = joystick.String("csv");
    const std::filesystem::path target = ResolveRelative(map.file(), relative);
    if (!std::filesystem::exists(target)) {
      joystick.Fail("csv", "a path to an existing CSV file", "\"" + relative + "\" (" + target.string() + " does not exist)");
    }
    const bool hold = joystick.BoolOr("hold", false);
    source = ReadRecordedJoystick(target);
    source.hold = hold;
  } else {
    YamlMap driver = joystick.Map("driver");
    source.kind = JoystickSource::Kind::kDriver;
    source.speed = driver.Number("speed_mps", Range::Positive(3.0, "m/s"));
    source.lookahead = driver.NumberOr("lookahead_m", source.lookahead, Range::Closed(0.1, 5.0, "m"));
    source.speed_gain = driver.NumberOr("speed_gain", source.speed_gain, Range::Closed(0.0, 10.0));
    if (driver.Has("path_m")) {
      source.path = ReadPointList(driver, "path_m");
    } else {
      if (circuit.gates.empty()) driver.Fail("path_m", "a path_m, or gates to drive through", "neither");
      source.path.push_back({circuit.start.x, circuit.start.y});
      for (const Gate& gate : circuit.gates) {
        source.path.push_back({0.5 * (gate.left.x + gate.right.x), 0.5 * (gate.left.y + gate.right.y)});
      }
      // run out 1 m beyond the last gate, square to it
      const Gate& last = circuit.gates.back();
      const double gx = last.right.x - last.left.x, gy = last.right.y - last.left.y;
      const double length = std::hypot(gx, gy);
      source.path.push_back({source.path.back().x - gy / length, source.path.back().y + gx / length});
    }
    for (std::size_t k = 0; k + 1 < source.path.size(); ++k) {
      if (source.path[k].x == source.path[k + 1].x && source.path[k].y == source.path[k + 1].y) {
        driver.Fail("path_m", "a path without repeated points", "point " + std::to_string(k + 1) + " repeats");
      }
      for (const Wall& wall : circuit.walls) {
        if (SegmentsCross(source.path[k], source.path[k + 1], wall.from, wall.to)) {
          driver.Fail(driver.Has("path_m") ? "path_m" : "speed_mps", "a path that passes no wall",
                      "the leg " + Describe(source.path[k]) + " to " + Describe(source.path[k + 1]) +
                          " goes through '" + wall.name + "'");
        }
      }
    }
    driver.Finish();
  }
  joystick.Finish();

  const int hit = FootprintHit(circuit, circuit.start);
  if (hit >= 0) {
    const std::string what = hit < static_cast<int>(circuit.walls.size())
                                 ? "'" + circuit.walls[hit].name + "'"
                                 : "'" + circuit.obstacles[hit - circuit.walls.size()].name + "'";
    map.Fail("start", "a start pose clear of every wall and obstacle", "the chair's footprint overlaps " + what);
  }
  return circuit;
}

CircuitRunner::CircuitRunner(const Chair& chair, const CircuitSpec& circuit, double load_kg, double dt,
                             PitchTorqueParams pitch_torque)
    : circuit_(circuit),
      simulator_(chair, circuit.layout, circuit.floor, load_kg, dt, pitch_torque, circuit.roll_torque) {}

const FullChairSample& CircuitRunner::Start() {
  driver_ = DriverState{};
  in_contact_ = false;
  contact_events_ = 0;
  last_contact_speed_ = 0.0;
  gates_passed_ = 0;
  return simulator_.Start(circuit_.start, circuit_.start_caster_angle);
}

const FullChairSample& CircuitRunner::Advance(double time) {
  const JoystickInput joystick = circuit_.joystick.kind == JoystickSource::Kind::kDriver
                                     ? DriveAlongPath(circuit_.joystick, circuit_.layout.controller, driver_,
                                                      simulator_.sample())
                                     : circuit_.joystick.At(time);
  return AdvanceWith(joystick);
}

const FullChairSample& CircuitRunner::AdvanceWith(const JoystickInput& joystick) {
  const PlanarState before = simulator_.sample().planar;
  const FullChairSample& next = simulator_.Advance(joystick);
  const PlanarState after = next.planar;
  if (FootprintHit(circuit_, after) >= 0) {
    // The chair stops at the wall: the step is not taken; a contact is counted when it begins.
    if (!in_contact_) {
      ++contact_events_;
      last_contact_speed_ = std::hypot(after.x - before.x, after.y - before.y) / simulator_.dt();
    }
    in_contact_ = true;
    simulator_.OverridePlanar({before.x, before.y, before.yaw, 0.0, 0.0});
  } else {
    if (in_contact_ && FootprintHit(circuit_, after, kContactReleaseGap) < 0) in_contact_ = false;
    if (gates_passed_ < static_cast<int>(circuit_.gates.size())) {
      const Gate& gate = circuit_.gates[gates_passed_];
      if (SegmentsCross({before.x, before.y}, {after.x, after.y}, gate.left, gate.right)) ++gates_passed_;
    }
  }
  simulator_.SetCircuitStatus(in_contact_, contact_events_, last_contact_speed_, gates_passed_);
  return simulator_.sample();
}

}  // namespace pwsim
