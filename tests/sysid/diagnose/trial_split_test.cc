// The marker-lever correction of a trial's track (sysid/diagnose/diagnose.h,
// TrackUnderMarkerLever) against its closed form: a marker at lever (r_x, r_z) in the chair
// frame measures x_m = x + r_x cos θ − r_z sin θ and Z_m = Z + r_x sin θ + r_z (cos θ − 1);
// taking the lever out must give back O_V's x and Z, whatever constant offset the measured
// pitch carries (it is centred on the rest window, where the chair stands level).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sysid/diagnose/diagnose.h"
#include "sysid/effects/effect_model.h"

namespace pwsim::diagnose {
namespace {

TEST(TrialSplitTest, TrackUnderMarkerLeverGivesBackTheMotionOfOv) {
  const double r_x = -0.17, r_z = 0.56, pitch_offset = 0.03;
  effects::TrialRecord record;
  std::vector<double> x_true, z_true;
  for (int k = 0; k <= 600; ++k) {
    const double t = 0.01 * k;
    // At rest and level for the first second, then driving with a pitch swing of 0.2 rad.
    const double moving = t > 1.0 ? t - 1.0 : 0.0;
    const double theta = 0.2 * std::sin(2.0 * std::numbers::pi * 1.2 * moving) * (moving > 0 ? 1.0 : 0.0);
    const double x = 0.4 * moving * moving, z = 0.01 * std::sin(3.0 * moving);
    x_true.push_back(x);
    z_true.push_back(z);
    record.t.push_back(t);
    record.x.push_back(x + r_x * std::cos(theta) - r_z * std::sin(theta));
    record.z.push_back(z + r_x * std::sin(theta) + r_z * (std::cos(theta) - 1.0));
    record.pitch.push_back(theta + pitch_offset);
  }
  const TrackUnderLever o = TrackUnderMarkerLever(record, r_x, r_z, 0.25);
  double worst_x = 0.0, worst_z = 0.0, lever_x = 0.0;
  for (std::size_t k = 0; k < record.t.size(); ++k) {
    worst_x = std::max(worst_x, std::abs(o.x[k] - x_true[k]));
    worst_z = std::max(worst_z, std::abs(o.z[k] - z_true[k]));
    lever_x = std::max(lever_x, std::abs(record.x[k] - x_true[k]));
  }
  EXPECT_LT(worst_x, 1e-12);
  EXPECT_LT(worst_z, 1e-12);
  EXPECT_GT(lever_x, 0.1);  // the lever did move the measured x

  // O_V's acceleration is 0.8 m/s² while driving; the marker's x swings with the pitch.
  const std::vector<double> a_ov = effects::EstimateAcceleration(record.t, o.x);
  const std::vector<double> a_marker = effects::EstimateAcceleration(record.t, record.x);
  const std::size_t k = 400;  // t = 4 s
  EXPECT_NEAR(a_ov[k], 0.8, 1e-9);
  EXPECT_GT(std::abs(a_marker[k] - 0.8), 0.5);
}

}  // namespace
}  // namespace pwsim::diagnose
