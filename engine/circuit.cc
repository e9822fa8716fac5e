#include "engine/circuit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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

Point2 ContactNormal(const CircuitSpec& circuit, int hit, const PlanarState& pose) {
  const PlanarLayout& layout = circuit.layout;
  const double mid = 0.5 * (layout.footprint_front + layout.footprint_rear);
  const Point2 c{pose.x + mid * std::cos(pose.yaw), pose.y + mid * std::sin(pose.yaw)};  // the footprint's centre
  const auto unit = [](double x, double y) {
    const double length = std::hypot(x, y);
    return length > 0.0 ? Point2{x / length, y / length} : Point2{1.0, 0.0};
  };
  const int walls = static_cast<int>(circuit.walls.size());
  if (hit < walls) {
    const Wall& w = circuit.walls[static_cast<std::size_t>(hit)];
    const double dx = w.to.x - w.from.x, dy = w.to.y - w.from.y;
    const double along = ((c.x - w.from.x) * dx + (c.y - w.from.y) * dy) / (dx * dx + dy * dy);
    if (along < 0.0) return unit(c.x - w.from.x, c.y - w.from.y);  // round the wall's end
    if (along > 1.0) return unit(c.x - w.to.x, c.y - w.to.y);
    const Point2 n = unit(-dy, dx);
    return (c.x - w.from.x) * n.x + (c.y - w.from.y) * n.y >= 0.0 ? n : Point2{-n.x, -n.y};
  }
  const Obstacle& o = circuit.obstacles[static_cast<std::size_t>(hit - walls)];
  if (o.shape == Obstacle::Shape::kCircle) return unit(c.x - o.centre.x, c.y - o.centre.y);
  // a box: the face the centre lies beyond the most, relative to the box's half sizes
  const double co = std::cos(o.yaw), so = std::sin(o.yaw);
  const double lx = co * (c.x - o.centre.x) + so * (c.y - o.centre.y);
  const double ly = -so * (c.x - o.centre.x) + co * (c.y - o.centre.y);
  if (std::abs(lx) / o.half_length >= std::abs(ly) / o.half_width) {
    const double s = lx >= 0.0 ? 1.0 : -1.0;
    return {s * co, s * so};
  }
  const double s = ly >= 0.0 ? 1.0 : -1.0;
  return {-s * so, s * co};
}

