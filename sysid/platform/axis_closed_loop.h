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

/// The sums of squares behind ClosedLoopErrors, so that pieces of one run (the report blocks of
/// a recording) can be pooled: error = 100·sqrt(Σ err²/Σ meas²) over every piece.
struct ClosedLoopSums {
  double position_err2{0.0}, position2{0.0};
  double velocity_err2{0.0}, velocity2{0.0};
  double effort_err2{0.0}, effort2{0.0};
  void Add(const ClosedLoopSums& other);
  ClosedLoopErrors Pct() const;
};

/// @throws std::invalid_argument when the recording has no reference or no loop gains.
ClosedLoopRun SimulateClosedLoop(const AxisRecording& recording, const AxisForwardModel& model,
                                 int substeps = 10);
/// Errors of `run` against the recording; velocity against `measured_qd`, whose first sample
/// is the recording's sample `measured_offset` (the identification chain's border).
ClosedLoopErrors CompareClosedLoop(const AxisRecording& recording,
                                   const std::vector<double>& measured_qd,
                                   std::size_t measured_offset, const ClosedLoopRun& run);
/// The same as sums; `run_offset`: the run's sample at the recording's first sample (a piece of
/// a recording compared with the run of the whole).
ClosedLoopSums CompareClosedLoopSums(const AxisRecording& recording,
                                     const std::vector<double>& measured_qd,
                                     std::size_t measured_offset, const ClosedLoopRun& run,
                                     std::size_t run_offset = 0);

}  // namespace pwsim::sysid::platform
