#pragma once
// The car's instruments drawn over a rendered frame, like the cabin indicators of seed 001:
// a rev counter (0-8000 rpm, red above the rev limit), a speedometer (0-200 km/h) and the
// engaged gear (R, N, 1-6), plus a stalled-engine lamp. Drawn into an owned BGRA image.
//
//   Image frame = CopyImage(renderer.Render(...));   DrawDashboard(frame, {rpm, kmh, gear});

#include "render/image_io.h"

namespace pwsim::render {

struct DashboardReading {
  double engine_rpm{0.0};
  double speed_kmh{0.0};
  int gear{0};               ///< -1 R, 0 N, 1..
  bool engine_running{true};
  double redline_rpm{6500.0};
};

/// Draws the instrument cluster along the bottom of `image` (scaled to its height).
void DrawDashboard(Image& image, const DashboardReading& reading);

/// Needle angle [rad] of a gauge, from 225° (value 0) clockwise to -45° (full scale), in the
/// image's mathematical orientation (counter-clockwise positive, y up).
double GaugeAngle(double value, double full_scale);

}  // namespace pwsim::render
