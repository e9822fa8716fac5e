#pragma once
// The session log: the input lines of a step, and the offline replay that feeds a log's inputs
// back through a fresh SessionCore and compares every output line, bit for bit.

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "hardware/session_core.h"
#include "hardware/session_report.h"
#include "hardware/session_text.h"

namespace pwsim::hw {

/// The input lines for one step (T, M, K, X, C, H), in the order Replay reads them; the line
/// formats are in session_core.h.
void AppendInputLines(std::int64_t tick, const SessionInputs& in, LogLines* lines);
void AppendInputLines(std::int64_t tick, const SessionInputs& in, std::vector<std::string>* lines);

struct ReplayResult {
  bool ok{false};
  std::int64_t steps{0};
  std::int64_t lines_compared{0};
  std::string message;  ///< first mismatch or parse error
  bool unreadable{false};  ///< the log itself is malformed (message: "line N: why"), not a mismatch
  SessionReport report;
};
/// Re-runs a session log offline and compares every output line.
ReplayResult ReplaySessionLog(std::istream& log);

}  // namespace pwsim::hw
