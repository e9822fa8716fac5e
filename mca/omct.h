#pragma once
// Objective Motion Cueing Test (OMCT): frequency responses of the whole cueing chain (washout,
// tilt coordination, platform limits, head kinematics) from a sinusoidal vehicle motion at the
// head to the motion the platform delivers there, at the 12 frequencies 10^(k/5) rad/s,
// k = -5..6 (0.1 .. 15.85 rad/s). Direct tests (p→p, q→q, r→r, fx→fx, fy→fy, fz→fz) and the
// cross-coupling tests (fx→q tilt coordination, fy→p, q→fx, p→fy); a test applies when the
// platform has an axis the input drives and an axis that produces the output.
// Signals: fx, fy, fz specific force deviation [m/s^2] in head axes; p, q, r roll, nose-up
// pitch and yaw rate [rad/s]. Gain is output/input in those units, phase in degrees.
//
//   std::vector<OmctPoint> points = RunOmct(washout_params, platform, OmctOptions{});
//   std::vector<OmctPoint> mpc_points = RunOmct(mca_config, OmctOptions{});  // washout or MPC

#include <array>
#include <string>
#include <vector>

#include "mca/config.h"
#include "mca/platform.h"
#include "mca/washout.h"

namespace pwsim::mca {

/// Signal indices: 0 fx, 1 fy, 2 fz, 3 p, 4 q, 5 r.
enum class OmctSignal : int { kFx = 0, kFy, kFz, kP, kQ, kR };

struct OmctTest {
  const char* name;     ///< e.g. "fx_to_q"
  OmctSignal input;
  OmctSignal output;
};
/// The ten OMCT tests in the usual order (direct first).
const std::array<OmctTest, 10>& OmctTests();
/// 10^(k/5) rad/s for k = -5..6.
std::array<double, 12> OmctFrequencies();
bool OmctApplies(const OmctTest& test, const WashoutParams& params, const PlatformSpec& platform);

struct OmctOptions {
  double rate_hz{1000.0};                 ///< MCA tick rate [Hz]
  double force_amplitude{0.1};            ///< input amplitude of fx, fy, fz [m/s^2]
  double rate_amplitude{1.0 * kDegToRad}; ///< input amplitude of p, q, r [rad/s]
  int settle_periods{2};                  ///< periods run before measuring
  double settle_min{20.0};                ///< [s] at least this long before measuring
  int measure_periods{2};                 ///< periods fitted
};

struct OmctPoint {
  std::string test;
  double frequency{0.0};  ///< [rad/s]
  double gain{0.0};       ///< output/input amplitude
  double phase{0.0};      ///< [deg], output relative to input, in (-180, 180]
  bool within_limits{true};  ///< every commanded pose inside the platform's travel
};

/// One test at one frequency.
OmctPoint RunOmctPoint(const OmctTest& test, double frequency, const WashoutParams& params,
                       const PlatformSpec& platform, const OmctOptions& options);
/// Every applicable test at every frequency.
std::vector<OmctPoint> RunOmct(const WashoutParams& params, const PlatformSpec& platform,
                               const OmctOptions& options);

/// Through config.algorithm: the washout (as above) or the MPC (mca/mpc.h) with the held-input
/// prediction (preview off: the sinusoid is only known up to now). The MPC's control period must
/// be a whole number of 1/rate_hz ticks.
OmctPoint RunOmctPoint(const OmctTest& test, double frequency, const McaConfig& config,
                       const OmctOptions& options);
/// For the MPC the tilt tests apply wherever the platform has pitch or roll (its cost carries
/// g·θ, g·φ); for the washout as OmctApplies(test, config.washout, config.platform).
bool OmctApplies(const OmctTest& test, const McaConfig& config);
std::vector<OmctPoint> RunOmct(const McaConfig& config, const OmctOptions& options);

}  // namespace pwsim::mca
