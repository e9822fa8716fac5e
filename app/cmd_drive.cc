// pwsim drive SCENE [--wheel | --joystick SPEC] [--device NAME] [--duration S] [--out DIR]
// [--no-realtime] [--can udp:HOST:PORT --hmd udp:HOST:PORT|none ...]:
// drives a car scene live at its clock rate: the controls come from a real steering wheel and
// pedals (SDL2, --wheel; mapping from the scene's session.controls), from a chair joystick
// (--joystick: the chair's R-Net bus listen-only, a recorded R-Net candump log, or an SDL
// joystick; hardware/car_drive_source.h maps it to a two-pedal car), or from the scene itself;
// each tick steps the car and the MCA (hardware/car_live.h) and logs the platform command
// (DIR/drive.csv), and draws the car's cueing as `pwsim run` does (DIR/mca.png). With --can the drive is a live session instead: joystick -> car -> MCA ->
// safety supervisor -> CiA 402 over CAN, camera pose to the HMD, the replayable session log,
// and the joystick -> platform command / HMD frame latencies in DIR/report.json.
// A circuit scene (a wheelchair scene with `circuit:`) is driven the same way, always as a live
// session (on --can, its default when not given): joystick -> full-DoF chair through the circuit -> MCA -> supervisor -> CAN
// (hardware/chair_drive_source.h) on the scene's platform (pw4dof by default: five drives) or
// --platform FILE's, and report.json also carries the drive's training metrics
// (engine/training_metrics.h; DIR/training.md), and the figures `pwsim run` writes for a circuit
// (top_view.png, wheels.png, mca.png, mca_lateral.png: report/run_circuit.h) of the chair as
// driven (the joystick track of the session replayed through the same chair model, tick for
// tick). --mca washout|mpc chooses the MCA over the scene's for cars and chairs alike (the MPC
// holds the current input: no trial ahead live). A recorded joystick (rnet-log:FILE) ends the
// drive when its log ends. Wiring only.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/output_folder.h"
#include "app/stop_signal.h"
#include "engine/trial_table.h"
#include "engine/vehicle/car_scene.h"
#include "app/session_setup.h"
#include "engine/atomic_file.h"
#include "engine/circuit.h"
#include "hardware/car_drive_source.h"
#include "hardware/chair_drive_source.h"
#include "engine/scene.h"
#include "report/skill_score.h"
#include "report/car_run.h"
#include "report/run_circuit.h"
#include "report/training_report.h"
#include "hardware/car_live.h"
#include "hardware/rnet_joystick.h"
#include "hardware/sdl/sdl_input.h"
#include "hardware/sdl/sdl_joystick.h"
#include "hardware/udp_socket.h"

