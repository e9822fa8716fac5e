#pragma once
// Input -> output latency of a live session (a joystick driving the vehicle): for each new
// input reading, the time from when it reached this process to when the first output computed
// from it left (the send call returned):
//
//   latency(reading i, output kind) = t_sent(first output of that kind after reading i) - t_in(i)
//
// Output kinds: the platform command (the drive cycle's RPDOs + SYNC, joystick -> platform) and
// the HMD frame (CAMERA_POSE, joystick -> HMD). A reading superseded before any output was sent
// is not counted (no output ever showed it). The wire, the drives' servo lag and the display are
// outside this figure; the visual-platform skew of session_report.h covers the far side.
// Generic: any source that stamps its inputs (InputStamp) plugs in; the buffer is reserved up
// front, so recording allocates nothing in the real-time loop.

#include <cstdint>
#include <vector>

#include "hardware/session_report.h"

namespace pwsim::hw {

/// Which input reading an output derives from: seq counts readings (0 = none yet), input_ns is
/// when that reading reached the process [ns, CLOCK_MONOTONIC].
struct InputStamp {
  std::uint64_t seq{0};
  std::int64_t input_ns{-1};
};

class InputLatency {
 public:
  explicit InputLatency(std::size_t capacity = 1U << 18);
  /// An output derived from `input` left at `sent_ns`; counted once per reading.
  void OnOutput(const InputStamp& input, std::int64_t sent_ns);
  /// Latencies [ms]: n, p50, p99, max, mean, stddev.
  Percentiles Summary() const;
  std::uint64_t overflow() const { return overflow_; }  ///< readings beyond the capacity

 private:
  std::vector<double> ms_;
  std::size_t capacity_;
  std::uint64_t last_seq_{0};
  std::uint64_t overflow_{0};
};

}  // namespace pwsim::hw