CircuitSpec ParseCircuit(YamlMap& map, const Chair& chair, double load_kg) {
  CircuitSpec circuit;
  (void)load_kg;
  const std::string file = map.file().string();
  circuit.duration = map.Number("duration_s", Range::Positive(3600.0, "s"));
  circuit.wall_friction = map.NumberOr("wall_friction", circuit.wall_friction, Range::Closed(0.0, 2.0));
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

namespace {

/// Peak responses of one base-excited axis J ẍ = C (ẏ − ẋ) + K (y − x) + Γ (ComputeHeadForceBound,
/// link 5) to a unit step of the base's rate (y = t) and to a unit step of Γ, integrated by RK4
/// at 1/1000 of a radian until e^-40 of the decay.
struct AxisGains {
  double rate_to_rate{1.0};      ///< max |ẋ| / ẏ (the overshoot) [-]
  double rate_to_accel{0.0};     ///< max |ẍ| / ẏ (C/J at the step) [1/s]
  double torque_to_rate{0.0};    ///< max |ẋ| / Γ [1/(kg m² s) s]
  double torque_to_accel{0.0};   ///< max |ẍ| / Γ (1/J at the step)
};

AxisGains GainsOf(double inertia, double damping, double stiffness) {
  AxisGains gains;
  if (!(damping > 0.0 && stiffness > 0.0 && inertia > 0.0)) {
    const double inf = std::numeric_limits<double>::infinity();
    return {inf, inf, inf, inf};
  }
  const double omega = std::sqrt(stiffness / inertia);
  const double zeta = damping / (2.0 * std::sqrt(stiffness * inertia));
  const double h = 1e-3 / omega;
  const long steps = static_cast<long>(40.0 / (zeta * omega) / h) + 1;
  // x relative to the base (e = x − y, ė = ẋ − ẏ), base rate `rate` and torque `torque` held:
  // ë = (−C ė − K e + Γ) / J; the absolute ẋ = ė + rate, ẍ = ë
  const auto peaks = [&](double rate, double torque, double& rate_peak, double& accel_peak) {
    double e = 0.0, de = -rate;  // at 0+: the body still, the base moving
    const auto accel = [&](double ee, double dd) { return (-damping * dd - stiffness * ee + torque) / inertia; };
    rate_peak = 0.0;
    accel_peak = std::abs(accel(e, de));
    for (long k = 0; k < steps; ++k) {
      const double a1 = accel(e, de);
      const double e2 = e + 0.5 * h * de, d2 = de + 0.5 * h * a1, a2 = accel(e2, d2);
      const double e3 = e + 0.5 * h * d2, d3 = de + 0.5 * h * a2, a3 = accel(e3, d3);
      const double e4 = e + h * d3, d4 = de + h * a3, a4 = accel(e4, d4);
      e += h / 6.0 * (de + 2.0 * d2 + 2.0 * d3 + d4);
      de += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
      rate_peak = std::max(rate_peak, std::abs(de + rate));
      accel_peak = std::max(accel_peak, std::abs(accel(e, de)));
    }
  };
  peaks(1.0, 0.0, gains.rate_to_rate, gains.rate_to_accel);
  peaks(0.0, 1.0, gains.torque_to_rate, gains.torque_to_accel);
  return gains;
}

/// Steepest slope of the envelope of a wheel of radius R over an edge of height h (tan β, where
/// the disc first touches the edge); ∞ at h >= R or for a point (R = 0).
double EdgeSlope(double h, double radius) {
  h = std::abs(h);
  if (h == 0.0) return 0.0;
  if (!(radius > h)) return std::numeric_limits<double>::infinity();
  return std::sqrt(2.0 * radius * h - h * h) / (radius - h);
}

/// A rise of h over a taper r taken by that wheel: min(h / r, tan β).
double RiseSlope(double h, double ramp, double radius) {
  const double taper = ramp > 0.0 ? std::abs(h) / ramp : std::numeric_limits<double>::infinity();
  return std::min(taper, EdgeSlope(h, radius));
}

bool Overlap(const FloorFeature& a, const FloorFeature& b) {
  return a.x_min < b.x_max && b.x_min < a.x_max && a.y_min < b.y_max && b.y_min < a.y_max;
}

/// max |plane value| over its rectangle [m].
double PlaneRise(const FloorFeature& f) {
  const double xc = f.has_origin ? f.origin_x : 0.5 * (f.x_min + f.x_max);
  const double yc = f.has_origin ? f.origin_y : 0.5 * (f.y_min + f.y_max);
  return std::abs(f.grade_x) * std::max(std::abs(f.x_max - xc), std::abs(f.x_min - xc)) +
         std::abs(f.grade_y) * std::max(std::abs(f.y_max - yc), std::abs(f.y_min - yc));
}

}  // namespace

HeadForceBound ComputeHeadForceBound(const Chair& chair, const CircuitSpec& circuit, double load_kg,
                                     PitchTorqueParams pitch_torque, const std::array<double, 3>& head_offset,
                                     double peak_speed, double peak_yaw_rate) {
  PWSIM_DEMAND(chair.gm.has_value() && chair.lm.has_value());
  const double g = kStandardGravity;
  const PlanarLayout& layout = circuit.layout;
  const FloorMap& floor = circuit.floor;
  const int rows = chair.wheel_count();
  HeadForceBound bound;

  // the floor: its grades, its highest bump
  double grade = 0.0, bump_max = 0.0;
  for (const FloorFeature& f : floor.features) {
    if (f.kind == FloorFeature::Kind::kPlane) {
      grade += std::hypot(f.grade_x, f.grade_y);
    } else {
      bump_max = std::max(bump_max, std::abs(f.height));
    }
  }
  double profile_slope = 0.0, profile_range = 0.0;
  const Terrain& p = floor.profile;
  for (std::size_t k = 0; k + 1 < p.x.size(); ++k) profile_slope = std::max(profile_slope, std::abs((p.z[k + 1] - p.z[k]) / (p.x[k + 1] - p.x[k])));
  for (double z : p.z) profile_range = std::max(profile_range, std::abs(z));
  double grid_slope = 0.0, grid_range = 0.0;
  if (floor.grid) {
    const HeightGrid& grid = *floor.grid;
    for (int j = 0; j < grid.ny; ++j) {
      for (int i = 0; i < grid.nx; ++i) {
        const double z = grid.z[static_cast<std::size_t>(j * grid.nx + i)];
        grid_range = std::max(grid_range, std::abs(z));
        if (i + 1 < grid.nx) grid_slope = std::max(grid_slope, std::abs(grid.z[static_cast<std::size_t>(j * grid.nx + i + 1)] - z) / grid.cell);
        if (j + 1 < grid.ny) grid_slope = std::max(grid_slope, std::abs(grid.z[static_cast<std::size_t>((j + 1) * grid.nx + i)] - z) / grid.cell);
      }
    }
  }
  grade += profile_slope;

  // 1. wheel speed over the floor
  int drive_row = 0;
  for (int i = 0; i < rows; ++i) {
    if (layout.rows[static_cast<std::size_t>(i)].role == WheelRole::kDrive) drive_row = i;
  }
  const double drive_x = chair.wheels[static_cast<std::size_t>(drive_row)].x;
  double reach = 0.0;
  for (int i = 0; i < rows; ++i) {
    const WheelRow& row = layout.rows[static_cast<std::size_t>(i)];
    const double trail = row.role == WheelRole::kCaster ? layout.caster.trail : 0.0;
    reach = std::max(reach, std::hypot(std::abs(chair.wheels[static_cast<std::size_t>(i)].x - drive_x) + trail, row.half_track));
  }
  bound.wheel_speed = peak_speed + peak_yaw_rate * reach;

  // 2.-3. per row: the steepest envelope and the contact's vertical speed through the tyre
  for (int i = 0; i < rows; ++i) {
    const WheelRow& row = layout.rows[static_cast<std::size_t>(i)];
    const double radius = layout.rolling_envelope ? chair.wheels[static_cast<std::size_t>(i)].radius : 0.0;
    double bumps = 0.0, planes = 0.0;
    for (std::size_t a = 0; a < floor.features.size(); ++a) {
      const FloorFeature& f = floor.features[a];
      if (f.kind == FloorFeature::Kind::kPlane) {
        const double edge = PlaneRise(f);
        planes += std::hypot(f.grade_x, f.grade_y) + (edge > 0.0 ? RiseSlope(edge, f.ramp, radius) : 0.0);
        continue;
      }
      double here = RiseSlope(f.height, f.ramp, radius);
      for (std::size_t b = 0; b < floor.features.size(); ++b) {
        const FloorFeature& o = floor.features[b];
        if (b != a && o.kind == FloorFeature::Kind::kBump && Overlap(f, o)) here += RiseSlope(o.height, o.ramp, radius);
      }
      bumps = std::max(bumps, here);
    }
    double grid_edge = 0.0;
    if (floor.grid) grid_edge = EdgeSlope(grid_range, radius) + grid_slope;
    const double profile_edge = p.x.empty() ? 0.0 : EdgeSlope(std::max(std::abs(p.z.front()), std::abs(p.z.back())), radius);
    const double slope = bumps + planes + profile_slope + profile_edge + grid_edge;
    bound.envelope_slope.push_back(slope);
    const double period = !layout.rolling_envelope ? 0.0
                          : row.role == WheelRole::kDrive ? layout.drive_tyre_period : layout.caster_tyre_period;
    double tyre_gain = 1.0;
    if (period > 0.0) {
      const double omega = 2.0 * std::numbers::pi / period;
      tyre_gain = GainsOf(1.0, 2.0 * layout.tyre_damping * omega, omega * omega).rate_to_rate;
    }
    // a wheel leaves an edge where its centre's arc asks more than g (v² / R > g): free fall
    const bool flies = bound.wheel_speed * bound.wheel_speed > g * radius;
    bound.contact_rate.push_back(std::max(tyre_gain * bound.wheel_speed * slope, flies ? std::sqrt(2.0 * g * bump_max) : 0.0));
  }

  // 4. the GM's rates, one wheel row meeting an edge at a time
  const std::vector<double>& alpha = chair.gm->alpha;
  double track_min = std::numeric_limits<double>::infinity();
  for (int i = 0; i < rows; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const double rate = bound.contact_rate[u];
    if (alpha[u] != 0.0) bound.gm_z_rate = std::max(bound.gm_z_rate, std::abs(alpha[u]) * rate);
    double pitch_rate = 0.0;
    for (const PairWeight& pair : chair.gm->beta) {
      if ((pair.i != i && pair.j != i) || pair.weight == 0.0) continue;
      const double dx = std::abs(chair.wheels[static_cast<std::size_t>(pair.i)].x - chair.wheels[static_cast<std::size_t>(pair.j)].x);
      const double s = std::min(0.99, grade + bump_max / dx);
      pitch_rate += std::abs(pair.weight) * rate / (dx * std::sqrt(1.0 - s * s));
    }
    bound.gm_pitch_rate = std::max(bound.gm_pitch_rate, pitch_rate);
    const WheelRow& row = layout.rows[u];
    const double w = 2.0 * row.half_track;
    track_min = std::min(track_min, w);
    const double s = std::min(0.99, grade + bump_max / w);
    if (row.roll_weight != 0.0) bound.gm_roll_rate = std::max(bound.gm_roll_rate, std::abs(row.roll_weight) * rate / (w * std::sqrt(1.0 - s * s)));
  }

  // 6. the planar motion (before 5: the torques follow the accelerations)
  const double mass = MovingMass(chair, load_kg);
  const double e = layout.cm_x - drive_x;
  const double yaw_inertia = layout.yaw_inertia * mass / chair.mass + mass * e * e;
  const double track = 2.0 * layout.rows[static_cast<std::size_t>(drive_row)].half_track;
  const double a_x = layout.friction * g + g * grade + (layout.caster.rolling_resistance + layout.rolling_resistance) * g +
                     std::abs(e) * peak_yaw_rate * peak_yaw_rate;
  bound.yaw_accel = layout.friction * mass * g * track / yaw_inertia;
  const double a_y = peak_speed * peak_yaw_rate + std::abs(drive_x) * bound.yaw_accel;
  bound.planar_accel = std::hypot(a_x, a_y);

  // 5. the LM axes
  const LumpedModelParams lm = MakeLumpedModelParams(chair, load_kg);
  const AxisGains heave = GainsOf(lm.heave.inertia, lm.heave.damping, lm.heave.stiffness);
  const AxisGains pitch = GainsOf(lm.pitch.inertia, lm.pitch.damping, lm.pitch.stiffness);
  const AxisGains roll = GainsOf(layout.roll_inertia + chair.cm_height * chair.cm_height * mass, layout.c_roll, layout.k_roll);
  const double roll_floor = std::asin(std::min(1.0, (bump_max + grid_range) / track_min)) + std::atan(grade);
  const double pitch_torque_dev = std::abs(pitch_torque.per_accel) * a_x;
  const double roll_torque_dev = std::abs(circuit.roll_torque.per_lateral_accel) * a_y +
                                 std::abs(circuit.roll_torque.gravity_lever) * g * std::sin(std::min(roll_floor, std::numbers::pi / 2));
  bound.heave_accel = heave.rate_to_accel * bound.gm_z_rate;
  bound.pitch_accel = pitch.rate_to_accel * bound.gm_pitch_rate + pitch.torque_to_accel * pitch_torque_dev;
  bound.pitch_rate = pitch.rate_to_rate * bound.gm_pitch_rate + pitch.torque_to_rate * pitch_torque_dev;
  bound.roll_accel = roll.rate_to_accel * bound.gm_roll_rate + roll.torque_to_accel * roll_torque_dev;
  bound.roll_rate = roll.rate_to_rate * bound.gm_roll_rate + roll.torque_to_rate * roll_torque_dev;

  // 7. the head
  const double wheelbase = std::abs(chair.wheels.front().x - chair.wheels.back().x);
  const double pitch_floor = std::asin(std::min(1.0, (bump_max + grid_range) / wheelbase)) + std::atan(grade);
  bound.tilt = pitch.rate_to_rate * pitch_floor + roll.rate_to_rate * roll_floor;
  const double r = std::sqrt(head_offset[0] * head_offset[0] + head_offset[1] * head_offset[1] + head_offset[2] * head_offset[2]);
  const double r_h = std::hypot(head_offset[0], head_offset[1]);
  // |Ω|² = φ̇² + θ̇² + ω² to first order in the tilts
  const double spin2 = bound.roll_rate * bound.roll_rate + bound.pitch_rate * bound.pitch_rate + peak_yaw_rate * peak_yaw_rate;
  bound.total = bound.planar_accel + bound.heave_accel + r * (bound.roll_accel + bound.pitch_accel + spin2) +
                r_h * bound.yaw_accel + g * bound.tilt;
  return bound;
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
  const int hit = FootprintHit(circuit_, after);
  if (hit >= 0) {
    // The step is not taken as it was: the wall takes O_V's speed toward it (an inelastic
    // impact) and, by Coulomb friction, μ_w times that from its speed along it (header).
    const double dt = simulator_.dt();
    const Point2 n = ContactNormal(circuit_, hit, before);
    const double ux = (after.x - before.x) / dt, uy = (after.y - before.y) / dt;
    const double normal = ux * n.x + uy * n.y;  // < 0: toward the wall
    const double along = -ux * n.y + uy * n.x;  // along t = (-n_y, n_x)
    const double lost = normal < 0.0 ? -normal : 0.0;
    const double slide = std::copysign(std::max(0.0, std::abs(along) - circuit_.wall_friction * lost), along);
    if (!in_contact_) {
      ++contact_events_;
      last_contact_speed_ = lost;
    }
    in_contact_ = true;
    const PlanarState slid{before.x - slide * n.y * dt, before.y + slide * n.x * dt, before.yaw, 0.0, 0.0};
    if (slide != 0.0 && FootprintHit(circuit_, slid) < 0) {
      // it slides along: O_V moved along t; the drive wheels keep their speed (they slip)
      PlanarState sliding = slid;
      sliding.v = after.v;
      simulator_.OverridePlanar(sliding);
    } else {
      simulator_.OverridePlanar({before.x, before.y, before.yaw, 0.0, 0.0});  // it stops at the wall
    }
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
