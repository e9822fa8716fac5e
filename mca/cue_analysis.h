#pragma once
// What the platform delivers at the head, and how consistent it is with the vehicle's motion.
// The platform is taken to follow its setpoints exactly (actuator dynamics are not modelled):
// its pose is (surge, sway, heave) of the centre of rotation and R = Rz(yaw) Ry(-pitch) Rx(roll)
// (pitch nose-up); the head sits at head_from_pivot in the platform frame. Specific force and
// angular velocity at the head come from central differences of that pose stream.
// The metrics compare perceived (vestibular-filtered) true and delivered motion per axis.
//
//   std::vector<HeadMotion> delivered = DeliveredHeadMotion(platform, poses, dt);
//   AxisConsistency c = CompareAxis(truth, platform, threshold, dt, /*max_lag=*/0.5);

#include <array>
#include <string>
#include <vector>

#include "mca/dof.h"
#include "mca/head_motion.h"
#include "mca/platform.h"

namespace pwsim::mca {

/// Head position in the lab [m] and R (row-major 3×3) for one platform pose.
using PlatformHeadPose = PointPose;
PlatformHeadPose HeadPoseOnPlatform(const PlatformSpec& platform, const DofArray& pose);

/// Head motion delivered by a stream of platform poses (one per tick). Allocates.
std::vector<HeadMotion> DeliveredHeadMotion(const PlatformSpec& platform,
                                            const std::vector<DofArray>& poses, double dt);

/// Consistency of one perceived axis: delivered (platform) against true (vehicle).
struct AxisConsistency {
  double correlation{0.0};   ///< Pearson, zero lag [-]
  double rms_error{0.0};     ///< RMS(platform - true) [axis unit]
  double gain{0.0};          ///< least-squares gain platform/true at the best lag [-]
  double xcorr{0.0};         ///< the best normalised cross-correlation within ±max_lag [-]
  double lag{0.0};           ///< [s] lag of the best cross-correlation, > 0: platform late
  double peak_true{0.0};     ///< max |true|
  double peak_platform{0.0}; ///< max |platform|
  int wrong_sign_count{0};   ///< episodes with |platform| > threshold and opposite sign
  double wrong_sign_duration{0.0};  ///< [s] total
};
/// @pre equal sizes; dt > 0; max_lag >= 0 [s].
AxisConsistency CompareAxis(const std::vector<double>& truth, const std::vector<double>& platform,
                            double threshold, double dt, double max_lag);

/// Episodes where |d angle/dt| exceeds `threshold` (tilt perceived as rotation).
struct RateCues {
  int count{0};
  double duration{0.0};  ///< [s]
  double max_rate{0.0};  ///< [rad/s]
};
RateCues RateAbove(const std::vector<double>& angle, double threshold, double dt);
/// The same from the rates themselves [rad/s], one per tick of length dt.
RateCues RatesAbove(const std::vector<double>& rate, double threshold, double dt);

/// Several channels compared at once (each mean-removed, their lagged products summed over the
/// channels before normalising): how well a vector signal follows another, one common lag.
struct StackedCorrelation {
  double zero_lag{0.0};  ///< normalised correlation at lag 0 [-]
  double peak{0.0};      ///< the largest normalised cross-correlation within ±max_lag [-]
  double lag{0.0};       ///< [s] its lag, > 0: platform late
};
/// @pre every channel of equal size in both; dt > 0; max_lag >= 0 [s].
StackedCorrelation CompareStacked(const std::vector<std::vector<double>>& truth,
                                  const std::vector<std::vector<double>>& platform, double dt, double max_lag);

/// Normalised cross-correlation max over lags within ±max_lag [s]: returns {value, lag [s]}.
std::array<double, 2> MaxCrossCorrelation(const std::vector<double>& a,
                                          const std::vector<double>& b, double dt, double max_lag);

}  // namespace pwsim::mca
