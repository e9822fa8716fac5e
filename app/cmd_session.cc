// pwsim session [SCENE] --can udp:HOST:PORT|socketcan:IFACE --hmd udp:HOST:PORT|none:
// the immersive session's real-time loop (hardware/session_runner.h). Writes DIR/session.log
// (replayable with `pwsim replay`), DIR/can.log (candump format) and DIR/report.json.

#include <atomic>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "app/commands.h"
#include "app/stop_signal.h"
#include "app/scene_path.h"
#include "engine/atomic_file.h"
#include "engine/scene.h"
#include "hardware/session_runner.h"
#include "hardware/session_streams.h"
#include "hardware/udp_can_bus.h"

namespace pwsim::app {
namespace {

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
          {"hmd", "SPEC", "-", "udp:127.0.0.1:29537", "HMD bridge peer: udp:HOST:PORT, or none"},
          {"duration", "S", "s", "", "motion time before the soft stop (default: the scene's)"},
          {"drive-cycle-ms", "MS", "ms", "4", "CAN SYNC period"},
          {"frame-ms", "MS", "ms", "10", "visual frame period (HMD rate)"},
          {"hmd-timeout-ms", "MS", "ms", "250", "a frame without a head pose after it this long: HMD stale -> soft stop"},
          {"max-stop-s", "S", "s", "30", "give up waiting for the platform to park after this"},
          {"rt-priority", "N", "-", "0", "run the loop SCHED_FIFO at this priority (0 = normal)"},
          {"drive-wait-ms", "MS", "ms", "0", "lockstep for hosts without real-time scheduling: each SYNC waits up to MS for the drives' answer to the last one (0 = strict real time)"},
          {"out", "DIR", "-", "out/session", "output folder (session.log, can.log, report.json)"},
      },
      "SCENE  a pwsim-scene/1 YAML file (default: the paper's speed-cushion trial)"};
  return spec;
}

int SessionCommand(const ParsedArgs& args) {
  if (args.positional().size() > 1) throw UsageError("expected at most one SCENE");
  const std::filesystem::path scene_path =
      args.positional().empty() ? DefaultScene() : std::filesystem::path(args.positional()[0]);
  const Scene scene = LoadScene(scene_path);
  if (const SceneSection* s = scene.section("session")) {
    (void)s;  // reserved: a `session:` section is accepted by the engine but has no keys yet
    YamlMap map(s->node, s->file, "session", s->line);
    map.Finish();
  }

  hw::SessionConfig config;
  config.clock_rate_hz = scene.clock.rate_hz;
  config.drive_cycle_ticks = TicksFromMs(args.GetDouble("drive-cycle-ms"), config.clock_rate_hz, "drive-cycle-ms");
  config.frame_ticks = TicksFromMs(args.GetDouble("frame-ms"), config.clock_rate_hz, "frame-ms");
  config.safety.dt = static_cast<double>(config.drive_cycle_ticks) / config.clock_rate_hz;
  config.master.heartbeat_period_cycles = std::max(1, static_cast<int>(std::lround(0.1 / config.safety.dt)));
  config.master.heartbeat_timeout_cycles = 3 * config.master.heartbeat_period_cycles;
  const double duration = args.Has("duration") ? args.GetDouble("duration") : scene.duration();
  if (!(duration >= 0.0 && duration <= 3600.0))
    throw UsageError("option --duration: expected 0..3600 s");
  config.run_ticks = scene.clock.TicksFor(duration);
  const double timeout_ms = args.GetDouble("hmd-timeout-ms", 1.0, 60'000.0);
  config.hmd_timeout_ns = static_cast<std::int64_t>(timeout_ms * 1e6);
  config.max_stop_ticks = scene.clock.TicksFor(args.GetDouble("max-stop-s", 0.01, 3600.0));
  config.session_id = static_cast<std::uint32_t>(hw::MonotonicNs() & 0x7FFFFFFF);
  const std::string hmd_spec = args.Get("hmd");
  config.hmd_required = hmd_spec != "none";
  const std::string bad = config.Validate();
  if (!bad.empty()) throw UsageError("session configuration: " + bad);

  // The CAN link.
  const std::string can_spec = args.Get("can");
  hw::BusOpenResult bus;
  if (can_spec.rfind("udp:", 0) == 0) {
    bus = hw::UdpCanBus::Open("127.0.0.1:0", can_spec.substr(4));
    if (bus.bus && hw::ParseUdpAddress(can_spec.substr(4))->ip != hw::ParseUdpAddress("127.0.0.1:0")->ip)
      bus = hw::UdpCanBus::Open("0.0.0.0:0", can_spec.substr(4));
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
    const std::string error = hmd.Bind(*hw::ParseUdpAddress("0.0.0.0:0"));
    if (!error.empty()) {
      std::cerr << "pwsim session: HMD link: " << error << "\n";
      return 1;
    }
  }

  std::string source;
  const hw::SessionStreams streams = hw::BuildSessionStreams(scene, config, &source);
  const std::filesystem::path out_dir = args.Get("out");
  std::filesystem::create_directories(out_dir);
  AtomicFileWriter log(out_dir / "session.log");
  AtomicFileWriter can_log(out_dir / "can.log");
  InstallStopSignalHandlers();
  std::cout << "pwsim session: scene '" << scene.name << "', " << source << "\n"
            << "  CAN " << bus.bus->name() << ", HMD " << (config.hmd_required ? hmd_peer.ToString() : "none")
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
            << "  limits " << (report.limits_ok ? "respected" : "EXCEEDED") << "; "
            << (out_dir / "session.log").string() << ", " << (out_dir / "report.json").string() << "\n";
  // 0: parked at neutral; 4: a latched fault (at rest, drives disabled); 3: anything else
  // (never started, timed out waiting to park, or a limit exceeded).
  if (!report.limits_ok || report.parked_tick < 0) return 3;
  return report.final_state == "parked" ? 0 : 4;
}

}  // namespace pwsim::app
