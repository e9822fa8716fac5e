#pragma once
// The offline ceiling of motion cueing on a platform: the whole trial optimised at once, with
// the trial known in advance. It is the MPC's problem (mca/mpc.h: the same perceived-motion
// cost, weights, limits, brake-to-stop and tilt-rate constraints) with one horizon spanning
// the trial, blocks of `block_s`, solved once from rest by the same dual active set (one big
// QP), and the plan followed open loop through the limiter in actuator space. On a mechanism
// with legs the actuator rows are linearised first about neutral, then twice more about the
// plan itself, block by block (sequential QP: a plan that spans the trial moves far from any
// one pose). Not real time (seconds per trial); the washout and the online MPC are measured
// against it (summary.json's mca.comparison, scripts/mca-figures.sh).
//
//   CueingTrace best = RunOfflineOptimum(config, truth, dt);

#include <vector>

#include "mca/config.h"
#include "mca/cueing.h"

namespace pwsim::mca {

/// The MPC parameters of the ceiling for a trial of `duration` [s] on `axes` platform axes:
/// config.mpc's weights, preview on, one horizon over the whole trial in blocks of 0.05 s, or
/// longer (whole 0.01 s) to keep the QP at about 800 accelerations.
MpcParams OfflineParams(const MpcParams& online, double duration, int axes);

/// Like RunCueing with the offline plan (trace.algorithm = kMpc, trace.preview = true).
/// `rail_yaw`: delivered motion of the rail + yaw chain (mca/rail_yaw.h) instead of the
/// generic kinematics.
CueingTrace RunOfflineOptimum(const McaConfig& config, const std::vector<HeadMotion>& truth, double dt,
                              bool rail_yaw = false);

}  // namespace pwsim::mca
