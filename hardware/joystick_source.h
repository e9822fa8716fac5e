#pragma once
// A joystick as a live drive sees it: once per engine tick, a deflection (x, y) and whether
// it is valid. x is to the right, y forward, both in [-1, 1] (full deflection); an invalid
// sample always carries (0, 0), so a consumer that ignores the flag still stops.
//
//   JoystickSample s = joystick.Poll(tick, MonotonicNs());
//   if (!s.valid) ... brake: the source lost its device or its frames (watchdog)
//
// Implementations: R-Net CAN frames (rnet_joystick.h: SocketCAN listen-only, a candump log, or
// any CanListener) and SDL2 joysticks (sdl/sdl_joystick.h).

#include <cstdint>
#include <string>

namespace pwsim::hw {

struct JoystickSample {
  double x{0.0};      ///< right deflection, -1 (full left) .. 1 (full right)
  double y{0.0};      ///< forward deflection, -1 (full reverse) .. 1 (full forward)
  bool valid{false};  ///< a fresh reading from a present device
  /// When the input that set (x, y) reached this process [ns, CLOCK_MONOTONIC], or -1: the
  /// start of the joystick -> platform / HMD latency (input_latency.h).
  std::int64_t input_ns{-1};
  /// Counts every new input reading (frame, device state change); lets a consumer tell which
  /// reading an output derives from.
  std::uint64_t input_seq{0};
};

class JoystickSource {
 public:
  virtual ~JoystickSource() = default;
  /// The reading for engine tick `tick` at monotonic time `now_ns`. Never blocks or throws.
  virtual JoystickSample Poll(std::int64_t tick, std::int64_t now_ns) = 0;
  /// A source of frames (a live bus) may expose a file descriptor that polls readable when
  /// input waits, and take it between ticks: Take stamps what waits with `now_ns` (its
  /// arrival, for latency) and counts it for the coming tick `tick`. Default: none.
  virtual int fd() const { return -1; }
  virtual void Take(std::int64_t /*tick*/, std::int64_t /*now_ns*/) {}
  virtual std::string name() const = 0;
};

}  // namespace pwsim::hw
