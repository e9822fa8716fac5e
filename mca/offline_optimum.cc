#include "mca/offline_optimum.h"

#include <algorithm>
#include <cmath>

#include "mca/rail_yaw.h"

namespace pwsim::mca {

MpcParams OfflineParams(const MpcParams& online, double duration, int axes) {
  const double block = std::max(0.05, std::ceil(duration * axes / 800.0 / 0.01) * 0.01);
  MpcParams p = online;
  p.whole_trial = true;
  p.preview = true;
  p.control_period = block;
  p.block = block;
  p.horizon = std::max(1.0, duration);
  return p;
}

CueingTrace RunOfflineOptimum(const McaConfig& config, const std::vector<HeadMotion>& truth, double dt,
                              bool rail_yaw) {
  McaConfig offline = config;
  offline.algorithm = McaAlgorithm::kMpc;
  int axes = 0;
  for (Dof dof : kAllDofs) axes += config.platform.Has(dof) ? 1 : 0;
  offline.mpc = OfflineParams(config.mpc, static_cast<double>(truth.size()) * dt, axes);
  return rail_yaw ? RunRailYawCueing(offline, truth, dt) : RunCueing(offline, truth, dt);
}

}  // namespace pwsim::mca
