#include "hardware/session_replay.h"

#include <algorithm>
#include <cmath>

#include "hardware/session_text.h"

namespace pwsim::hw {
void AppendInputLines(std::int64_t tick, const SessionInputs& in, LogLines* lines) {
  lines->Line('T').Int(tick).Int(in.now_ns).Int(in.scheduled_ns);
  if (in.setpoint) {
    lines->Line('M').Int(tick);
    for (double x : *in.setpoint) lines->Num(x);
  }
  if (in.camera) lines->Line('K').Int(tick).PoseNums(*in.camera);
  if (in.stop_request) lines->Line('X').Int(tick);
  for (const RxFrame& r : in.can) lines->Line('C').Int(r.rx_ns).Frame(r.frame);
  for (const RxDatagram& d : in.hmd) lines->Line('H').Int(d.rx_ns).Hex(d.bytes);
}

void AppendInputLines(std::int64_t tick, const SessionInputs& in, std::vector<std::string>* lines) {
  LogLines text;
  AppendInputLines(tick, in, &text);
  for (std::string_view l : text) lines->emplace_back(l);
}

ReplayResult ReplaySessionLog(std::istream& log) {
  ReplayResult result;
  std::string line;
  std::int64_t number = 0;
  std::optional<SessionCore> core;
  SessionInputs in;
  std::int64_t tick = -1;
  std::vector<std::string> expected;
  std::vector<std::int64_t> expected_line;
  SessionOutputs out;
  auto fail = [&](std::int64_t at, const std::string& why) {
    result.ok = false;
    result.unreadable = true;
    result.message = "line " + std::to_string(at) + ": " + why;
    return result;
  };
  auto flush = [&]() -> bool {
    if (tick < 0) return true;
    out.Clear();
    core->Step(tick, in, &out);
    ++result.steps;
    const std::size_t n = std::min(out.log.size(), expected.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (out.log[i] != expected[i]) {
        result.message = "line " + std::to_string(expected_line[i]) + ": replay gives '" +
                         std::string(out.log[i]) + "', log has '" + expected[i] + "'";
        return false;
      }
      ++result.lines_compared;
    }
    if (out.log.size() != expected.size()) {
      result.message = "tick " + std::to_string(tick) + ": replay gives " +
                       std::to_string(out.log.size()) + " output lines, log has " +
                       std::to_string(expected.size());
      return false;
    }
    in = SessionInputs{};
    expected.clear();
    expected_line.clear();
    return true;
  };
  while (std::getline(log, line)) {
    ++number;
    if (line.empty()) continue;
    if (line[0] == '#') {
      if (!core && line.rfind("# pwsim-session-log/", 0) == 0) {
        if (line.rfind(std::string(kSessionLogMagic) + " ", 0) != 0)
          return fail(number, "a session log of another format ('" + line.substr(0, line.find(' ', 2)) +
                                  "'): this pwsim replays '" + kSessionLogMagic + "' logs");
        std::string error;
        auto config = SessionConfig::FromHeader(line, &error);
        if (!config) return fail(number, error);
        core.emplace(*config);
      }
      continue;
    }
    if (!core) return fail(number, std::string("no '") + kSessionLogMagic + "' header before the first record");
    const auto parts = SplitWords(line);
    const char kind = line[0];
    if (line.size() < 2 || line[1] != ' ') return fail(number, "expected '<kind> ...'");
    switch (kind) {
      case 'T': {
        if (!flush()) {
          result.ok = false;
          return result;
        }
        std::int64_t t = 0;
        if (parts.size() != 4 || !ParseI64(parts[1], &t) || !ParseI64(parts[2], &in.now_ns) ||
            !ParseI64(parts[3], &in.scheduled_ns))
          return fail(number, "bad T record");
        // Ticks increase, by at most 10^6 at a time (the runner steps every drive cycle).
        if (t <= tick || t > tick + 1'000'000) return fail(number, "tick out of sequence");
        tick = t;
        break;
      }
      case 'M': {
        mca::DofArray sp{};
        if (parts.size() != 2 + sp.size()) return fail(number, "bad M record (expected tick and 6 pose numbers)");
        for (std::size_t k = 0; k < sp.size(); ++k)
          if (!ParseF64(parts[2 + k], &sp[k])) return fail(number, "bad M record");
        in.setpoint = sp;
        break;
      }
      case 'K': {
        Pose p;
        if (parts.size() != 9) return fail(number, "bad K record");
        for (std::size_t i = 0; i < 3; ++i)
          if (!ParseF64(parts[2 + i], &p.p[i])) return fail(number, "bad K record");
        for (std::size_t i = 0; i < 4; ++i)
          if (!ParseF64(parts[5 + i], &p.q[i])) return fail(number, "bad K record");
        in.camera = p;
        break;
      }
      case 'X': in.stop_request = true; break;
      case 'C': {
        RxFrame r;
        if (parts.size() != 3 || !ParseI64(parts[1], &r.rx_ns) ||
            ParseFrameText(parts[2], &r.frame) != CodecError::kOk)
          return fail(number, "bad C record");
        in.can.push_back(r);
        break;
      }
      case 'H': {
        RxDatagram d;
        if (parts.size() != 3 || !ParseI64(parts[1], &d.rx_ns) || !HexDecode(parts[2], &d.bytes))
          return fail(number, "bad H record");
        in.hmd.push_back(std::move(d));
        break;
      }
      case 'c': case 'h': case 'S': case 'P': case 'E':
        expected.push_back(line);
        expected_line.push_back(number);
        break;
      default:
        return fail(number, std::string("unknown record kind '") + kind + "'");
    }
  }
  if (!core) return fail(number, "empty log");
  if (!flush()) {
    result.ok = false;
    return result;
  }
  result.ok = true;
  result.report = core->Report();
  result.message = "replayed " + std::to_string(result.steps) + " steps, " +
                   std::to_string(result.lines_compared) + " output lines identical";
  return result;
}


}  // namespace pwsim::hw
