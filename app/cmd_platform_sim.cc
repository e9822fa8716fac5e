// pwsim platform-sim: the platform's CiA 402 servo drives, simulated, one node per actuator of
// the mechanism of --platform FILE (node = 1 + actuator index; each actuator's servo with its
// stroke, speed, acceleration and force limits, the plate pose measured by forward kinematics;
// default and for car2dof: the car's yaw and rail on seed 001's 2-DoF Lagrange model with dry +
// viscous friction and joint PID), behind CAN over UDP in cannelloni framing. A session
// connects with --can udp:HOST:PORT. The drives take frames from one peer only: the session's
// CAN address given with --peer, or (tests, demos) with --adopt-first-peer the sender that runs
// a CANopen master's start-up (NMT to the drives' nodes, then SYNC; with --link-key: an
// authenticated sender); frames from anyone else are counted and dropped (udp_can_bus.h).
// Wiring only: see hardware/.

#include <csignal>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/link_key_option.h"
#include "app/stop_signal.h"
#include "engine/atomic_file.h"
#include "engine/number_format.h"
#include "hardware/candump_log.h"
#include "hardware/platform_chirp.h"
#include "sysid/platform/axis_recording.h"
#include "hardware/simulated_drives.h"
#include "hardware/udp_can_bus.h"
#include "mca/platform.h"

