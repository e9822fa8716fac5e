// pwsim replay LOG: re-runs a session log offline through the same session core and checks
// that every command, pose and packet comes out bit for bit as logged.

#include <fstream>
#include <iostream>

#include "app/commands.h"
#include "engine/atomic_file.h"
#include "hardware/session.h"

namespace pwsim::app {

const CommandSpec& ReplaySpec() {
  static const CommandSpec spec{
      "replay",
      "pwsim replay LOG [options]",
      "Replay a session log offline and check every output bit for bit.",
      {
          {"report", "FILE", "-", "", "write the replayed session's report.json here"},
      },
      "LOG  a session.log written by `pwsim session`"};
  return spec;
}

int ReplayCommand(const ParsedArgs& args) {
  if (args.positional().size() != 1) throw UsageError("expected one LOG");
  std::ifstream in(args.positional()[0]);
  if (!in) throw UsageError("cannot open '" + args.positional()[0] + "'");
  const hw::ReplayResult r = hw::ReplaySessionLog(in);
  if (!r.ok) {
    std::cerr << "pwsim replay: MISMATCH: " << r.message << "\n";
    return 1;
  }
  if (!args.Get("report").empty()) WriteFileAtomically(args.Get("report"), r.report.ToJson());
  std::cout << "pwsim replay: " << r.message << "\n";
  return 0;
}

}  // namespace pwsim::app
