#include "engine/scene.h"

#include <algorithm>

#include "engine/check.h"
#include "engine/input_error.h"

namespace pwsim {
namespace {

/// `key` is either a relative path to a file in the spec's format or an inline mapping.
template <typename InlineParser, typename FileReader>
auto ReadReferenced(YamlMap& scene, const std::string& key, InlineParser parse_inline,
                    FileReader read_file) {
  YAML::Node node = scene.Raw(key);
  if (node.IsScalar()) {
    const std::filesystem::path target = ResolveRelative(scene.file(), node.Scalar());
    if (!std::filesystem::exists(target)) {
      scene.Fail(key, "a path to an existing file or an inline mapping",
                 "\"" + node.Scalar() + "\" (" + target.string() + " does not exist)");
    }
    return read_file(target);
  }
  YamlMap map(node, scene.file(), key, scene.LineOfKey(key));
  auto value = parse_inline(map);
  map.Finish();
  return value;
}

Scene ParseSceneRoot(const YamlDocument& document) {
  Scene scene;
  scene.file = document.file;
  YamlMap root(document.root, document.file, "");

  root.RequireFormat("pwsim-scene/1");
  // `kind: car` scenes (seed 001) are read by engine/vehicle/car_scene.h
  if (root.ChoiceOr("kind", "wheelchair", {"wheelchair", "car"}) != "wheelchair") {
    root.Fail("kind", "wheelchair here (a car scene is loaded with vehicle::LoadCarScene)", "car");
  }
  scene.name = root.String("name");
  root.StringOr("description", "");

  if (root.Has("clock")) {
    YamlMap clock = root.Map("clock");
    scene.clock.rate_hz = clock.Integer("rate_hz", 50, 100000);
    clock.Finish();
  }
  if (root.Has("room")) {
    YamlMap room = root.Map("room");
    scene.room.length = room.Number("length_m", Range::Closed(2.0, 200.0, "m"));
    scene.room.width = room.Number("width_m", Range::Closed(1.0, 100.0, "m"));
    scene.room.height = room.Number("height_m", Range::Closed(2.0, 20.0, "m"));
    room.Finish();
  }

  const bool circuit = root.Has("circuit");
  if (!circuit || root.Has("terrain")) scene.terrain = ReadReferenced(
      root, "terrain",
      [](YamlMap& map) {
        map.StringOr("format", "pwsim-terrain/1");
        return ParseTerrainProfile(map);
      },
      [](const std::filesystem::path& path) { return ReadTerrainFile(path); });
  scene.chair = ReadReferenced(
      root, "chair",
      [](YamlMap& map) {
        map.StringOr("format", "pwsim-chair/1");
        return ParseChair(map);
      },
      [](const std::filesystem::path& path) { return ReadChairFile(path); });
  if (!scene.chair.gm || !scene.chair.lm) {
    root.Fail("chair", "a chair with identified gm and lm sections (the scene simulates it)",
              std::string("a chair without ") + (!scene.chair.gm ? "gm" : "lm"));
  }
  scene.load_kg = root.Number("load_kg", Range::Closed(0.0, 300.0, "kg"));

  if (!circuit || root.Has("drive")) {
  YamlMap drive = root.Map("drive");
  scene.drive.start_x = drive.NumberOr("start_x_m", 0.0, Range::Closed(-100.0, 100.0, "m"));
  scene.drive.start_delay = drive.NumberOr("start_delay_s", 0.5, Range::Closed(0.0, 60.0, "s"));
  scene.drive.speed = drive.Number("speed_mps", Range::Positive(4.0, "m/s"));
  scene.drive.accel = drive.Number("accel_mps2", Range::Positive(5.0, "m/s^2"));
  scene.drive.decel = drive.NumberOr("decel_mps2", scene.drive.accel, Range::Positive(5.0, "m/s^2"));
  scene.drive.stop_x = drive.Number("stop_x_m", Range::Closed(-100.0, 200.0, "m"));
  scene.settle_time = drive.NumberOr("settle_s", 1.5, Range::Closed(0.0, 60.0, "s"));
  if (const std::string problem = scene.drive.Validate(); !problem.empty()) {
    drive.Fail("stop_x_m", "a drive that can reach its speed and stop (" + problem + ")",
               "start_x_m and stop_x_m too close for this speed and acceleration");
  }
  drive.Finish();
  }
  if (circuit) {
    YamlMap section = root.Map("circuit");
    scene.circuit = ParseCircuit(section, scene.chair, scene.load_kg);
    section.Finish();
  }

  if (root.Has("pitch_torque")) {
    YamlMap torque = root.Map("pitch_torque");
    scene.pitch_torque.constant = torque.NumberOr("constant_nm", 0.0, Range::Closed(-1e4, 1e4, "N m"));
    scene.pitch_torque.per_accel =
        torque.NumberOr("per_accel_kgm", 0.0, Range::Closed(-1e4, 1e4, "N m per m/s^2"));
    torque.Finish();
  }
  if (root.Has("occupant")) {
    YamlMap occupant = root.Map("occupant");
    const std::vector<double> head =
        occupant.Numbers("head_offset_m", Range::Closed(-3.0, 3.0, "m"), 3, 3);
    std::copy(head.begin(), head.end(), scene.occupant.head_offset.begin());
    occupant.Finish();
  }
  if (root.Has("servo")) {
    YamlMap servo = root.Map("servo");
    scene.servo.enabled = servo.BoolOr("enabled", true);
    scene.servo.kp = servo.NumberOr("kp", scene.servo.kp, Range::Closed(0.0, 100.0));
    scene.servo.ki = servo.NumberOr("ki", scene.servo.ki, Range::Closed(0.0, 100.0));
    scene.servo.drift_yaw_rate =
        servo.NumberOr("drift_yaw_rate_radps", scene.servo.drift_yaw_rate, Range::Closed(-1.0, 1.0, "rad/s"));
    scene.servo.drift_lateral =
        servo.NumberOr("drift_lateral_mps", scene.servo.drift_lateral, Range::Closed(-1.0, 1.0, "m/s"));
    servo.Finish();
  }
  scene.sections = ReadExtensionSections(root, document.file);
  root.Finish();
  return scene;
}

}  // namespace

std::map<std::string, SceneSection> ReadExtensionSections(YamlMap& root,
                                                          const std::filesystem::path& file) {
  std::map<std::string, SceneSection> sections;
  for (const std::string& key : ExtensionSectionKeys()) {
    if (root.Has(key)) {
      const int line = root.LineOfKey(key);
      sections[key] = SceneSection{root.Raw(key), file, line};
    }
  }
  return sections;
}

const SceneSection* Scene::section(const std::string& key) const {
  const auto found = sections.find(key);
  return found == sections.end() ? nullptr : &found->second;
}

Scene LoadScene(const std::filesystem::path& file) { return ParseSceneRoot(LoadYamlFile(file)); }

Scene ParseScene(const YamlDocument& document) { return ParseSceneRoot(document); }

Scene ParseScene(const std::string& yaml_text, const std::filesystem::path& label) {
  return ParseSceneRoot(LoadYamlString(yaml_text, label.string()));
}

std::filesystem::path DefaultScenePath(const std::filesystem::path& source_dir) {
  return source_dir / "scenes" / "speed_cushion.yaml";
}

std::vector<ChairSample> SimulateScene(const Scene& scene) {
  ChairSimulator simulator(scene.chair, scene.terrain, scene.load_kg, scene.clock.dt(),
                           scene.pitch_torque);
  const std::int64_t ticks = scene.tick_count();
  std::vector<ChairSample> samples;
  samples.reserve(static_cast<std::size_t>(ticks));
  samples.push_back(simulator.Start(EvaluateDrive(scene.drive, 0.0)));
  for (std::int64_t tick = 1; tick < ticks; ++tick) {
    samples.push_back(simulator.Advance(EvaluateDrive(scene.drive, scene.clock.TimeAt(tick))));
  }
  return samples;
}

std::vector<FullChairSample> SimulateCircuitScene(const Scene& scene) {
  PWSIM_DEMAND(scene.is_circuit());
  CircuitRunner runner(scene.chair, *scene.circuit, scene.load_kg, scene.clock.dt(), scene.pitch_torque);
  const std::int64_t ticks = scene.tick_count();
  std::vector<FullChairSample> samples;
  samples.reserve(static_cast<std::size_t>(ticks));
  samples.push_back(runner.Start());
  // the joystick is sampled at each tick's start
  for (std::int64_t tick = 1; tick < ticks; ++tick) samples.push_back(runner.Advance(scene.clock.TimeAt(tick - 1)));
  return samples;
}

std::vector<FullChairSample> SimulateSceneFullChair(const Scene& scene) {
  PWSIM_DEMAND(!scene.is_circuit());
  const FloorMap floor = FloorFromTerrain(scene.terrain);
  const PlanarLayout layout = DefaultPlanarLayout(scene.chair);
  FullChairSimulator simulator(scene.chair, layout, floor, scene.load_kg, scene.clock.dt(), scene.pitch_torque);
  const std::int64_t ticks = scene.tick_count();
  std::vector<FullChairSample> samples;
  samples.reserve(static_cast<std::size_t>(ticks));
  const Longitudinal first = EvaluateDrive(scene.drive, 0.0);
  samples.push_back(simulator.StartAlong({first.x, 0.0, 0.0, 0.0, 0.0}, first));
  for (std::int64_t tick = 1; tick < ticks; ++tick) {
    samples.push_back(simulator.AdvanceAlong(EvaluateDrive(scene.drive, scene.clock.TimeAt(tick))));
  }
  return samples;
}

}  // namespace pwsim
