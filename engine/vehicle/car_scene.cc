#include "engine/vehicle/car_scene.h"

#include <cmath>

#include "engine/input_error.h"
#include "engine/number_format.h"
#include "engine/yaml_reader.h"

namespace pwsim::vehicle {

const SceneSection* CarScene::section(const std::string& key) const {
  const auto found = sections.find(key);
  return found == sections.end() ? nullptr : &found->second;
}

std::string SceneKind(const std::filesystem::path& file) { return SceneKind(LoadYamlFile(file)); }

std::string SceneKind(const YamlDocument& document) {
  YamlMap root(document.root, document.file, "");
  if (!root.Has("kind")) return "wheelchair";
  return root.Choice("kind", {"wheelchair", "car"});
}

std::vector<PathPoint> RoutePolyline(const std::vector<RouteItem>& route, double x0, double y0,
                                     double heading0, double spacing) {
  std::vector<PathPoint> points{{x0, y0}};
  double x = x0, y = y0, heading = heading0;
  for (const RouteItem& item : route) {
    if (item.turn == 0.0) {
      const int n = std::max(1, static_cast<int>(std::ceil(item.straight / spacing)));
      const double step = item.straight / n;
      for (int k = 0; k < n; ++k) {
        x += step * std::cos(heading);
        y += step * std::sin(heading);
        points.push_back({x, y});
      }
    } else {
      const double length = std::abs(item.turn) * item.radius;
      const int n = std::max(2, static_cast<int>(std::ceil(length / spacing)));
      const double side = item.turn > 0.0 ? 1.0 : -1.0;
      // centre of the arc on the inside of the turn
      const double cx = x - side * item.radius * std::sin(heading);
      const double cy = y + side * item.radius * std::cos(heading);
      const double start = heading;
      for (int k = 1; k <= n; ++k) {
        const double h = start + item.turn * k / n;
        x = cx + side * item.radius * std::sin(h);
        y = cy - side * item.radius * std::cos(h);
        points.push_back({x, y});
      }
      heading = start + item.turn;
    }
  }
  return points;
}

namespace {

std::vector<PathPoint> ReadPoints(YamlMap& map, const std::string& key, double limit) {
  YAML::Node list = map.Sequence(key);
  const std::string field = map.FieldName(key);
  std::vector<PathPoint> points;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string name = field + "[" + std::to_string(i) + "]";
    if (!list[i].IsSequence() || list[i].size() != 2) {
      throw InputError(map.file().string(), LineOf(list[i]), name, "a pair [x_m, y_m]", "something else");
    }
    points.push_back({ScalarNumber(list[i][0], map.file(), name + "[0]", Range::Closed(-limit, limit, "m")),
                      ScalarNumber(list[i][1], map.file(), name + "[1]", Range::Closed(-limit, limit, "m"))});
  }
  return points;
}

std::vector<RouteItem> ReadRoute(YamlMap& d) {
  YAML::Node list = d.Sequence("route");
  const std::string field = d.FieldName("route");
  std::vector<RouteItem> route;
  for (std::size_t i = 0; i < list.size(); ++i) {
    YamlMap item(list[i], d.file(), field + "[" + std::to_string(i) + "]", d.LineOfKey("route"));
    RouteItem r;
    if (item.Has("straight_m")) {
      r.straight = item.Number("straight_m", Range::Positive(1.0e4, "m"));
    } else {
      r.turn = item.Number("turn_deg", Range::Closed(-360.0, 360.0, "deg")) * kPi / 180.0;
      r.radius = item.Number("radius_m", Range::Closed(5.0, 1.0e4, "m"));
      if (r.turn == 0.0) item.Fail("turn_deg", "a non-zero turn (or straight_m)", "0");
    }
    item.Finish();
    route.push_back(r);
  }
  if (route.empty()) d.Fail("route", "at least one item", "none");
  return route;
}

void ParseDriver(YamlMap& d, CarScene& scene) {
  PathDriverParams& p = scene.driver;
  p.preview_time = d.NumberOr("preview_time_s", p.preview_time, Range::Closed(0.0, 5.0, "s"));
  p.min_preview = d.NumberOr("min_preview_m", p.min_preview, Range::Positive(100.0, "m"));
  p.speed_gain = d.NumberOr("speed_gain_per_mps", p.speed_gain, Range::Closed(0.0, 100.0, "1/(m/s)"));
  p.speed_integral = d.NumberOr("speed_integral_per_m", p.speed_integral, Range::Closed(0.0, 100.0, "1/m"));
  p.brake_gain = d.NumberOr("brake_gain_per_mps", p.brake_gain, Range::Closed(0.0, 100.0, "1/(m/s)"));
  p.brake_band = d.NumberOr("brake_band_mps", p.brake_band, Range::Closed(0.0, 10.0, "m/s"));
  p.max_brake = d.NumberOr("max_brake", p.max_brake, Range::Closed(0.0, 1.0));
  p.brake_rate = d.NumberOr("brake_rate_per_s", p.brake_rate, Range::Positive(1000.0, "1/s"));
  p.clutch_rate = d.NumberOr("clutch_rate_per_s", p.clutch_rate, Range::Positive(1000.0, "1/s"));
  p.upshift_rpm = d.NumberOr("upshift_rpm", p.upshift_rpm, Range::Positive(20000.0, "rpm"));
  p.downshift_rpm = d.NumberOr("downshift_rpm", p.downshift_rpm, Range::Positive(20000.0, "rpm"));
  p.shift_time = d.NumberOr("shift_time_s", p.shift_time, Range::Positive(5.0, "s"));
  p.launch_rpm = d.NumberOr("launch_rpm", p.launch_rpm, Range::Positive(20000.0, "rpm"));
  p.launch_time = d.NumberOr("launch_time_s", p.launch_time, Range::Positive(10.0, "s"));
  p.stop_speed = d.NumberOr("stop_speed_mps", p.stop_speed, Range::Closed(0.0, 20.0, "m/s"));
  p.top_gear = d.IntegerOr("top_gear", 0, 0, scene.car.gear_count());
  if (!(p.downshift_rpm < p.upshift_rpm)) {
    d.Fail("downshift_rpm", "downshift_rpm < upshift_rpm", FormatDouble(p.downshift_rpm));
  }

  const bool has_route = d.Has("route");
  const bool has_iso = d.Has("iso3888_1");
  const bool has_path = d.Has("path_m");
  if (int(has_route) + int(has_iso) + int(has_path) != 1) {
    d.Fail("route", "exactly one of route, iso3888_1 or path_m", std::to_string(int(has_route) + int(has_iso) + int(has_path)) + " given");
  }
  if (has_route) {
    const std::vector<RouteItem> route = ReadRoute(d);
    scene.path = RoutePolyline(route, 0.0, 0.0, 0.0, 0.5);
    scene.road.centre = scene.path;
  } else if (has_iso) {
    YamlMap iso = d.Map("iso3888_1");
    const double x0 = iso.Number("start_x_m", Range::Closed(10.0, 5000.0, "m"));
    const double run_in = iso.Number("run_in_m", Range::Closed(0.0, 5000.0, "m"));
    const double run_out = iso.Number("run_out_m", Range::Closed(10.0, 5000.0, "m"));
    iso.Finish();
    if (run_in > x0) iso.Fail("run_in_m", "run_in_m <= start_x_m (the car starts at x = start_x_m - run_in_m >= 0)", FormatDouble(run_in));
    const LaneChangeTrack track = MakeIso3888Track(scene.car.chassis.width, x0, run_in, run_out);
    scene.path = track.centre;
    scene.road.centre = {{track.centre.front().x, 0.0}, {track.centre.back().x + 100.0, 0.0}};
    scene.road.cones = track.left_cones;
    scene.road.cones.insert(scene.road.cones.end(), track.right_cones.begin(), track.right_cones.end());
  } else {
    scene.path = ReadPoints(d, "path_m", 1.0e5);
    if (scene.path.size() < 2) d.Fail("path_m", "at least 2 points", std::to_string(scene.path.size()));
    scene.road.centre = scene.path;
  }
  for (std::size_t i = 1; i < scene.path.size(); ++i) {
    if (scene.path[i].x == scene.path[i - 1].x && scene.path[i].y == scene.path[i - 1].y) {
      d.Fail(has_path ? "path_m" : "route", "distinct consecutive points", "a repeated point");
    }
  }

  YAML::Node speed = d.Sequence("speed_kmh");
  const std::string field = d.FieldName("speed_kmh");
  for (std::size_t i = 0; i < speed.size(); ++i) {
    const std::string name = field + "[" + std::to_string(i) + "]";
    if (!speed[i].IsSequence() || speed[i].size() != 2) {
      throw InputError(d.file().string(), LineOf(speed[i]), name, "a pair [s_m, speed_kmh]", "something else");
    }
    SpeedPoint point;
    point.s = ScalarNumber(speed[i][0], d.file(), name + "[0]", Range::Closed(0.0, 1.0e5, "m"));
    point.v = ScalarNumber(speed[i][1], d.file(), name + "[1]", Range::Closed(0.0, 250.0, "km/h")) / 3.6;
    if (!scene.speed.empty() && !(point.s > scene.speed.back().s)) {
      throw InputError(d.file().string(), LineOf(speed[i]), name + "[0]", "s_m rising strictly", FormatDouble(point.s));
    }
    scene.speed.push_back(point);
  }
  if (scene.speed.empty()) d.Fail("speed_kmh", "at least one [s_m, speed_kmh] point", "none");
  d.Finish();
}

CarScene ParseRoot(const YamlDocument& document) {
  YamlMap root(document.root, document.file, "");
  root.RequireFormat("pwsim-scene/1");
  CarScene scene;
  scene.file = document.file;
  if (root.Choice("kind", {"wheelchair", "car"}) != "car") {
    root.Fail("kind", "car (this is the car scene reader)", "wheelchair");
  }
  scene.name = root.String("name");
  scene.description = root.StringOr("description", "");
  if (root.Has("clock")) {
    YamlMap clock = root.Map("clock");
    scene.clock.rate_hz = clock.Integer("rate_hz", 100, 100000);
    clock.Finish();
  }
  scene.vehicle_file = ResolveRelative(document.file, root.String("vehicle"));
  scene.car = ReadVehicleFile(scene.vehicle_file);
  scene.duration = root.Number("duration_s", Range::Positive(3600.0, "s"));

  const int sources = int(root.Has("inputs")) + int(root.Has("recorded_drive")) + int(root.Has("driver"));
  if (sources != 1) {
    root.Fail("inputs", "exactly one of inputs, recorded_drive or driver", std::to_string(sources) + " given");
  }
  if (root.Has("inputs")) {
    scene.source = CarScene::Source::kTables;
    YamlMap inputs = root.Map("inputs");
    scene.tables = ParseInputTables(inputs, scene.car.gear_count());
  } else if (root.Has("recorded_drive")) {
    scene.source = CarScene::Source::kRecordedDrive;
    scene.recorded_drive_file = ResolveRelative(document.file, root.String("recorded_drive"));
    scene.tables = ReadRecordedDrive(scene.recorded_drive_file, scene.car.gear_count());
  } else {
    scene.source = CarScene::Source::kDriver;
    YamlMap driver = root.Map("driver");
    ParseDriver(driver, scene);
  }

  // start pose: the path's start for the driver, else the origin heading +x
  scene.start = InitialState(scene.car);
  if (scene.source == CarScene::Source::kDriver) {
    scene.start.x = scene.path[0].x;
    scene.start.y = scene.path[0].y;
    scene.start.yaw = std::atan2(scene.path[1].y - scene.path[0].y, scene.path[1].x - scene.path[0].x);
  }
  if (root.Has("start")) {
    YamlMap start = root.Map("start");
    scene.start.x = start.NumberOr("x_m", scene.start.x, Range::Closed(-1.0e5, 1.0e5, "m"));
    scene.start.y = start.NumberOr("y_m", scene.start.y, Range::Closed(-1.0e5, 1.0e5, "m"));
    scene.start.yaw = start.NumberOr("yaw_deg", scene.start.yaw * 180.0 / kPi, Range::Closed(-360.0, 360.0, "deg")) * kPi / 180.0;
    const double speed = start.NumberOr("speed_kmh", 0.0, Range::Closed(0.0, 250.0, "km/h")) / 3.6;
    scene.start_gear = start.IntegerOr("gear", 0, 0, scene.car.gear_count());
    start.Finish();
    scene.start.u = speed;
    for (double& w : scene.start.omega) w = speed / scene.car.tyre.radius;
    if (scene.start_gear > 0) {
      const double engine = scene.car.GearRatio(scene.start_gear) * scene.car.gearbox.final_drive * speed / scene.car.tyre.radius;
      if (engine < scene.car.engine.idle_rpm * kRpmToRadps || engine > scene.car.engine.max_rpm * kRpmToRadps) {
        start.Fail("gear", "a gear whose engine speed at speed_kmh lies between idle_rpm and max_rpm",
                   "gear " + std::to_string(scene.start_gear) + " at " + FormatDouble(engine / kRpmToRadps) + " rpm");
      }
      scene.start.engine_speed = engine;
      scene.start.clutch_locked = true;
    }
  }

  if (root.Has("road")) {
    YamlMap road = root.Map("road");
    scene.road.lane_width = road.NumberOr("lane_width_m", scene.road.lane_width, Range::Closed(2.0, 6.0, "m"));
    scene.road.lanes = road.IntegerOr("lanes", scene.road.lanes, 1, 6);
    if (road.Has("route")) {
      if (scene.source == CarScene::Source::kDriver) road.Fail("route", "no route: the road follows the driver's path", "a route");
      scene.road.centre = RoutePolyline(ReadRoute(road), scene.start.x, scene.start.y, scene.start.yaw, 0.5);
    }
    if (road.Has("length_m")) {
      const double length = road.Number("length_m", Range::Positive(1.0e5, "m"));
      if (scene.source == CarScene::Source::kDriver) road.Fail("length_m", "no length_m: the road follows the driver's path", FormatDouble(length));
      scene.road.centre = {{scene.start.x - 50.0, scene.start.y}, {scene.start.x + length, scene.start.y}};
    }
    if (road.Has("cones_m")) {
      const std::vector<PathPoint> cones = ReadPoints(road, "cones_m", 1.0e5);
      scene.road.cones.insert(scene.road.cones.end(), cones.begin(), cones.end());
    }
    road.Finish();
  }
  if (scene.road.centre.empty()) {
    scene.road.centre = {{scene.start.x - 50.0, scene.start.y}, {scene.start.x + 1000.0, scene.start.y}};
  }
  if (root.Has("occupant")) {
    YamlMap occupant = root.Map("occupant");
    const std::vector<double> head = occupant.Numbers("head_offset_m", Range::Closed(-3.0, 3.0, "m"), 3, 3);
    scene.head_offset = {head[0], head[1], head[2]};
    occupant.Finish();
  }
  scene.sections = ReadExtensionSections(root, document.file);
  root.Finish();
  return scene;
}

}  // namespace

