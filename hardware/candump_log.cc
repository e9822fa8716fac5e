#include "hardware/candump_log.h"

#include <cstdio>

namespace pwsim::hw {

std::string FormatCandumpLine(const CandumpRecord& record) {
  const std::int64_t t = record.time_us < 0 ? 0 : record.time_us;
  char stamp[40];
  std::snprintf(stamp, sizeof(stamp), "(%lld.%06lld) ", static_cast<long long>(t / 1000000),
                static_cast<long long>(t % 1000000));
  return stamp + record.iface + " " + FormatFrameText(record.frame);
}

CodecError ParseCandumpLine(std::string_view line, CandumpRecord* record) {
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
  if (line.size() < 4 || line[0] != '(') return CodecError::kBadSyntax;
  const std::size_t close = line.find(')');
  if (close == std::string_view::npos) return CodecError::kBadSyntax;
  const std::string_view stamp = line.substr(1, close - 1);
  const std::size_t dot = stamp.find('.');
  if (dot == std::string_view::npos || dot == 0 || stamp.size() - dot - 1 != 6 || dot > 12)
    return CodecError::kBadSyntax;
  std::int64_t sec = 0;
  std::int64_t usec = 0;
  for (std::size_t i = 0; i < stamp.size(); ++i) {
    if (i == dot) continue;
    const char c = stamp[i];
    if (c < '0' || c > '9') return CodecError::kBadSyntax;
    if (i < dot) {
      sec = sec * 10 + (c - '0');
    } else {
      usec = usec * 10 + (c - '0');
    }
  }
  if (close + 1 >= line.size() || line[close + 1] != ' ') return CodecError::kBadSyntax;
  const std::string_view rest = line.substr(close + 2);
  const std::size_t space = rest.find(' ');
  if (space == std::string_view::npos || space == 0 || space > 15) return CodecError::kBadSyntax;
  std::string_view frame_text = rest.substr(space + 1);
  // candump -l may append " T"/" R" (direction) or flags after the frame: ignore one token.
  const std::size_t extra = frame_text.find(' ');
  if (extra != std::string_view::npos) frame_text = frame_text.substr(0, extra);
  CandumpRecord r;
  r.time_us = sec * 1000000 + usec;
  r.iface = std::string(rest.substr(0, space));
  const CodecError e = ParseFrameText(frame_text, &r.frame);
  if (e != CodecError::kOk) return e;
  *record = std::move(r);
  return CodecError::kOk;
}

void CandumpWriter::Write(std::int64_t time_us, const CanFrame& frame) {
  out_ << FormatCandumpLine({time_us, iface_, frame}) << '\n';
  ++lines_;
}

std::vector<CandumpRecord> ReadCandumpLog(std::istream& in, int* bad_line, CodecError* error) {
  std::vector<CandumpRecord> records;
  std::string line;
  int number = 0;
  *bad_line = 0;
  *error = CodecError::kOk;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line == "\r") continue;
    CandumpRecord r;
    const CodecError e = ParseCandumpLine(line, &r);
    if (e != CodecError::kOk) {
      *bad_line = number;
      *error = e;
      break;
    }
    records.push_back(std::move(r));
  }
  return records;
}

}  // namespace pwsim::hw
