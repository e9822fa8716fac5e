#pragma once
// The engine's clock: an integer tick count at a fixed rate. Time is always tick * dt, never a
// running sum, so tick k has the same time in every run and every consumer (video frame k is
// tick k·N exactly).

#include <cstdint>

#include "engine/check.h"

namespace pwsim {

struct Clock {
  int rate_hz{1000};  ///< ticks per second

  double dt() const { return 1.0 / rate_hz; }                       ///< [s]
  double TimeAt(std::int64_t tick) const {                          ///< [s]
    return static_cast<double>(tick) / rate_hz;
  }
  /// Number of whole ticks covering `duration` [s] (rounded up).
  std::int64_t TicksFor(double duration) const {
    PWSIM_DEMAND(duration >= 0.0);
    const double ticks = duration * rate_hz;
    auto whole = static_cast<std::int64_t>(ticks);
    if (static_cast<double>(whole) < ticks - 1e-9) ++whole;
    return whole;
  }
};

}  // namespace pwsim
