// pwsim replay LOG: re-runs a session log offline through the same session core and checks
// that every command, pose and packet comes out bit for bit as logged.
//
// Exit status: 0 every output line identical; 1 the log cannot be read or is malformed (bad
// input, as for every command: "LOG:LINE: field 'record': expected ..., got ..."); 2 a usage
// error; 3 the log reads but the replay differs from it (a real mismatch: the first differing
// line is named).

#include <fstream>
#include <iostream>
#include <string>

#include "app/commands.h"
#include "engine/atomic_file.h"
#include "engine/input_error.h"
#include "hardware/session.h"

namespace pwsim::app {
namespace {

/// The exit status of a replay that read the log and found an output that differs.
constexpr int kExitMismatch = 3;

/// Line `number` of `file` (1-based), cut to 80 characters; "" when there is none.
std::string LineText(const std::string& file, int number) {
  std::ifstream in(file);
  std::string text;
  for (int k = 0; k < number && std::getline(in, text); ++k) {
  }
  if (number < 1 || !in) return "";
  return text.size() > 80 ? text.substr(0, 77) + "..." : text;
}

}  // namespace

const CommandSpec& ReplaySpec() {
  static const CommandSpec spec{
      "replay",
      "pwsim replay LOG [options]",
      "Replay a session log offline and check every output bit for bit (exit 0 identical, 1 unreadable log, "
      "3 mismatch).",
      {
          {"report", "FILE", "", "", "write the replayed session's report.json here"},
      },
      "LOG  a session.log written by `pwsim session` or `pwsim drive`"};
  return spec;
}

int ReplayCommand(const ParsedArgs& args) {
  if (args.positional().size() != 1) throw UsageError("expected one LOG");
  const std::string file = args.positional()[0];
  RequireReadableFile(file, "a session log (pwsim session, pwsim drive)");
  std::ifstream in(file);
  if (!in) throw InputError(file, 0, "(file)", "a readable session log", "cannot open");
  const hw::ReplayResult r = hw::ReplaySessionLog(in);
  if (!r.ok && r.unreadable) {
    // "line N: why" -> file:N, the record's problem as the expectation
    int line = 0;
    std::string why = r.message;
    if (r.message.rfind("line ", 0) == 0) {
      const std::size_t colon = r.message.find(": ");
      try {
        line = std::stoi(r.message.substr(5, colon - 5));
        why = r.message.substr(colon + 2);
      } catch (const std::exception&) {
        line = 0;
      }
    }
    const std::string text = LineText(file, line);
    throw InputError(file, line, "record", "a well-formed session log (records of hardware/session_core.h)",
                     why + (text.empty() ? "" : " in \"" + text + "\""));
  }
  if (!r.ok) {
    std::cerr << "pwsim replay: MISMATCH in " << file << ": " << r.message << "\n";
    return kExitMismatch;
  }
  if (!args.Get("report").empty()) WriteFileAtomically(args.Get("report"), r.report.ToJson());
  std::cout << "pwsim replay: " << file << ": " << r.message << "\n";
  return 0;
}

}  // namespace pwsim::app