CarScene LoadCarScene(const std::filesystem::path& file) { return ParseRoot(LoadYamlFile(file)); }

CarScene ParseCarScene(const YamlDocument& document) { return ParseRoot(document); }

CarScene ParseCarScene(const std::string& yaml_text, const std::filesystem::path& label) {
  YamlDocument document = LoadYamlString(yaml_text, label.string());
  document.file = label;
  return ParseRoot(document);
}

CarSample FirstCarSample(const CarScene& scene) {
  CarSample first;
  first.state = scene.start;
  first.input.clutch = scene.start_gear > 0 ? 0.0 : 1.0;
  first.input.gear = scene.start_gear;
  return first;
}

CarSample NextCarSample(const Vehicle& car, const CarSample& previous, const DriverInput& input, double dt) {
  StepInfo info;
  const VehicleState& state = previous.state;
  CarSample sample;
  sample.tick = previous.tick + 1;
  sample.state = StepVehicle(car, state, input, dt, &info);
  sample.input = input;
  sample.road_wheel_angle = info.road_wheel_angle;
  sample.throttle_effective = info.throttle;
  sample.engine_torque = info.engine_torque;
  sample.clutch_torque = info.clutch_torque;
  sample.roll_accel = (sample.state.roll_rate - state.roll_rate) / dt;
  sample.pitch_accel = (sample.state.pitch_rate - state.pitch_rate) / dt;
  return sample;
}

