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
#include "app/stop_signal.h"
#include "app/scene_path.h"
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
    streams = hw::BuildTrackSessionStreams(scene, config, track, smooth_ticks, label, description);
    j["source"] = TrialSourceName(source);
    j["trial"] = args.Get("trial");
  } else {
    streams = hw::BuildSessionStreams(scene, config, description);
    j["source"] = "scene";
  }
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
  hw::SessionStreams streams = hw::BuildCarSessionStreams(scene, config, description);
  nlohmann::ordered_json j;
  j["format"] = "pwsim-session-trial/1";
  j["source"] = "car scene";
  j["description"] = *description;
  WriteFileAtomically(out_dir / "trial.json", j.dump(2) + "\n");
  return streams;
}

int TicksFromMs(double ms, int rate_hz, const char* option) {
  const double ticks = ms * rate_hz / 1000.0;
  const long rounded = std::lround(ticks);
  if (rounded < 1 || std::abs(ticks - static_cast<double>(rounded)) > 1e-9)
    throw UsageError(std::string("option --") + option +
                                ": expected a whole number of engine ticks (>= 1)");
  return static_cast<int>(rounded);
}

}  // namespace

const CommandSpec& SessionSpec() {
  static const CommandSpec spec{
      "session",
      "pwsim session [SCENE] --can udp:HOST:PORT|socketcan:IFACE --hmd udp:HOST:PORT|none [options]",
      "Run an immersive session: MCA -> safety -> CiA 402 over CAN, camera poses to the HMD.",
      {
          {"can", "SPEC", "-", "udp:127.0.0.1:29536", "CAN link: udp:HOST:PORT (cannelloni) or socketcan:IFACE"},
          {"can-local", "HOST:PORT", "-", "", "address the CAN link sends from and listens on (default: any free port, on 127.0.0.1 for a loopback peer); give it to platform-sim --peer"},
          {"hmd", "SPEC", "-", "udp:127.0.0.1:29537", "HMD bridge peer: udp:HOST:PORT, or none"},
          {"hmd-local", "HOST:PORT", "-", "", "address the HMD link sends from and listens on (default: any free port); give it to hmd-peer --peer"},
          {"duration", "S", "s", "", "motion time before the soft stop (default: the scene's)"},
          {"drive-cycle-ms", "MS", "ms", "4", "CAN SYNC period"},
          {"frame-ms", "MS", "ms", "10", "visual frame period (HMD rate)"},
          {"hmd-timeout-ms", "MS", "ms", "250", "a frame without a head pose after it this long: HMD stale -> soft stop"},
          {"max-stop-s", "S", "s", "30", "give up waiting for the platform to park after this"},
          {"rt-priority", "N", "-", "0", "run the loop SCHED_FIFO at this priority (0 = normal)"},
          {"drive-wait-ms", "MS", "ms", "0", "lockstep for hosts without real-time scheduling: each SYNC waits up to MS for the drives' answer to the last one (0 = strict real time)"},
          {"out", "DIR", "-", "out/session", "output folder (session.log, can.log, report.json, trial.json)"},
          {"trial", "TRIAL_DIR", "-", "", "replay this measured trial (measured-trials.md) instead of the scene's chair"},
          {"source", "S", "-", "measured", "with --trial: measured (tracked motion, T_r) or model (T_m)"},
          {"plan", "PLAN.csv", "-", "", "follow a study plan (pwsim study plan): the condition of --participant's trial"},
          {"participant", "P", "-", "", "with --plan: the participant"},
          {"trial-index", "K", "-", "1", "with --plan: the position of the trial in the participant's sequence"},
          {"sources", "MAP", "-", "T_r=measured,T_m=model", "with --plan: condition -> measured|model"},
          {"chair", "FILE", "-", "", "model chair for the model source (default: the trial's if identified, else Table I)"},
          {"smooth-ms", "MS", "ms", "20", "with --trial: half-width of the moving average on track derivatives"},
      },
      "SCENE  a pwsim-scene/1 YAML file (default: the paper's speed-cushion trial); kind: car drives seed 001's car"};
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

  hw::SessionConfig config;
  config.clock_rate_hz = clock.rate_hz;
  config.drive_cycle_ticks = TicksFromMs(args.GetDouble("drive-cycle-ms"), config.clock_rate_hz, "drive-cycle-ms");
  config.frame_ticks = TicksFromMs(args.GetDouble("frame-ms"), config.clock_rate_hz, "frame-ms");
  config.safety.dt = static_cast<double>(config.drive_cycle_ticks) / config.clock_rate_hz;
  config.master.heartbeat_period_cycles = std::max(1, static_cast<int>(std::lround(0.1 / config.safety.dt)));
  config.master.heartbeat_timeout_cycles = 3 * config.master.heartbeat_period_cycles;
  const double duration = args.Has("duration") ? args.GetDouble("duration") : scene_duration;
  if (!(duration >= 0.0 && duration <= 3600.0))
    throw UsageError("option --duration: expected 0..3600 s");
  config.run_ticks = clock.TicksFor(duration);
  const double timeout_ms = args.GetDouble("hmd-timeout-ms", 1.0, 60'000.0);
  config.hmd_timeout_ns = static_cast<std::int64_t>(timeout_ms * 1e6);
  config.max_stop_ticks = clock.TicksFor(args.GetDouble("max-stop-s", 0.01, 3600.0));
  config.session_id = static_cast<std::uint32_t>(hw::MonotonicNs() & 0x7FFFFFFF);
  const std::string hmd_spec = args.Get("hmd");
  config.hmd_required = hmd_spec != "none";
  const std::string bad = config.Validate();
  if (!bad.empty()) throw UsageError("session configuration: " + bad);

  // The CAN link.
  const std::string can_spec = args.Get("can");
  hw::BusOpenResult bus;
  if (can_spec.rfind("udp:", 0) == 0) {
    // Frames are taken from the peer only (address and port); others are counted in report.json.
    std::string local = args.Get("can-local");
    if (local.empty()) {
      const auto remote = hw::ParseUdpAddress(can_spec.substr(4));
      local = remote && remote->ip == hw::ParseUdpAddress("127.0.0.1:0")->ip ? "127.0.0.1:0" : "0.0.0.0:0";
    } else if (!hw::ParseUdpAddress(local)) {
      throw UsageError("option --can-local: expected HOST:PORT, got '" + local + "'");
    }
    bus = hw::UdpCanBus::Open(local, can_spec.substr(4));
  } else if (can_spec.rfind("socketcan:", 0) == 0) {
    bus = hw::OpenSocketCan(can_spec.substr(10));
  } else {
    throw UsageError("option --can: expected udp:HOST:PORT or socketcan:IFACE");
  }
  if (!bus.bus) {
    std::cerr << "pwsim session: CAN link '" << can_spec << "': " << bus.message << "\n";
    return 1;
  }
  // The HMD link.
  hw::UdpSocket hmd;
  hw::UdpAddress hmd_peer;
  if (config.hmd_required) {
    if (hmd_spec.rfind("udp:", 0) != 0 || !hw::ParseUdpAddress(hmd_spec.substr(4)))
      throw UsageError("option --hmd: expected udp:HOST:PORT or none");
    hmd_peer = *hw::ParseUdpAddress(hmd_spec.substr(4));
    const std::string local = args.Get("hmd-local").empty() ? "0.0.0.0:0" : args.Get("hmd-local");
    if (!hw::ParseUdpAddress(local)) throw UsageError("option --hmd-local: expected HOST:PORT, got '" + local + "'");
    const std::string error = hmd.Bind(*hw::ParseUdpAddress(local));
    if (!error.empty()) {
      std::cerr << "pwsim session: HMD link: " << error << "\n";
      return 1;
    }
    hmd.AcceptOnlyFrom(hmd_peer);  // head poses from the headset only; others counted, never logged
  }

  std::string source;
  const std::filesystem::path out_dir = args.Get("out");
  std::filesystem::create_directories(out_dir);
  std::filesystem::remove(out_dir / "trial.json");
  const hw::SessionStreams streams = is_car ? CarStreams(args, *car_scene, config, out_dir, &source)
                                              : ChooseStreams(args, *chair_scene, config, out_dir, &source);
  AtomicFileWriter log(out_dir / "session.log");
  AtomicFileWriter can_log(out_dir / "can.log");
  InstallStopSignalHandlers();
  std::cout << "pwsim session: scene '" << scene_name << "', " << source << "\n"
            << "  CAN " << bus.bus->name() << ", HMD "
            << (config.hmd_required ? std::to_string(hmd.local_port()) + "->" + hmd_peer.ToString() : "none")
            << ", drive cycle " << config.drive_cycle_ticks << " ticks, frame " << config.frame_ticks
            << " ticks, motion for " << duration << " s\n" << std::flush;

  hw::RunnerIo io;
  io.bus = bus.bus.get();
  io.hmd = config.hmd_required ? &hmd : nullptr;
  io.hmd_peer = hmd_peer;
  io.log = &log.stream();
  io.candump = &can_log.stream();
  io.stop = &StopRequested();
  const long long rt = args.GetInt("rt-priority", 0, 99);
  io.rt_priority = static_cast<int>(rt);
  const double drive_wait_ms = args.GetDouble("drive-wait-ms", 0.0, 10'000.0);
  io.drive_answer_wait_ns = static_cast<std::int64_t>(drive_wait_ms * 1e6);
  if (rt > 0) {
    const std::string why = hw::EnterRealtime(io.rt_priority);
    std::cout << "  real-time: " << (why.empty() ? "SCHED_FIFO " + std::to_string(rt) : why) << "\n";
  }
  const hw::SessionReport report = hw::RunSession(config, streams, io);
  log.Commit();
  can_log.Commit();
  WriteFileAtomically(out_dir / "report.json", report.ToJson());

  std::cout << "pwsim session: " << report.final_state
            << (report.stop_reason.empty() ? "" : " after " + report.stop_reason) << ", "
            << report.steps << " steps\n"
            << "  cycle lateness p50 " << report.cycle_lateness_us.p50 << " us, p99 "
            << report.cycle_lateness_us.p99 << " us; period jitter p50 "
            << report.cycle_period_jitter_us.p50 << " us, p99 " << report.cycle_period_jitter_us.p99 << " us; "
            << report.schedule_slips << " schedule slips (" << report.schedule_slip_ms << " ms)\n"
            << "  visual-platform skew p50 " << report.skew_ms.p50 << " ms, p99 " << report.skew_ms.p99
            << " ms, jitter (sd) " << report.skew_ms.stddev << " ms over " << report.skew_ms.n << " frames\n"
            << "  refused datagrams from senders other than the peers: CAN " << report.can_rx_refused
            << ", HMD " << report.hmd_rx_refused << "\n"
            << "  limits " << (report.limits_ok ? "respected" : "EXCEEDED") << "; "
            << (out_dir / "session.log").string() << ", " << (out_dir / "report.json").string() << "\n";
  // 0: parked at neutral; 4: a latched fault (at rest, drives disabled); 3: anything else
  // (never started, timed out waiting to park, or a limit exceeded).
  if (!report.limits_ok || report.parked_tick < 0) return 3;
  return report.final_state == "parked" ? 0 : 4;
}

}  // namespace pwsim::app
