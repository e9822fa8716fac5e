#pragma once
// The platform's drive axes: one CiA 402 node per actuator of the platform's mechanism
// (mca/mechanism.h), node id = 1 + the actuator's index, at most kMaxDriveAxes of them. Every
// per-axis quantity of the session (setpoints, commands, measurements, limits, node
// configuration) lives in a fixed-capacity array of that size, so that a drive cycle allocates
// nothing; only the first `axis_count` entries are used, the rest stay 0.

#include <array>

namespace pwsim::hw {

inline constexpr int kMaxDriveAxes = 8;  ///< = mca::kMaxActuators (static_assert in session_config.cc)

/// One value per drive axis, in the actuator's own coordinate [m | rad].
using AxisValues = std::array<double, kMaxDriveAxes>;

}  // namespace pwsim::hw
