#pragma once
// What `pwsim session` and `pwsim drive --can ...` share: the live session's options (links,
// timing, timeouts), the configuration built from them, the two links opened (each taking
// datagrams from its peer only), and the run with its outputs (session.log, can.log,
// report.json) and summary. Wiring only.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "engine/clock.h"
#include "hardware/session_runner.h"
#include "hardware/session_streams.h"
#include "hardware/udp_socket.h"
#include "mca/config.h"

namespace pwsim::app {

/// --can, --can-local, --hmd, --hmd-local, --drive-cycle-ms, --frame-ms, --hmd-timeout-ms,
/// --max-stop-s, --drive-return-s, --rt-priority, --drive-wait-ms.
std::vector<OptionSpec> SessionLinkOptions();

struct SessionSetup {
  hw::SessionConfig config;
  hw::BusOpenResult bus;
  hw::UdpSocket hmd;
  hw::UdpAddress hmd_peer;
};

/// --mca washout|mpc (pwsim session, drive, omct): the cueing that overrides the scene's
/// mca.algorithm, or nothing when the option is absent. @throws UsageError on another value.
std::optional<mca::McaAlgorithm> McaAlgorithmOption(const ParsedArgs& args);
/// The option's spec line for a command's table.
OptionSpec McaAlgorithmOptionSpec();

/// --platform FILE (pwsim session, drive): the platform over the scene's, or nothing when absent.
/// @throws InputError (the file).
std::optional<hw::PlatformChoice> PlatformOption(const ParsedArgs& args);
OptionSpec PlatformOptionSpec();

/// The configuration for `duration_s` of motion on `clock`, driving `platform`'s mechanism (one
/// CiA 402 node per actuator), and the links opened. Returns "" or why a link could not be
/// opened. @throws UsageError on bad options.
std::string SetUpSession(const ParsedArgs& args, const Clock& clock, double duration_s, const mca::PlatformSpec& platform,
                         SessionSetup* setup);

/// Runs the session from `source`, writes OUT/session.log, can.log, report.json, prints the
/// summary and each event line as it happens ("WHO: event TICK ..."); returns the exit status
/// (hw::SessionReport::ExitStatus: 0 only when the drives' feedback shows the platform parked
/// and no drive was lost, restarted, quick-stopped or faulted).
/// `add_to_report`, when given, adds its sections to report.json after the run (e.g. a chair
/// drive's training metrics).
int RunAndReport(const std::string& who, const ParsedArgs& args, SessionSetup& setup, hw::SessionSource& source,
                 const std::filesystem::path& out_dir,
                 const std::function<void(nlohmann::ordered_json&)>& add_to_report = {});

}  // namespace pwsim::app
