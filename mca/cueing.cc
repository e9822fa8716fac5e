#include "mca/cueing.h"

#include <algorithm>
#include <cmath>

namespace pwsim::mca {

McaStepper::McaStepper(const McaConfig& config, double dt) {
  if (config.algorithm == McaAlgorithm::kMpc) {
    mpc_ = std::make_unique<MpcCueing>(config.mpc, config.washout, config.vestibular, config.platform, dt);
  } else {
    washout_.emplace(config.washout, config.platform, dt);
  }
}

McaStepper::~McaStepper() = default;

void McaStepper::SetPreview(const std::vector<HeadMotion>* trial) {
  if (mpc_) mpc_->SetPreview(trial);
}

const McaCommand& McaStepper::Step(const HeadMotion& input) { return mpc_ ? mpc_->Step(input) : washout_->Step(input); }

CueingTrace RunCueing(const McaConfig& config, const std::vector<HeadMotion>& truth, double dt) {
  CueingTrace trace;
  trace.truth = truth;
  const std::size_t n = truth.size();
  trace.commands.reserve(n);
  std::vector<DofArray> poses;
  poses.reserve(n);
  trace.algorithm = config.algorithm;
  McaStepper stepper(config, dt);
  stepper.SetPreview(&truth);
  trace.preview = stepper.using_preview();
  trace.whole_trial = config.algorithm == McaAlgorithm::kMpc && config.mpc.whole_trial;
  for (const HeadMotion& input : truth) trace.commands.push_back(stepper.Step(input));
  trace.mpc = stepper.mpc_stats();
  for (const McaCommand& c : trace.commands) poses.push_back(c.pose);
  trace.delivered = DeliveredHeadMotion(config.platform, poses, dt);
  VestibularModel vehicle(config.vestibular, dt);
  VestibularModel platform(config.vestibular, dt);
  trace.perceived_true.reserve(n);
  trace.perceived_platform.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    trace.perceived_true.push_back(vehicle.Step(truth[k]));
    trace.perceived_platform.push_back(platform.Step(trace.delivered[k]));
  }
  return trace;
}

ConsistencyReport EvaluateConsistency(const McaConfig& config, const CueingTrace& trace, double dt,
                                      double max_lag) {
  ConsistencyReport report;
  const std::size_t n = trace.commands.size();
  std::vector<double> t(n), p(n);
  for (std::size_t axis = 0; axis < 3; ++axis) {
    for (std::size_t k = 0; k < n; ++k) {
      t[k] = trace.perceived_true[k].fs[axis];
      p[k] = trace.perceived_platform[k].fs[axis];
    }
    report.otolith[axis] = CompareAxis(t, p, config.vestibular.thresholds.fs[axis], dt, max_lag);
    for (std::size_t k = 0; k < n; ++k) {
      t[k] = trace.perceived_true[k].w[axis];
      p[k] = trace.perceived_platform[k].w[axis];
    }
    report.canals[axis] = CompareAxis(t, p, config.vestibular.thresholds.w[axis], dt, max_lag);
  }
  // the commanded tilt-coordination rates (McaCommand::tilt_rate_*): for the washout its tilt
  // channel's, for the MPC its rotation beyond or against the vehicle's own
  std::vector<double> tilt_pitch(n), tilt_roll(n);
  for (std::size_t k = 0; k < n; ++k) {
    tilt_pitch[k] = trace.commands[k].tilt_rate_pitch;
    tilt_roll[k] = trace.commands[k].tilt_rate_roll;
    if (trace.commands[k].fault) ++report.fault_ticks;
  }
  report.tilt_pitch = RatesAbove(tilt_pitch, config.vestibular.thresholds.tilt_rate, dt);
  report.tilt_roll = RatesAbove(tilt_roll, config.vestibular.thresholds.tilt_rate, dt);
  for (Dof dof : kAllDofs) {
    if (!config.platform.Has(dof)) continue;
    const DofLimits& limits = config.platform.limits(dof);
    DofUsage usage;
    usage.dof = dof;
    const auto i = static_cast<std::size_t>(Index(dof));
    for (const McaCommand& c : trace.commands) {
      usage.peak_pose = std::max(usage.peak_pose, std::abs(c.pose[i]));
      usage.peak_rate = std::max(usage.peak_rate, std::abs(c.rate[i]));
      usage.peak_accel = std::max(usage.peak_accel, std::abs(c.accel[i]));
    }
    usage.pose_fraction = std::isfinite(limits.travel) ? usage.peak_pose / limits.travel : 0.0;
    usage.rate_fraction = usage.peak_rate / limits.speed;
    usage.accel_fraction = usage.peak_accel / limits.accel;
    report.usage.push_back(usage);
  }
  return report;
}

}  // namespace pwsim::mca
