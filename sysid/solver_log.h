#pragma once
// Ceres Solver logs through glog. A multi-start candidate whose simulation turns non-finite is
// dropped by the fit (greybox_fit.h: the cost reports the failure, the start scores ∞), yet
// Ceres writes an ERROR line, and for a non-finite residual the whole residual block, to
// stderr each time: noise that reads like a failure to a user of `pwsim identify` or
// `pwsim diagnose`. The CLI silences it at start; PWSIM_SOLVER_LOG=1 keeps it for debugging.

namespace pwsim {

/// glog below FATAL is dropped from here on, unless the environment sets PWSIM_SOLVER_LOG=1.
void QuietSolverLog();

}  // namespace pwsim
