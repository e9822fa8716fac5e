#pragma once
// Forward simulation of one axis in the closed loop it was recorded under (the EMPS loop of the
// benchmark description: ν_k = kv·(kp·(q_r,k − q_k) − (q_f,k − q_f,k−1)/T), q_f,k = ½(q_k +
// q_k−1), applied after `delay_samples` samples, saturated at ±limit; τ = gain·ν), with the
// rigid-body model M q̈ = τ − F(q, q̇) integrated by RK4 at T/`substeps` with τ held over a
// sample. F is the identified friction (base, or extended by one of the effects that depend on
// (q, q̇) only). Errors: 100·‖x_meas − x_sim‖/‖x_meas‖ for position, velocity (measured = the
// identification chain's q̇) and effort.

#include <functional>
#include <vector>

#include "sysid/platform/axis_recording.h"

namespace pwsim::sysid::platform {

struct AxisForwardModel {
  double inertia{1.0};  ///< [kg] or [kg m²]
  /// Friction + offset force [N] at (q, q̇).
  std::function<double(double q, double qd)> friction;
};

struct ClosedLoopRun {
  std::vector<double> q, qd, effort;  ///< at the recording's samples
};

struct ClosedLoopErrors {
  double position_pct{0.0}, velocity_pct{0.0}, effort_pct{0.0};
};

/// @throws std::invalid_argument when the recording has no reference or no loop gains.
ClosedLoopRun SimulateClosedLoop(const AxisRecording& recording, const AxisForwardModel& model,
                                 int substeps = 10);
/// Errors of `run` against the recording; velocity against `measured_qd`, whose first sample
/// is the recording's sample `measured_offset` (the identification chain's border).
ClosedLoopErrors CompareClosedLoop(const AxisRecording& recording,
                                   const std::vector<double>& measured_qd,
                                   std::size_t measured_offset, const ClosedLoopRun& run);

}  // namespace pwsim::sysid::platform
