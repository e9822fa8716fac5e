#pragma once
// Scene: one simulator trial as a file (`pwsim-scene/1`, YAML under scenes/): the room, the
// ground, the chair and its load, the drive, the clock. Sections owned by other libraries
// (mca, platform, render, session) are kept as YAML and parsed, with the same strictness,
// by those libraries; any other unknown key is an error.
//
//   Scene scene = LoadScene("scenes/speed_cushion.yaml");
//   std::vector<ChairSample> trial = SimulateScene(scene);

#include <yaml-cpp/yaml.h>

#include "engine/yaml_reader.h"

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "engine/chair_simulator.h"
#include "engine/circuit.h"
#include "engine/clock.h"
#include "engine/drive_profile.h"
#include "engine/straight_line_servo.h"
#include "engine/terrain.h"

namespace pwsim {

struct Room {
  double length{12.0};  ///< [m] along W's x, starting at x = -2 m
  double width{4.0};    ///< [m] across, centred on the path
  double height{3.0};   ///< [m]
};

struct Occupant {
  /// p_VH: the head (vestibular point) from O_V, in V (x forward, y left, z up) [m].
  std::array<double, 3> head_offset{0.05, 0.0, 1.25};
};

/// A YAML section owned by another library, with where it came from.
struct SceneSection {
  YAML::Node node;
  std::filesystem::path file;  ///< the scene file, for error messages
  int line{0};
};

struct Scene {
  std::filesystem::path file;   ///< where it was loaded from ("" when built in code)
  std::string name{"speed_cushion"};
  Clock clock;
  Room room;
  Terrain terrain;
  Chair chair;
  double load_kg{100.0};        ///< M_u [kg]
  DriveProfile drive;
  double settle_time{1.5};      ///< [s] simulated after the chair stops
  PitchTorqueParams pitch_torque;
  Occupant occupant;
  ServoParams servo;
  std::map<std::string, SceneSection> sections;  ///< mca, platform, render, session, skill
  /// Present for a circuit scene (`circuit:` section): the full-DoF chair driven by a joystick
  /// through walls, obstacles and gates over a floor height map (circuit.h). `drive` and
  /// `terrain` are then optional and unused by SimulateCircuitScene.
  std::optional<CircuitSpec> circuit;

  bool is_circuit() const { return circuit.has_value(); }
  /// [s]: the drive's stop time plus settling, or the circuit's duration.
  double duration() const { return circuit ? circuit->duration : drive.StopTime() + settle_time; }
  std::int64_t tick_count() const { return clock.TicksFor(duration()) + 1; }
  const SceneSection* section(const std::string& key) const;
};

/// Keys of sections other libraries parse (the only unknown top-level keys allowed).
inline const std::vector<std::string>& ExtensionSectionKeys() {
  static const std::vector<std::string> keys{"mca", "platform", "render", "session", "skill"};
  return keys;
}

/// The sections of a scene's root that other libraries parse (ExtensionSectionKeys), raw, with
/// their file and line; used by the chair and the car scene readers.
std::map<std::string, SceneSection> ReadExtensionSections(YamlMap& root,
                                                          const std::filesystem::path& file);

/// Loads and validates a scene file. @throws InputError (file, line, field, expected).
Scene LoadScene(const std::filesystem::path& file);
/// Same, from a YAML document already read (LoadYamlFile), so a scene is read only once.
Scene ParseScene(const YamlDocument& document);
/// Same, from YAML text; relative paths resolve against `label`'s folder.
Scene ParseScene(const std::string& yaml_text, const std::filesystem::path& label);
/// The built-in default: the paper's speed-cushion trial (also scenes/speed_cushion.yaml).
std::filesystem::path DefaultScenePath(const std::filesystem::path& source_dir);

/// Runs the chair through the scene's drive on the scene's clock: one sample per tick.
std::vector<ChairSample> SimulateScene(const Scene& scene);

/// A circuit scene run by the full-DoF chair: one sample per tick. @pre scene.is_circuit().
std::vector<FullChairSample> SimulateCircuitScene(const Scene& scene);

/// The straight drive of a (non-circuit) scene run by the full-DoF chair (AdvanceAlong) on the
/// scene's terrain as a floor: the sagittal columns equal SimulateScene's bit for bit.
std::vector<FullChairSample> SimulateSceneFullChair(const Scene& scene);

}  // namespace pwsim
