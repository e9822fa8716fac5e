// pwsim session [SCENE] --can udp:HOST:PORT|socketcan:IFACE --hmd udp:HOST:PORT|none:
// the immersive session's real-time loop (hardware/session_runner.h). Writes DIR/session.log
// (replayable with `pwsim replay`), DIR/can.log (candump format) and DIR/report.json.
// With --trial TRIAL_DIR it replays a measured trial, tracked (T_r) or as the model (T_m); with
// --plan PLAN.csv --participant P --trial-index K it follows a study plan (pwsim study plan),
// choosing the source from the planned condition; DIR/trial.json records what was shown.

#include <atomic>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/output_folder.h"
#include "app/stop_signal.h"
#include "app/scene_path.h"
#include "app/session_setup.h"
#include "engine/atomic_file.h"
#include "engine/chair.h"
#include "sysid/measured/measured_trial.h"
#include "engine/scene.h"
#include "engine/vehicle/car_scene.h"
#include "hardware/car_session_streams.h"
#include "hardware/sdl/sdl_input.h"
#include "hardware/session_runner.h"
#include "hardware/session_streams.h"
#include "report/trial_track.h"
#include "hardware/track_streams.h"
#include "hardware/udp_can_bus.h"
#include "study/plan.h"

namespace pwsim::app {
namespace {

using report::ParseTrialSource;
using report::TrialSource;
using report::TrialSourceName;
using report::TrialTrack;

/// The streams of this run: the scene's own chair simulation, or (--trial, or --plan with
/// --participant) a measured trial replayed as tracked (T_r) or as the model (T_m). The choice
/// is written to OUT/trial.json so the ratings of a study can be traced to what was shown.
hw::SessionStreams ChooseStreams(const ParsedArgs& args, const Scene& scene, const hw::SessionConfig& config,
                                 const mca::McaConfig& mca_config, const hw::PlatformChoice* platform,
                                 const std::filesystem::path& out_dir, std::string* description) {
  nlohmann::ordered_json j;
  j["format"] = "pwsim-session-trial/1";
  TrialSource source = TrialSource::kMeasured;
  bool from_trial = args.Has("trial");
  if (args.Has("plan")) {
    if (!args.Has("participant")) throw UsageError("option --plan needs --participant");
    const long long index = args.GetInt("trial-index");
    if (index < 1) throw UsageError("option --trial-index: expected a positive integer");
    const std::string plan_file = args.Get("plan");
    const study::PlanTrial planned = study::FindPlannedTrial(study::ReadPlan(plan_file), plan_file,
                                                             args.Get("participant"), static_cast<int>(index));
    // condition -> source, e.g. T_r=measured,T_m=model
    std::string source_name;
    std::stringstream map(args.Get("sources"));
    for (std::string item; std::getline(map, item, ',');) {
      const auto eq = item.find('=');
      if (eq == std::string::npos) throw UsageError("option --sources: expected CONDITION=measured|model,...");
      if (item.substr(0, eq) == planned.condition) source_name = item.substr(eq + 1);
    }
    if (source_name.empty())
      throw UsageError("option --sources: no source for condition '" + planned.condition +
                                  "' (planned for " + planned.participant + ", trial " + std::to_string(index) + ")");
    if (!ParseTrialSource(source_name, &source))
      throw UsageError("option --sources: expected measured or model, got '" + source_name + "'");
    j["plan"] = plan_file;
    j["participant"] = planned.participant;
    j["trial_index"] = planned.trial_index;
    j["condition"] = planned.condition;
    if (!from_trial && source == TrialSource::kMeasured)
      throw UsageError("condition '" + planned.condition + "' replays a measured trial: give --trial TRIAL_DIR");
  } else if (args.Has("source") && !ParseTrialSource(args.Get("source"), &source)) {
    throw UsageError("option --source: expected measured or model");
  }
  hw::SessionStreams streams;
  if (from_trial) {
    const MeasuredTrial trial = ReadMeasuredTrial(args.Get("trial"));
    Chair chair = args.Has("chair") ? ReadChairFile(args.Get("chair")) : trial.chair;
    if (!chair.gm || !chair.lm) chair = MakeTableOneChair();
    const double smooth_ms = args.GetDouble("smooth-ms");
    if (!(smooth_ms >= 0.0 && smooth_ms <= 1000.0)) throw UsageError("option --smooth-ms: expected 0..1000 ms");
    const int smooth_ticks = static_cast<int>(std::lround(smooth_ms * 1e-3 * config.clock_rate_hz));
    const mca::SagittalTrack track = TrialTrack(trial, source, chair, 1.0 / config.clock_rate_hz);
    const std::string label = "trial '" + trial.name + "' as " + TrialSourceName(source) +
                              (source == TrialSource::kMeasured ? " (tracked O_V)" : " (model driven by the measured x(t))");
    streams = hw::BuildTrackSessionStreams(scene, config, track, smooth_ticks, label, description,
                                           McaAlgorithmOption(args), platform);
    j["source"] = TrialSourceName(source);
    j["trial"] = args.Get("trial");
  } else {
    streams = hw::BuildSessionStreams(scene, config, mca_config, description);
    j["source"] = "scene";
  }
  j["mca"] = streams.mca_algorithm;
  j["platform"] = config.platform;
  j["description"] = *description;
  WriteFileAtomically(out_dir / "trial.json", j.dump(2) + "\n");
  return streams;
}

/// The streams of a car scene (kind: car, seed 001): the car through its controls and the MCA on
/// the rail + yaw platform. Measured chair trials and study plans do not apply.
hw::SessionStreams CarStreams(const ParsedArgs& args, const vehicle::CarScene& scene, const hw::SessionConfig& config,
                              const std::filesystem::path& out_dir, std::string* description) {
  if (args.Has("trial") || args.Has("plan")) {
    throw UsageError("options --trial and --plan replay chair trials; " + scene.file.string() +
                                " is a car scene (kind: car)");
  }
  hw::SessionStreams streams = hw::BuildCarSessionStreams(scene, config, description, McaAlgorithmOption(args));
  nlohmann::ordered_json j;
  j["format"] = "pwsim-session-trial/1";
  j["source"] = "car scene";
  j["mca"] = streams.mca_algorithm;
  j["platform"] = config.platform;
  j["description"] = *description;
  WriteFileAtomically(out_dir / "trial.json", j.dump(2) + "\n");
  return streams;
}


}  // namespace

const CommandSpec& SessionSpec() {
  static const CommandSpec spec = [] {
    CommandSpec c{
      "session",
      "pwsim session [SCENE] --can udp:HOST:PORT|socketcan:IFACE --hmd udp:HOST:PORT|none [options]",
      "Run an immersive session: MCA -> safety -> CiA 402 over CAN, camera poses to the HMD.",
      {
          {"duration", "S", "s", "", "motion time before the soft stop (default: the scene's)"},
          OutOption("session", "session.log, can.log, report.json, trial.json"),
          {"trial", "TRIAL_DIR", "-", "", "replay this measured trial (measured-trials.md) instead of the scene's chair"},
          {"source", "S", "-", "measured", "with --trial: measured (tracked motion, T_r) or model (T_m)"},
          {"plan", "PLAN.csv", "-", "", "follow a study plan (pwsim study plan): the condition of --participant's trial"},
          {"participant", "P", "-", "", "with --plan: the participant"},
          {"trial-index", "K", "-", "1", "with --plan: the position of the trial in the participant's sequence"},
          {"sources", "MAP", "-", "T_r=measured,T_m=model", "with --plan: condition -> measured|model"},
          {"chair", "FILE", "-", "", "model chair for the model source (default: the trial's if identified, else Table I)"},
          {"smooth-ms", "MS", "ms", "20", "with --trial: half-width of the moving average on track derivatives"},
          McaAlgorithmOptionSpec(),
          PlatformOptionSpec(),
      },
      "SCENE  a pwsim-scene/1 YAML file (default: the paper's speed-cushion trial, on the PW platform pw4dof: 5 drives); kind: car drives seed 001's car on its rail + yaw (2 drives)"};
    const std::vector<OptionSpec> links = SessionLinkOptions();
    c.options.insert(c.options.begin(), links.begin(), links.end());
    return c;
  }();
  return spec;
}

int SessionCommand(const ParsedArgs& args) {
  if (args.positional().size() > 1) throw UsageError("expected at most one SCENE");
  const std::filesystem::path scene_path =
      args.positional().empty() ? DefaultScene() : std::filesystem::path(args.positional()[0]);
  // a wheelchair scene (seed 000) or a car scene (kind: car, seed 001)
  const bool is_car = vehicle::SceneKind(scene_path) == "car";
  std::optional<Scene> chair_scene;
  std::optional<vehicle::CarScene> car_scene;
  if (is_car) {
    car_scene = vehicle::LoadCarScene(scene_path);
  } else {
    chair_scene = LoadScene(scene_path);
  }
  const SceneSection* session_section = is_car ? car_scene->section("session") : chair_scene->section("session");
  if (const SceneSection* s = session_section) {
    // reserved for the chair; a car scene may map its wheel and pedals (`controls:`, pwsim drive)
    YamlMap map(s->node, s->file, "session", s->line);
    if (is_car && map.Has("controls")) {
      YamlMap controls = map.Map("controls");
      (void)hw::ParseControlMapping(controls);
      controls.Finish();
    }
    map.Finish();
  }
  const Clock clock = is_car ? car_scene->clock : chair_scene->clock;
  const std::string scene_name = is_car ? car_scene->name : chair_scene->name;
  const double scene_duration = is_car ? car_scene->duration : chair_scene->duration();

  const double duration = args.Has("duration") ? args.GetDouble("duration") : scene_duration;
  // The platform the session drives: the scene's (a chair scene: pw4dof by default), or --platform's.
  const std::optional<hw::PlatformChoice> platform = PlatformOption(args);
  if (is_car && platform) throw UsageError("option --platform: a car scene drives its own platform (its platform: section)");
  const mca::McaConfig mca_config = is_car ? mca::LoadCarMcaConfig(*car_scene)
                                           : hw::SessionMcaConfig(*chair_scene, McaAlgorithmOption(args),
                                                                  platform ? &*platform : nullptr);
  SessionSetup setup;
  const std::string link_error = SetUpSession(args, clock, duration, mca_config.platform, &setup);
  if (!link_error.empty()) {
    std::cerr << "pwsim session: " << link_error << "\n";
    return 1;
  }
  const hw::SessionConfig& config = setup.config;

  std::string source;
  OutputFolder folder(OutDir(args), "session");  // replaces what the last command wrote there
  const std::filesystem::path out_dir = folder.dir();
  std::filesystem::remove(out_dir / "trial.json");
  const hw::SessionStreams streams = is_car ? CarStreams(args, *car_scene, config, out_dir, &source)
                                              : ChooseStreams(args, *chair_scene, config, mca_config,
                                                              platform ? &*platform : nullptr, out_dir, &source);
  std::cout << "pwsim session: scene '" << scene_name << "', " << source << "\n";
  hw::StreamsSource streams_source(config, streams);
  const int status = RunAndReport("pwsim session", args, setup, streams_source, out_dir);
  folder.Print(std::cout, "pwsim session");
  return status;
}

}  // namespace pwsim::app