namespace pwsim::app {
const CommandSpec& PlatformSimSpec() {
  static const CommandSpec spec{
      "platform-sim",
      "pwsim platform-sim [options]",
      "Simulated CiA 402 drives of a platform's actuators (default: the 2-DoF rail+yaw car of seed 001) on CAN over UDP.",
      {
          {"listen", "HOST:PORT", "-", "127.0.0.1:29536", "UDP address to serve the CAN link on (port 0: any free port; the line 'listening on HOST:PORT' names it)"},
          {"peer", "udp:HOST:PORT", "-", "", "the session's CAN address (pwsim session --can-local): the only sender whose frames are taken"},
          {"adopt-first-peer", "", "-", "", "instead of --peer: the sender that starts the drives as a CANopen master does (NMT to their nodes, then SYNC) becomes the only peer (tests and demos on one machine); a first datagram alone adopts no one"},
          LinkKeyOptionSpec(),
          {"platform", "FILE", "-", "", "platform file (pwsim-platform/1, e.g. scenes/platforms/pw4dof.yaml): one drive per actuator, node 1 + its index (default: the car, yaw node 1, rail node 2)"},
          {"cycle-ms", "MS", "ms", "4", "SYNC period the drives interpolate over"},
          {"duration", "S", "s", "0", "exit after this long (0 = until idle or signal)"},
          {"idle-exit", "S", "s", "2", "exit when no frame arrived for this long after a master was seen"},
          {"exit-after", "S", "s", "0", "vanish abruptly this long after the master's first frame (fault injection; 0 = never)"},
          {"fault-at", "S", "s", "0", "drive fault (EMCY 0x5530 on --fault-node) this long after the master's first frame (0 = never)"},
          {"fault-node", "N", "-", "2", "the node --fault-at faults (the car's rail is node 2)"},
          {"candump", "FILE", "-", "", "write the bus traffic as a candump log"},
          {"report", "FILE", "-", "", "write a JSON summary, atomically: per actuator its stroke use, peak speed, acceleration and effort against its limits and whether one was exceeded (sampled on every simulation substep), its state; the plate pose by forward kinematics"},
          {"chirp", "FILE.yaml", "-", "",
           "instead of serving CAN: run the chirp experiment offline and write the recording "
           "(pwsim-axis-trial/1 + CSV) for `pwsim platform frequency-response`"},
          {"chirp-joint", "rail|yaw", "-", "rail", "joint swept by the chirp"},
          {"chirp-w0", "W", "rad/s", "1", "sweep start frequency"},
          {"chirp-w1", "W", "rad/s", "300", "sweep end frequency"},
          {"chirp-sweep", "S", "s", "20", "duration of one sweep"},
          {"chirp-sweeps", "N", "-", "3", "number of identical sweeps"},
          {"chirp-amplitude", "A", "m or rad", "0.05", "amplitude at low frequency"},
          {"chirp-max-accel", "A", "m/s^2 or rad/s^2", "0",
           "amplitude limited to a_max/w^2 (0 = half the effort limit over the inertia)"},
      },
      ""};
  return spec;
}

namespace {

// The chirp experiment: simulate, then write the recording in the platform-data format.
int RunChirpExperiment(const ParsedArgs& args) {
  hw::ChirpParams c;
  const std::string joint = args.Get("chirp-joint");
  if (joint != "rail" && joint != "yaw") throw UsageError("option --chirp-joint: expected rail or yaw");
  c.joint = joint == "yaw" ? 0 : 1;
  c.w0_rad_s = args.GetDouble("chirp-w0");
  c.w1_rad_s = args.GetDouble("chirp-w1");
  c.sweep_s = args.GetDouble("chirp-sweep");
  c.sweeps = static_cast<int>(args.GetInt("chirp-sweeps"));
  c.amplitude = args.GetDouble("chirp-amplitude");
  c.max_accel = args.GetDouble("chirp-max-accel");
  const hw::PlatformParams platform;
  const hw::ChirpRecord rec = hw::RunChirp(c, platform);
  sysid::platform::AxisRecording r;
  r.file = args.Get("chirp");
  r.experiment = "chirp";
  r.t = rec.t;
  r.dt = c.sample_s;
  const char* names[2] = {"yaw", "rail"};
  const double gears[2] = {platform.gear1, platform.gear2};
  for (std::size_t j = 0; j < 2; ++j) {
    sysid::platform::JointRecording jr;
    jr.name = names[j];
    jr.kind = j == 0 ? sysid::platform::JointKind::kRevolute : sysid::platform::JointKind::kPrismatic;
    jr.position = rec.q[j];
    jr.reference = rec.q_ref[j];
    jr.command_to_effort = gears[j];  // command = actuator effort, tau_i = K_i tau_a,i (eq. 13)
    for (double tau : rec.tau[j]) jr.command.push_back(tau / gears[j]);
    jr.effort = rec.tau[j];
    r.joints.push_back(std::move(jr));
  }
  sysid::platform::WriteAxisRecordingCsv(r, args.Get("chirp"));
  std::cout << "pwsim platform-sim: chirp on " << joint << ", " << rec.t.size()
            << " samples, a_max " << rec.max_accel << ", wrote " << args.Get("chirp") << "\n";
  if (rec.saturated_samples > 0)
    std::cout << "pwsim platform-sim: warning: the actuator saturated on " << rec.saturated_samples
              << " samples; the response is not linear (lower --chirp-amplitude or "
                 "--chirp-max-accel)\n";
  return 0;
}

}  // namespace

int PlatformSimCommand(const ParsedArgs& args) {
  if (!args.positional().empty()) throw UsageError("takes no positional arguments");
  if (!args.Get("chirp").empty()) return RunChirpExperiment(args);
  const double cycle_ms = args.GetDouble("cycle-ms", 0.5, 100.0);
  const double duration = args.GetDouble("duration", 0.0, 86400.0);
  const double idle_exit = args.GetDouble("idle-exit", 0.0, 86400.0);
  const double exit_after = args.GetDouble("exit-after", 0.0, 86400.0);
  const double fault_at = args.GetDouble("fault-at", 0.0, 86400.0);
  const auto fault_node = static_cast<int>(args.GetInt("fault-node", 1, 127));

  const bool adopt = args.Flag("adopt-first-peer");
  std::string peer = args.Get("peer");
  if (adopt == !peer.empty())
    throw UsageError("give the session's CAN address with --peer udp:HOST:PORT, or --adopt-first-peer (not both)");
  if (!peer.empty()) {
    if (peer.rfind("udp:", 0) != 0 || !hw::ParseUdpAddress(peer.substr(4)))
      throw UsageError("option --peer: expected udp:HOST:PORT, got '" + peer + "'");
    peer = peer.substr(4);
  }
  // The drives: one CiA 402 node per actuator of the platform's mechanism, node 1 + its index.
  std::string platform_name = "car2dof (built in)";
  mca::Mechanism mechanism = hw::SimulatedDrives::CarMechanism();
  if (!args.Get("platform").empty()) {
    const mca::PlatformSpec spec = mca::ReadPlatformFile(args.Get("platform"));
    platform_name = spec.name;
    mechanism = spec.mechanism;
  }
  if (const std::string why = mechanism.Validate(); !why.empty())
    throw std::invalid_argument(args.Get("platform") + ": " + why);
  std::vector<std::uint8_t> nodes;
  for (int i = 0; i < mechanism.actuator_count(); ++i) nodes.push_back(static_cast<std::uint8_t>(1 + i));
  if (fault_at > 0 && fault_node > mechanism.actuator_count())
    throw UsageError("option --fault-node: this platform's drives are nodes 1 to " +
                     std::to_string(mechanism.actuator_count()));
  hw::UdpCanBus::Options link;  // adoption needs a master's start-up to the drives' nodes
  link.policy = adopt ? hw::UdpCanBus::PeerPolicy::kAdoptConfirmed : hw::UdpCanBus::PeerPolicy::kConfigured;
  if (adopt) link.confirm = hw::MasterStartsNodes(nodes);  // the drives' node ids
  link.key = LinkKeyOption(args, "platform-sim");
  link.role = hw::LinkRole::kPeer;
  hw::BusOpenResult opened = hw::UdpCanBus::Open(args.Get("listen"), peer, link);
  if (!opened.bus) {
    std::cerr << "pwsim platform-sim: " << opened.message << "\n";
    return 1;
  }
  hw::UdpCanBus& bus = static_cast<hw::UdpCanBus&>(*opened.bus);
  std::ofstream dump_file;
  std::unique_ptr<hw::CandumpWriter> dump;
  if (!args.Get("candump").empty()) {
    dump_file.open(args.Get("candump"));
    dump = std::make_unique<hw::CandumpWriter>(dump_file, "can0");
  }
  hw::DriveSimConfig config;
  config.cycle_s = cycle_ms / 1000.0;
  hw::SimulatedDrives drives(mechanism, config);
  InstallStopSignalHandlers();
  hw::UdpAddress bound = *hw::ParseUdpAddress(args.Get("listen"));  // Open parsed it already
  bound.port = bus.local_port();
  std::string drive_list;
  for (int i = 0; i < drives.axis_count(); ++i)
    drive_list += (i == 0 ? "" : ", ") + std::to_string(drives.node(i)) + " (" + mechanism.actuator(i).name + ")";
  std::cout << "pwsim platform-sim: " << platform_name << ", drives " << drive_list
            << (drives.uses_car_plant() ? " on seed 001's Lagrange plant" : " (actuator servos)") << ", on "
            << bus.name() << ", frames taken from "
            << (adopt ? "the master that starts them" : peer) << " only\n"
            << "pwsim platform-sim: listening on " << bound.ToString() << "\n"
            << std::flush;

  // The fault-injection times count from the master's first frame, not from this process's
  // start, so that they fall at the same point of the session however long it took to start.
  const std::int64_t start = hw::MonotonicNs();
  std::int64_t first_rx = -1;
  std::int64_t last_rx = start;
  bool master_seen = false;
  bool faulted = false;
  bool enabled_said = false;
  std::uint64_t refused_said = 0;
  std::vector<hw::CanFrame> out;
  std::string why = "signal";
  for (;;) {
    if (StopRequested()) break;
    const std::int64_t now = hw::MonotonicNs();
    const double t = static_cast<double>(now - start) / 1e9;
    if (duration > 0 && t >= duration) {
      why = "duration reached";
      break;
    }
    const double t_master = first_rx < 0 ? -1.0 : static_cast<double>(now - first_rx) / 1e9;
    if (exit_after > 0 && t_master >= exit_after) {
      std::cout << "pwsim platform-sim: vanishing " << t_master << " s after the master's first frame (--exit-after)\n"
                << std::flush;
      return 0;
    }
    if (master_seen && idle_exit > 0 && static_cast<double>(now - last_rx) / 1e9 >= idle_exit) {
      why = "master idle";
      break;
    }
    out.clear();
    if (fault_at > 0 && t_master >= fault_at && !faulted) {
      faulted = true;
      drives.InjectFault(fault_node - 1, 0x5530, &out);
    }
    hw::WaitReadable(bus, 1);
    hw::CanFrame f;
    while (bus.Receive(&f) == hw::BusStatus::kOk) {
      const std::int64_t rx = hw::MonotonicNs();
      if (dump) dump->Write(rx / 1000, f);
      drives.OnFrame(f, rx, &out);
      last_rx = rx;
      if (first_rx < 0) first_rx = rx;
      master_seen = true;
    }
    drives.Poll(hw::MonotonicNs(), &out);
    for (const hw::CanFrame& x : out) {
      if (bus.Send(x) == hw::BusStatus::kOk && dump) dump->Write(hw::MonotonicNs() / 1000, x);
    }
    // Events other processes can wait for (lines on stdout, never timing).
    if (!enabled_said && drives.all_enabled()) {
      enabled_said = true;
      std::cout << "pwsim platform-sim: operation enabled, master " << bus.peer() << "\n" << std::flush;
    }
    if (bus.stats().rx_refused != refused_said) {
      refused_said = bus.stats().rx_refused;
      std::cout << "pwsim platform-sim: refused " << refused_said << " datagrams from senders other than "
                << (bus.has_peer() ? bus.peer() : "the peer") << "\n" << std::flush;
    }
  }
  const auto& peak = drives.peak_abs_position();
  std::cout << "pwsim platform-sim: stopped (" << why << "), " << drives.syncs() << " SYNCs, refused "
            << bus.stats().rx_refused << " datagrams from other senders\n";
  std::istringstream summary(hw::DrivesSummaryText(drives));  // what the actuators did, in words
  for (std::string line; std::getline(summary, line);) std::cout << "pwsim platform-sim: " << line << "\n";
  if (!args.Get("report").empty()) {
    std::ostringstream r;
    r << "{\n  \"format\": \"pwsim-platform-sim-report/1\",\n  \"syncs\": " << drives.syncs()
      << ",\n  \"peer\": \"" << bus.peer() << "\",\n  \"frames_taken\": " << bus.stats().rx
      << ",\n  \"refused_datagrams\": " << bus.stats().rx_refused
      << ",\n  \"malformed_datagrams\": " << bus.stats().rx_malformed
      << ",\n  \"platform\": \"" << platform_name << "\"";
    auto per_axis = [&](const char* key, auto value) {  // one number per drive, node order
      r << ",\n  \"" << key << "\": [";
      for (int i = 0; i < drives.axis_count(); ++i) r << (i == 0 ? "" : ", ") << FormatDouble(value(i));
      r << "]";
    };
    per_axis("peak_abs_position", [&](int i) { return peak[static_cast<std::size_t>(i)]; });
    per_axis("final_position", [&](int i) { return drives.position(i); });
    per_axis("final_velocity", [&](int i) { return drives.velocity(i); });
    r << ",\n  \"master_lost\": " << (drives.master_lost() ? "true" : "false");
    if (drives.uses_car_plant())
      r << ",\n  \"rail_state\": \"" << hw::canopen::DriveStateName(drives.drive_state(1)) << "\"";
    r << ",\n" << hw::DrivesReportJsonMembers(drives) << "\n}\n";
    WriteFileAtomically(args.Get("report"), r.str());
  }
  return 0;
}

}  // namespace pwsim::app