namespace pwsim::app {

const CommandSpec& DriveSpec() {
  static const CommandSpec spec = [] {
    CommandSpec c{
      "drive",
      "pwsim drive SCENE [options]",
      "Drive a car scene live (a wheel and pedals with --wheel, a chair joystick with --joystick), car + MCA per tick; with --can a live session to the platform and the headset. A circuit scene (wheelchair) is always driven by --joystick as a live session (to --can, its default unless given), with training metrics and the figures of pwsim run; a recorded joystick ends the drive when its log ends.",
      {
          {"wheel", "", "-", "", "read the controls from an SDL2 joystick (wheel, pedals, shifter)"},
          {"joystick", "SPEC", "-", "", "drive with a chair joystick: rnet:IFACE (R-Net bus, listen-only SocketCAN), rnet-log:FILE (a candump log of one), sdl or sdl:NAME (an SDL joystick), sdl-script:FILE.yaml (a pwsim-joystick-script/1 played on an SDL virtual joystick)"},
          {"joystick-timeout-ms", "MS", "ms", "100", "R-Net watchdog: zero deflection this long after the last valid joystick frame"},
          {"device", "NAME", "-", "", "part of the joystick's name (default: session.controls.device or the first)"},
          {"duration", "S", "s", "", "drive time (default: the scene's duration_s; a recorded joystick, rnet-log:FILE, ends the drive when its log ends)"},
          {"no-realtime", "", "-", "", "step as fast as possible instead of at the clock rate"},
          OutOption("drive", "drive.csv, mca.png; with --can: session.log, can.log, report.json, joystick.json; a circuit: also training.md and the figures of pwsim run"),
          McaAlgorithmOptionSpec(),
          PlatformOptionSpec(),
      },
      "SCENE  a pwsim-scene/1 YAML file with kind: car, or a wheelchair scene with a circuit: section (on the PW platform pw4dof by default: 5 drives)"};
    // With --can (given explicitly) the drive runs as a live session on these links.
    std::vector<OptionSpec> links = SessionLinkOptions();
    for (OptionSpec& link : links) {
      if (link.name == "can")
        link.help = "CAN link of the live session: udp:HOST:PORT (cannelloni) or socketcan:IFACE; a circuit always "
                    "drives one (on this default when not given), a car only when --can is given";
    }
    c.options.insert(c.options.end(), links.begin(), links.end());
    return c;
  }();
  return spec;
}

namespace {

/// The car scene's MCA configuration with --mca over its mca.algorithm.
mca::McaConfig DriveMcaConfig(const ParsedArgs& args, const vehicle::CarScene& scene) {
  mca::McaConfig config = mca::LoadCarMcaConfig(scene);
  if (const std::optional<mca::McaAlgorithm> algorithm = McaAlgorithmOption(args)) {
    mca::ChooseAlgorithm(*algorithm, config);
  }
  return config;
}

/// The joystick named by `spec` (see the --joystick option).
std::unique_ptr<hw::JoystickSource> OpenJoystick(const std::string& spec, int rate_hz, double timeout_ms) {
  hw::RnetJoystickParams rnet;
  rnet.timeout_ticks = hw::WatchdogTicks(timeout_ms, rate_hz);
  if (spec.rfind("rnet-log:", 0) == 0) {
    const std::string file = spec.substr(9);
    return std::make_unique<hw::RnetLogJoystick>(hw::ReadCandumpFile(file), rate_hz, rnet, "R-Net log " + file);
  }
  if (spec.rfind("rnet:", 0) == 0) {
    hw::ListenerOpenResult opened =
        hw::OpenSocketCanListenOnly(spec.substr(5), hw::kRnetJoystickId, hw::kRnetJoystickMask);
    if (!opened.listener) throw std::runtime_error("R-Net joystick '" + spec + "': " + opened.message);
    return std::make_unique<hw::RnetJoystick>(std::move(opened.listener), rnet);
  }
  if (spec.rfind("sdl-script:", 0) == 0) {
    const std::string file = spec.substr(11);
    return std::make_unique<hw::SdlScriptedJoystick>(hw::ReadJoystickScript(file), rate_hz, "script " + file);
  }
  if (spec == "sdl" || spec.rfind("sdl:", 0) == 0) {
    hw::JoystickAxes axes;
    if (spec.size() > 4) axes.device = spec.substr(4);
    return std::make_unique<hw::SdlJoystick>(axes);
  }
  throw UsageError("option --joystick: expected rnet:IFACE, rnet-log:FILE, sdl, sdl:NAME or sdl-script:FILE, got '" +
                   spec + "'");
}

void WriteJoystickReport(const hw::JoystickSource& joystick, std::uint64_t invalid_polls,
                         const std::filesystem::path& out);

/// The drive time: `duration`, cut to the end of a recorded joystick (an R-Net candump log: the
/// tick of its last record, at least one tick), which is said on stdout; a live joystick never
/// ends the drive.
double DriveDuration(double duration, const hw::JoystickSource& joystick, const Clock& clock) {
  const auto* log = dynamic_cast<const hw::RnetLogJoystick*>(&joystick);
  if (log == nullptr) return duration;
  const double end = clock.TimeAt(std::max<std::int64_t>(log->last_record_tick(), 1));
  if (end >= duration) return duration;
  std::cout << "pwsim drive: " << joystick.name() << " ends at " << end << " s: the drive ends with it\n";
  return end;
}

/// The figures `pwsim run` writes for a circuit (report/run_circuit.h: top_view.png, wheels.png,
/// mca.png, mca_lateral.png), of the chair as driven: the deflection applied at each tick of the
/// drive (its trace) replayed through the same chair model from the same start, and the MCA as
/// `pwsim run` runs it (with --mca and --platform) on that motion. The replay is the drive tick
/// for tick (the model is deterministic); its largest distance from the drive's track is
/// returned [m] (0 when it is the drive).
double WriteDriveFigures(const ParsedArgs& args, const Scene& scene, const std::vector<TrainingTick>& trace,
                         const std::filesystem::path& out) {
  if (trace.size() < 2) return 0.0;
  CircuitRunner runner(scene.chair, *scene.circuit, scene.load_kg, scene.clock.dt(), scene.pitch_torque);
  std::vector<FullChairSample> samples;
  samples.reserve(trace.size());
  samples.push_back(runner.Start());
  double departure = 0.0;
  for (std::size_t k = 1; k < trace.size(); ++k) {
    samples.push_back(runner.AdvanceWith({trace[k].forward, trace[k].turn}));
    departure = std::max(departure, std::hypot(samples.back().planar.x - trace[k].x, samples.back().planar.y - trace[k].y));
  }
  report::McaChoice choice;
  choice.algorithm = McaAlgorithmOption(args);
  if (args.Has("platform")) choice.platform = std::filesystem::path(args.Get("platform"));
  choice.compare = false;  // the drive's cueing, not the comparison of a run
  TrialTable table = report::CircuitColumns(scene, samples);
  nlohmann::ordered_json summary;
  report::AddCircuitMotionCueing(scene, samples, table, summary, out, choice);
  report::WriteCircuitFigures(scene, samples, out);
  return departure;
}

/// report.json's chair.mca: the algorithm and, for the MPC, how it predicts without a trial ahead
/// (live: the present input's transients decay, mca/mpc.h) and its solves and fallbacks to the washout.
nlohmann::ordered_json MpcUseJson(mca::McaAlgorithm algorithm, const mca::MpcStats& stats) {
  nlohmann::ordered_json j{{"algorithm", mca::McaAlgorithmName(algorithm)}};
  if (algorithm != mca::McaAlgorithm::kMpc) return j;
  j["preview"] = "none: the present input's transients decay (live, no trial ahead)";
  j["solves"] = stats.solves;
  j["fallbacks_to_washout"] = stats.fallbacks;
  j["fault_ticks"] = stats.fault_ticks;
  return j;
}

/// The links opened (false, said on stderr, when one cannot be) and the output folder made.
bool OpenDriveSession(const ParsedArgs& args, const Clock& clock, double duration, const mca::PlatformSpec& platform,
                      const std::filesystem::path& out, SessionSetup* setup) {
  const std::string link_error = SetUpSession(args, clock, duration, platform, setup);
  if (!link_error.empty()) {
    std::cerr << "pwsim drive: " << link_error << "\n";
    return false;
  }
  std::filesystem::create_directories(out);
  return true;
}

/// The drive as a live session: joystick -> car -> MCA -> supervisor -> CAN, eye pose -> HMD.
int DriveSession(const ParsedArgs& args, const vehicle::CarScene& scene, hw::JoystickSource& joystick,
                 double duration) {
  const mca::McaConfig mca_config = DriveMcaConfig(args, scene);
  if (!mca_config.platform.Has(mca::Dof::kSurge) || !mca_config.platform.Has(mca::Dof::kYaw))
    throw UsageError("car scene platform '" + mca_config.platform.name + "' lacks surge or yaw");
  SessionSetup setup;
  const std::filesystem::path out = args.Get("out");
  if (!OpenDriveSession(args, scene.clock, duration, mca_config.platform, out, &setup)) return 1;
  hw::CarDriveSource source(scene, mca_config, joystick);
  std::cout << "pwsim drive: car '" << scene.car.name << "' driven live by " << joystick.name() << ", mca "
            << mca::McaAlgorithmName(mca_config.algorithm) << "\n";
  const int status = RunAndReport("pwsim drive", args, setup, source, out);
  WriteJoystickReport(joystick, source.invalid_polls(), out);
  return status;
}

/// A circuit driven by a chair joystick as a live session: joystick -> chair -> MCA ->
/// supervisor -> CAN, head pose -> HMD; report.json with the training metrics.
int DriveChairSession(const ParsedArgs& args, const Scene& scene, const std::string& scene_path,
                      hw::JoystickSource& joystick, double duration, const mca::McaConfig& mca_config) {
  SessionSetup setup;
  const std::filesystem::path out = args.Get("out");
  if (!OpenDriveSession(args, scene.clock, duration, mca_config.platform, out, &setup)) return 1;
  // the metrics cover the drive up to the stop request (the park after it is not scored)
  hw::ChairDriveSource source(scene, joystick, setup.config.run_ticks, mca_config);
  const char* cueing = mca::McaAlgorithmName(source.mca().algorithm);
  std::cout << "pwsim drive: chair '" << scene.name << "' through its circuit, driven live by " << joystick.name()
            << ", mca " << cueing << " on '" << source.mca().platform.name << "' (" << source.mca().platform_source
            << ": the CAN drives, one per actuator)\n";
  TrainingMetrics training;
  const int status = RunAndReport("pwsim drive", args, setup, source, out, [&](nlohmann::ordered_json& j) {
    training = ComputeTrainingMetrics(*scene.circuit, source.trace(), scene.clock.dt());
    j["training"] = report::TrainingJson(training);
    nlohmann::ordered_json peak;
    for (mca::Dof d : mca::kAllDofs) {
      if (source.mca().platform.Has(d)) peak[mca::DofName(d)] = source.peak()[mca::Index(d)];
    }
    j["chair"] = {{"scene", scene_path},
                  {"engine_ticks", source.trace().size()},
                  {"platform", source.mca().platform.name},
                  {"peak_pose_command", peak},
                  {"mca", MpcUseJson(source.mca().algorithm, source.mpc_stats())}};
  });
  report::WriteTrainingPage(training, "pwsim drive " + scene_path + " (" + joystick.name() + ")", out);
  const double departure = WriteDriveFigures(args, scene, source.trace(), out);
  std::cout << "  figures of the drive (as pwsim run writes them): ";
  for (const char* figure : {"top_view.png", "wheels.png", "mca.png", "mca_lateral.png"}) {
    if (std::filesystem::exists(out / figure)) std::cout << (out / figure).string() << " ";
  }
  std::cout << "(the joystick track replayed: " << (departure == 0.0 ? "the drive exactly" : "off by up to " + std::to_string(departure) + " m") << ")\n";
  const std::string skill = report::ScoreSkillItem(scene, scene_path, source.trace(), out);  // a skill item: score.json
  if (!skill.empty()) std::cout << "  " << skill << "\n";
  std::cout << "  training: " << training.gates_passed << " of " << training.gates_total << " gates, "
            << training.contacts << " contacts, clearance min " << training.clearance_min_m << " m, "
            << training.joystick_commands << " joystick commands; " << (out / "training.md").string() << "\n";
  WriteJoystickReport(joystick, source.invalid_polls(), out);
  return status;
}

/// What the joystick delivered: OUT/joystick.json and a line.
void WriteJoystickReport(const hw::JoystickSource& joystick, std::uint64_t invalid_polls,
                         const std::filesystem::path& out) {
  nlohmann::ordered_json j;
  j["format"] = "pwsim-drive-joystick/1";
  j["joystick"] = joystick.name();
  j["invalid_polls"] = invalid_polls;
  std::cout << "  joystick invalid (lost or unplugged) on " << invalid_polls << " polls\n";
  const hw::RnetJoystickCounters* c = nullptr;
  if (const auto* log = dynamic_cast<const hw::RnetLogJoystick*>(&joystick)) c = &log->counters();
  if (const auto* bus = dynamic_cast<const hw::RnetJoystick*>(&joystick)) c = &bus->counters();
  if (c != nullptr) {
    j["rnet_frames"] = {{"joystick", c->valid}, {"garbage", c->garbage}, {"other_slot", c->other_device},
                        {"other", c->other}, {"watchdog_timeouts", c->timeouts}};
    std::cout << "  R-Net frames: " << c->valid << " joystick, " << c->garbage << " garbage, " << c->other_device
              << " other slot, " << c->other << " other; " << c->timeouts << " watchdog timeouts\n";
  }
  WriteFileAtomically(out / "joystick.json", j.dump(2) + "\n");
}

}  // namespace

int DriveCommand(const ParsedArgs& args) {
  if (args.positional().size() != 1) throw UsageError("expected one SCENE (kind: car)");
  const std::filesystem::path scene_path = args.positional()[0];
  if (vehicle::SceneKind(scene_path) != "car") {
    const Scene scene = LoadScene(scene_path);
    if (!scene.is_circuit()) throw UsageError("pwsim drive needs a car scene (kind: car) or a circuit scene (circuit:)");
    (void)report::SkillOf(scene);  // a skill item's skill: section, before any link opens
    if (!args.Has("joystick") || args.Flag("wheel"))
      throw UsageError("a chair drives a circuit from a joystick: give --joystick SPEC (the live session goes to --can, "
                       "default " + args.Get("can") + ")");
    double duration = args.Has("duration") ? args.GetDouble("duration") : scene.duration();
    if (!(duration > 0.0 && duration <= 3600.0)) throw UsageError("option --duration: expected (0, 3600] s");
    // the platform (the scene's, pw4dof by default, or --platform's) and the cueing (the scene's
    // or --mca's), before any link opens
    const std::optional<hw::PlatformChoice> platform = PlatformOption(args);
    const mca::McaConfig mca_config =
        hw::SessionMcaConfig(scene, McaAlgorithmOption(args), platform ? &*platform : nullptr);
    const std::unique_ptr<hw::JoystickSource> joystick = OpenJoystick(
        args.Get("joystick"), scene.clock.rate_hz, args.GetDouble("joystick-timeout-ms", 1.0, 10'000.0));
    duration = DriveDuration(duration, *joystick, scene.clock);
    OutputFolder folder(OutDir(args), "drive");  // replaces what the last command wrote there
    const int status = DriveChairSession(args, scene, scene_path.string(), *joystick, duration, mca_config);
    folder.Print(std::cout, "pwsim drive");
    return status;
  }
  const vehicle::CarScene scene = vehicle::LoadCarScene(scene_path);
  if (args.Has("platform")) throw UsageError("option --platform: a car scene drives its own platform (its platform: section)");
  hw::ControlMapping mapping;
  if (const SceneSection* s = scene.section("session")) {
    YamlMap map(s->node, s->file, "session", s->line);
    if (map.Has("controls")) {
      YamlMap controls = map.Map("controls");
      mapping = hw::ParseControlMapping(controls);
      controls.Finish();
    }
    map.Finish();
  }
  if (args.Has("device")) mapping.device = args.Get("device");
  double duration = args.Has("duration") ? args.GetDouble("duration") : scene.duration;
  if (!(duration > 0.0 && duration <= 3600.0)) throw UsageError("option --duration: expected (0, 3600] s");

  std::unique_ptr<hw::JoystickSource> joystick;
  if (args.Has("joystick")) {
    if (args.Flag("wheel")) throw UsageError("options --wheel and --joystick: give one");
    joystick = OpenJoystick(args.Get("joystick"), scene.clock.rate_hz, args.GetDouble("joystick-timeout-ms", 1.0, 10'000.0));
    duration = DriveDuration(duration, *joystick, scene.clock);
  }
  const std::int64_t ticks = scene.clock.TicksFor(duration);
  if (args.Has("can")) {
    if (!joystick) throw UsageError("option --can (a live session) needs --joystick");
    OutputFolder folder(OutDir(args), "drive");  // replaces what the last command wrote there
    const int status = DriveSession(args, scene, *joystick, duration);
    folder.Print(std::cout, "pwsim drive");
    return status;
  }

  std::unique_ptr<hw::SdlWheel> wheel;
  std::vector<vehicle::CarSample> scripted;
  if (joystick) {
    std::cout << "pwsim drive: " << joystick->name() << "\n";
  } else if (args.Flag("wheel")) {
    wheel = std::make_unique<hw::SdlWheel>(mapping);
    std::cout << "pwsim drive: wheel '" << wheel->name() << "'\n";
  } else {
    scripted = vehicle::SimulateCarScene(scene);  // the scene's own controls
  }
  const mca::McaConfig mca_config = DriveMcaConfig(args, scene);
  hw::CarLiveLoop loop(scene, mca_config);
  OutputFolder folder(OutDir(args), "drive");  // replaces what the last command wrote there
  std::cout << "pwsim drive: mca " << mca::McaAlgorithmName(mca_config.algorithm) << " on platform '"
            << mca_config.platform.name << "'\n";
  const std::size_t rows = static_cast<std::size_t>(ticks) + 1;
  std::vector<double> t(rows), x(rows), y(rows), yaw(rows), v(rows), rpm(rows), gear(rows), throttle(rows),
      brake(rows), clutch(rows), steer(rows), rail(rows), turn(rows), cue_x(rows), cue_y(rows), late(rows);
  std::vector<vehicle::CarSample> samples;  // for the figures after the drive
  samples.reserve(rows);
  InstallStopSignalHandlers();
  const auto start = std::chrono::steady_clock::now();
  const auto period = std::chrono::nanoseconds(1000000000LL / scene.clock.rate_hz);
  std::size_t done = 0;
  for (std::int64_t k = 0; k <= ticks && !StopRequested().load(); ++k) {
    const auto due = start + k * period;
    if (!args.Flag("no-realtime")) std::this_thread::sleep_until(due);
    late[done] = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - due).count();
    vehicle::DriverInput input;
    if (joystick) {
      input = hw::CarControlsFromJoystick(joystick->Poll(k, hw::MonotonicNs()),
                                          vehicle::Speed(loop.last().sample.state), hw::JoystickCarParams{});
    } else if (wheel) {
      input = wheel->Poll();
    } else {
      input = scripted[std::min(static_cast<std::size_t>(k), scripted.size() - 1)].input;
    }
    const hw::CarLiveTick& tick = k == 0 ? loop.last() : loop.Step(input);
    const vehicle::CarSample& s = tick.sample;
    samples.push_back(s);
    t[done] = scene.clock.TimeAt(k);
    x[done] = s.state.x;
    y[done] = s.state.y;
    yaw[done] = s.state.yaw;
    v[done] = vehicle::Speed(s.state);
    rpm[done] = vehicle::EngineRpm(s.state);
    gear[done] = s.input.gear;
    throttle[done] = s.input.throttle;
    brake[done] = s.input.brake;
    clutch[done] = s.input.clutch;
    steer[done] = s.input.steer;
    rail[done] = tick.command.pose[mca::Index(mca::Dof::kSurge)];
    turn[done] = tick.command.pose[mca::Index(mca::Dof::kYaw)];
    cue_x[done] = tick.false_cue_surge;
    cue_y[done] = tick.false_cue_sway;
    ++done;
    if (k % scene.clock.rate_hz == 0) {
      std::cout << "  t " << t[done - 1] << " s  " << std::lround(v[done - 1] * 3.6) << " km/h  "
                << std::lround(rpm[done - 1]) << " rpm  gear " << s.input.gear << "  rail " << rail[done - 1]
                << " m  yaw " << turn[done - 1] << " rad\n" << std::flush;
    }
  }
  TrialTable table(done);
  auto cut = [&](std::vector<double>& c) { c.resize(done); return c; };
  table.Add("t_s", cut(t));
  table.Add("x_m", cut(x));
  table.Add("y_m", cut(y));
  table.Add("yaw_rad", cut(yaw));
  table.Add("v_mps", cut(v));
  table.Add("engine_rpm", cut(rpm));
  table.Add("gear", cut(gear));
  table.Add("throttle", cut(throttle));
  table.Add("brake", cut(brake));
  table.Add("clutch", cut(clutch));
  table.Add("steer_rad", cut(steer));
  table.Add("plat_surge_m", cut(rail));
  table.Add("plat_yaw_rad", cut(turn));
  table.Add("false_cue_surge_mps2", cut(cue_x));
  table.Add("false_cue_sway_mps2", cut(cue_y));
  table.Add("tick_lateness_us", cut(late));
  const std::filesystem::path out = folder.dir();
  table.WriteCsv(out / "drive.csv");
  // the figure `pwsim run` writes for a car (mca.png, report/car_run.h), of the car as driven
  report::McaChoice choice;
  choice.algorithm = McaAlgorithmOption(args);
  choice.compare = false;  // the drive's cueing, not the comparison of a run
  TrialTable run_table = report::CarColumns(scene, samples);
  nlohmann::ordered_json summary;
  report::AddCarCueing(scene, samples, run_table, summary, out, choice);
  std::cout << "pwsim drive: " << done << " ticks" << (StopRequested().load() ? " (stopped)" : "") << "\n";
  folder.Print(std::cout, "pwsim drive");
  return 0;
}

}  // namespace pwsim::app
