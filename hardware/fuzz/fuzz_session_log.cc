// libFuzzer target: the session log reader behind `pwsim replay` (a log is outside input).
#include <cstdint>
#include <sstream>
#include <string>

#include "hardware/session.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 4096) return 0;
  std::string text =
      "# pwsim-session-log/1 clock_rate_hz=1000 drive_cycle_ticks=4 frame_ticks=10 "
      "ping_every_frames=10 run_ticks=40 max_stop_ticks=100 hmd_timeout_ns=250000000 "
      "hmd_required=1 session_id=1\n";
  text.append(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  (void)pwsim::hw::ReplaySessionLog(in);
  return 0;
}
