#include "app/session_setup.h"

#include <algorithm>
#include <cmath>
#include <iostream>

#include "app/link_key_option.h"
#include "app/stop_signal.h"
#include "engine/atomic_file.h"
#include "hardware/udp_can_bus.h"

namespace pwsim::app {
namespace {

int TicksFromMs(double ms, int rate_hz, const char* option) {
  const double ticks = ms * rate_hz / 1000.0;
  const long rounded = std::lround(ticks);
  if (rounded < 1 || std::abs(ticks - static_cast<double>(rounded)) > 1e-9)
    throw UsageError(std::string("option --") + option + ": expected a whole number of engine ticks (>= 1)");
  return static_cast<int>(rounded);
}

}  // namespace

std::optional<mca::McaAlgorithm> McaAlgorithmOption(const ParsedArgs& args) {
  if (!args.Has("mca")) return std::nullopt;
  const std::string name = args.Get("mca");
  if (name != "washout" && name != "mpc") throw UsageError("option --mca: expected washout or mpc, got '" + name + "'");
  return name == "mpc" ? mca::McaAlgorithm::kMpc : mca::McaAlgorithm::kWashout;
}

OptionSpec McaAlgorithmOptionSpec() {
  return {"mca", "washout|mpc", "-", "", "motion cueing: the washout or the MPC (held input); overrides the scene's mca.algorithm"};
}

std::vector<OptionSpec> SessionLinkOptions() {
  return {
          {"can", "SPEC", "-", "udp:127.0.0.1:29536", "CAN link: udp:HOST:PORT (cannelloni) or socketcan:IFACE"},
          {"can-local", "HOST:PORT", "-", "", "address the CAN link sends from and listens on (default: any free port, on 127.0.0.1 for a loopback peer); give it to platform-sim --peer"},
          {"hmd", "SPEC", "-", "udp:127.0.0.1:29537", "HMD bridge peer: udp:HOST:PORT, or none"},
          {"hmd-local", "HOST:PORT", "-", "", "address the HMD link sends from and listens on (default: any free port); give it to hmd-peer --peer"},
          {"drive-cycle-ms", "MS", "ms", "4", "CAN SYNC period"},
          {"frame-ms", "MS", "ms", "10", "visual frame period (HMD rate)"},
          {"hmd-timeout-ms", "MS", "ms", "250", "a frame without a head pose after it this long: HMD stale -> soft stop"},
          {"max-stop-s", "S", "s", "30", "give up waiting for the platform to park after this"},
          {"drive-return-s", "S", "s", "5", "a drive whose feedback is lost is waited for this long to come back (re-admitted) before the session gives up"},
          {"rt-priority", "N", "-", "0", "run the loop SCHED_FIFO at this priority (0 = normal)"},
          {"drive-wait-ms", "MS", "ms", "0", "lockstep for hosts without real-time scheduling: each SYNC waits up to MS for the drives' answer to the last one (0 = strict real time)"},
          LinkKeyOptionSpec(),
  };
}

OptionSpec PlatformOptionSpec() {
  return {"platform", "FILE", "-", "", "drive this platform (a pwsim-platform/1 file, e.g. scenes/platforms/car2dof.yaml) instead of the scene's"};
}

std::optional<hw::PlatformChoice> PlatformOption(const ParsedArgs& args) {
  if (!args.Has("platform") || args.Get("platform").empty()) return std::nullopt;
  const std::string file = args.Get("platform");
  return hw::PlatformChoice{mca::ReadPlatformFile(file), file};
}

std::string SetUpSession(const ParsedArgs& args, const Clock& clock, double duration, const mca::PlatformSpec& platform,
                         SessionSetup* setup) {
  hw::SessionConfig& config = setup->config;
  config.clock_rate_hz = clock.rate_hz;
  config.drive_cycle_ticks = TicksFromMs(args.GetDouble("drive-cycle-ms"), config.clock_rate_hz, "drive-cycle-ms");
  config.frame_ticks = TicksFromMs(args.GetDouble("frame-ms"), config.clock_rate_hz, "frame-ms");
  config.safety.dt = static_cast<double>(config.drive_cycle_ticks) / config.clock_rate_hz;
  config.master.heartbeat_period_cycles = std::max(1, static_cast<int>(std::lround(0.1 / config.safety.dt)));
  config.master.heartbeat_timeout_cycles = 3 * config.master.heartbeat_period_cycles;
  if (!(duration >= 0.0 && duration <= 3600.0)) throw UsageError("option --duration: expected 0..3600 s");
  config.run_ticks = clock.TicksFor(duration);
  const double timeout_ms = args.GetDouble("hmd-timeout-ms", 1.0, 60'000.0);
  config.hmd_timeout_ns = static_cast<std::int64_t>(timeout_ms * 1e6);
  config.max_stop_ticks = clock.TicksFor(args.GetDouble("max-stop-s", 0.01, 3600.0));
  config.drive_return_ticks = clock.TicksFor(args.GetDouble("drive-return-s", 0.01, 3600.0));
  config.SetPlatform(platform.name, platform.mechanism);  // its drives: one per actuator
  config.session_id = static_cast<std::uint32_t>(hw::MonotonicNs() & 0x7FFFFFFF);
  const std::string hmd_spec = args.Get("hmd");
  config.hmd_required = hmd_spec != "none";
  const std::string bad = config.Validate();
  if (!bad.empty()) throw UsageError("session configuration: " + bad);

  // --link-key: both UDP links authenticated (hardware/link_auth.h).
  const std::optional<hw::LinkKey> key = LinkKeyOption(args, "session");
  // The CAN link: frames are taken from the peer only (address and port); others are counted.
  const std::string can_spec = args.Get("can");
  if (can_spec.rfind("udp:", 0) == 0) {
    std::string local = args.Get("can-local");
    if (local.empty()) {
      const auto remote = hw::ParseUdpAddress(can_spec.substr(4));
      local = remote && remote->ip == hw::ParseUdpAddress("127.0.0.1:0")->ip ? "127.0.0.1:0" : "0.0.0.0:0";
    } else if (!hw::ParseUdpAddress(local)) {
      throw UsageError("option --can-local: expected HOST:PORT, got '" + local + "'");
    }
    hw::UdpCanBus::Options link;
    link.key = key;
    setup->bus = hw::UdpCanBus::Open(local, can_spec.substr(4), link);
  } else if (can_spec.rfind("socketcan:", 0) == 0) {
    setup->bus = hw::OpenSocketCan(can_spec.substr(10));
  } else {
    throw UsageError("option --can: expected udp:HOST:PORT or socketcan:IFACE");
  }
  if (!setup->bus.bus) return "CAN link '" + can_spec + "': " + setup->bus.message;
  // The HMD link: head poses from the headset only; others are counted and never logged.
  if (config.hmd_required) {
    if (hmd_spec.rfind("udp:", 0) != 0 || !hw::ParseUdpAddress(hmd_spec.substr(4)))
      throw UsageError("option --hmd: expected udp:HOST:PORT or none");
    setup->hmd_peer = *hw::ParseUdpAddress(hmd_spec.substr(4));
    const std::string local = args.Get("hmd-local").empty() ? "0.0.0.0:0" : args.Get("hmd-local");
    if (!hw::ParseUdpAddress(local)) throw UsageError("option --hmd-local: expected HOST:PORT, got '" + local + "'");
    const std::string error = setup->hmd.Bind(*hw::ParseUdpAddress(local));
    if (!error.empty()) return "HMD link: " + error;
    setup->hmd.AcceptOnlyFrom(setup->hmd_peer);
    if (key) {
      setup->hmd.EnableAuth(*key, hw::LinkKind::kHmd, hw::LinkRole::kSession);
      (void)setup->hmd.SendHello(setup->hmd_peer);  // the headset learns our epoch at once
    }
  }
  return "";
}

int RunAndReport(const std::string& who, const ParsedArgs& args, SessionSetup& setup, hw::SessionSource& source,
                 const std::filesystem::path& out_dir,
                 const std::function<void(nlohmann::ordered_json&)>& add_to_report) {
  const hw::SessionConfig& config = setup.config;
  AtomicFileWriter log(out_dir / "session.log");
  AtomicFileWriter can_log(out_dir / "can.log");
  InstallStopSignalHandlers();
  std::cout << "  platform '" << config.platform << "': " << config.axis_count() << " drives (nodes";
  for (int i = 0; i < config.axis_count(); ++i)
    std::cout << (i == 0 ? " " : ", ") << static_cast<int>(config.master.axes[static_cast<std::size_t>(i)].node) << " "
              << config.mechanism.actuator(i).name;
  std::cout << ")\n";
  std::cout << "  CAN " << setup.bus.bus->name() << ", HMD "
            << (config.hmd_required ? std::to_string(setup.hmd.local_port()) + "->" + setup.hmd_peer.ToString()
                                    : "none")
            << ", drive cycle " << config.drive_cycle_ticks << " ticks, frame " << config.frame_ticks
            << " ticks, motion for " << static_cast<double>(config.run_ticks) / config.clock_rate_hz << " s\n"
            << std::flush;

  hw::RunnerIo io;
  io.bus = setup.bus.bus.get();
  io.hmd = config.hmd_required ? &setup.hmd : nullptr;
  io.hmd_peer = setup.hmd_peer;
  io.log = &log.stream();
  io.candump = &can_log.stream();
  io.events = &std::cout;  // event lines other processes can wait for
  io.events_prefix = who + ": event ";
  io.stop = &StopRequested();
  const long long rt = args.GetInt("rt-priority", 0, 99);
  io.rt_priority = static_cast<int>(rt);
  const double drive_wait_ms = args.GetDouble("drive-wait-ms", 0.0, 10'000.0);
  io.drive_answer_wait_ns = static_cast<std::int64_t>(drive_wait_ms * 1e6);
  if (rt > 0) {
    const std::string why = hw::EnterRealtime(io.rt_priority);
    std::cout << "  real-time: " << (why.empty() ? "SCHED_FIFO " + std::to_string(rt) : why) << "\n";
  }
  const hw::SessionReport report = hw::RunSession(config, source, io);
  log.Commit();
  can_log.Commit();
  if (add_to_report) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(report.ToJson());
    add_to_report(j);
    WriteFileAtomically(out_dir / "report.json", j.dump(2) + "\n");
  } else {
    WriteFileAtomically(out_dir / "report.json", report.ToJson());
  }

  std::cout << who << ": " << report.final_state << (report.stop_reason.empty() ? "" : " after " + report.stop_reason)
            << " (by the drives' feedback), " << report.steps << " steps\n";
  for (const hw::AxisReport& a : report.axes) {
    std::cout << "  drive " << a.node << " " << a.actuator << ": " << a.state << ", at " << a.position << " " << a.unit
              << ", " << a.velocity << " " << a.unit << "/s, last feedback " << a.feedback_age_ms << " ms before the end";
    if (a.restarts + a.returns > 0) std::cout << ", restarted " << a.restarts + a.returns << "x, re-admitted " << a.readmissions << "x";
    std::cout << "\n";
  }
  std::cout
            << "  cycle lateness p50 " << report.cycle_lateness_us.p50 << " us, p99 "
            << report.cycle_lateness_us.p99 << " us; period jitter p50 "
            << report.cycle_period_jitter_us.p50 << " us, p99 " << report.cycle_period_jitter_us.p99 << " us; "
            << report.schedule_slips << " schedule slips (" << report.schedule_slip_ms << " ms)\n"
            << "  visual-platform skew p50 " << report.skew_ms.p50 << " ms, p99 " << report.skew_ms.p99
            << " ms, jitter (sd) " << report.skew_ms.stddev << " ms over " << report.skew_ms.n << " frames\n";
  if (report.has_live_input) {  // the HMD part only with a headset (not --hmd none)
    std::cout << "  joystick -> platform command p50 " << report.input_to_platform_ms.p50 << " ms, p99 "
              << report.input_to_platform_ms.p99 << " ms";
    if (config.hmd_required) {
      std::cout << "; joystick -> HMD frame p50 " << report.input_to_hmd_ms.p50 << " ms, p99 "
                << report.input_to_hmd_ms.p99 << " ms (" << report.input_to_platform_ms.n << " / "
                << report.input_to_hmd_ms.n << " readings)\n";
    } else {
      std::cout << " (" << report.input_to_platform_ms.n << " readings; no headset: --hmd none)\n";
    }
  }
  std::cout << "  refused datagrams from senders other than the peers: CAN " << report.can_rx_refused << ", HMD "
            << report.hmd_rx_refused << "\n"
            << "  limits " << (report.limits_ok ? "respected" : "EXCEEDED") << " (commands), "
            << (report.within_limits ? "respected" : "EXCEEDED") << " (measured); "
            << (out_dir / "session.log").string() << ", " << (out_dir / "report.json").string() << "\n";
  // hw::SessionReport::ExitStatus: 0 parked (by the drives' feedback) without drive trouble, 3 not
  // parked or a limit exceeded, 4 fault, 5 feedback lost or quick stop, 6 parked after drive trouble.
  return report.ExitStatus();
}

}  // namespace pwsim::app
