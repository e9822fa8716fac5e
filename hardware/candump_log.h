#pragma once
// candump log files as can-utils writes them (`candump -l`): one frame a line,
//   (1700000000.123456) can0 123#DEADBEEF
// readable by can-utils' log2long, log2asc and canplayer. Timestamps are kept in integer
// microseconds so a log reads back exactly.

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "hardware/can_frame.h"

namespace pwsim::hw {

struct CandumpRecord {
  std::int64_t time_us{0};  ///< microseconds (the log's seconds.microseconds)
  std::string iface;        ///< e.g. "can0"
  CanFrame frame;
  bool operator==(const CandumpRecord&) const = default;
};

std::string FormatCandumpLine(const CandumpRecord& record);
/// Parses one line (no newline). kBadSyntax names malformed timestamps/interfaces.
CodecError ParseCandumpLine(std::string_view line, CandumpRecord* record);

class CandumpWriter {
 public:
  explicit CandumpWriter(std::ostream& out, std::string iface = "can0")
      : out_(out), iface_(std::move(iface)) {}
  void Write(std::int64_t time_us, const CanFrame& frame);
  std::uint64_t lines() const { return lines_; }

 private:
  std::ostream& out_;
  std::string iface_;
  std::uint64_t lines_{0};
};

/// Reads every record of a log; empty lines are skipped. Returns the 1-based line of the
/// first malformed line in `bad_line` (0 when all good) and stops there.
std::vector<CandumpRecord> ReadCandumpLog(std::istream& in, int* bad_line, CodecError* error);

}  // namespace pwsim::hw
