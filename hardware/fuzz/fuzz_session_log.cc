// libFuzzer target: the session log reader behind `pwsim replay` (a log is outside input).
#include <cstdint>
#include <sstream>
#include <string>

#include "hardware/session.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 4096) return 0;
  static const std::string header = [] {
    pwsim::hw::SessionConfig c;
    c.run_ticks = 40;
    c.max_stop_ticks = 100;
    return std::string(pwsim::hw::kSessionLogMagic) + " " + c.ToHeader() + "\n";
  }();
  std::string text = header;
  text.append(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  (void)pwsim::hw::ReplaySessionLog(in);
  return 0;
}