std::vector<CarSample> SimulateCarScene(const CarScene& scene) {
  const std::int64_t ticks = scene.tick_count();
  const double dt = scene.clock.dt();
  std::vector<CarSample> samples;
  samples.reserve(static_cast<std::size_t>(ticks));
  samples.push_back(FirstCarSample(scene));
  PathDriver driver(scene.driver, scene.path.size() >= 2 ? scene.path : std::vector<PathPoint>{{0, 0}, {1, 0}},
                    scene.speed);
  if (scene.start_gear > 0) driver.StartRolling(scene.start_gear);
  for (std::int64_t k = 1; k < ticks; ++k) {
    const double t = scene.clock.TimeAt(k - 1);
    const VehicleState& state = samples.back().state;
    const DriverInput input =
        scene.source == CarScene::Source::kDriver ? driver.Step(scene.car, state, dt) : scene.tables.At(t);
    samples.push_back(NextCarSample(scene.car, samples.back(), input, dt));
  }
  return samples;
}

CarHeadMotion HeadMotionOfCar(const CarSample& sample, const std::array<double, 3>& head) {
  const VehicleState& s = sample.state;
  const double ax = s.ax - s.yaw_accel * head[1] - s.r * s.r * head[0] - sample.pitch_accel * head[2];
  const double ay = s.ay + s.yaw_accel * head[0] - s.r * s.r * head[1] - sample.roll_accel * head[2];
  CarHeadMotion m;
  m.fs = {ax + kGravity * std::sin(s.pitch), ay + kGravity * std::sin(s.roll),
          kGravity * std::cos(s.roll) * std::cos(s.pitch)};
  m.w = {s.roll_rate, -s.pitch_rate, s.r};
  return m;
}

}  // namespace pwsim::vehicle
