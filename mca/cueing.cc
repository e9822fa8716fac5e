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

void McaStepper::SetPredictor(VehiclePredictor* predictor) {
  if (mpc_) mpc_->SetPredictor(predictor);
}

const McaCommand& McaStepper::Step(const HeadMotion& input) { return mpc_ ? mpc_->Step(input) : washout_->Step(input); }

CueingTrace RunCueing(const McaConfig& config, const std::vector<HeadMotion>& truth, double dt,
                      VehiclePredictor* predictor) {
  CueingTrace trace;
  trace.truth = truth;
  const std::size_t n = truth.size();
  trace.commands.reserve(n);
  std::vector<DofArray> poses;
  poses.reserve(n);
  trace.algorithm = config.algorithm;
  McaStepper stepper(config, dt);
  stepper.SetPreview(&truth);
  stepper.SetPredictor(predictor);
  trace.preview = stepper.using_preview();
  trace.predictor = stepper.using_predictor();
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

PerceivedError EvaluatePerceivedError(const CueingTrace& trace, double dt, double max_lag) {
  PerceivedError out;
  const std::size_t n = trace.perceived_true.size();
  if (n == 0) return out;
  std::vector<std::vector<double>> truth(6, std::vector<double>(n)), platform(6, std::vector<double>(n));
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t c = 0; c < 6; ++c) {
      const double weight = c < 3 ? 1.0 : kCanalWeight;
      truth[c][k] = weight * (c < 3 ? trace.perceived_true[k].fs[c] : trace.perceived_true[k].w[c - 3]);
      platform[c][k] = weight * (c < 3 ? trace.perceived_platform[k].fs[c] : trace.perceived_platform[k].w[c - 3]);
      const double e = platform[c][k] - truth[c][k];
      sum += e * e;
    }
  }
  out.rms = std::sqrt(sum / (6.0 * static_cast<double>(n)));
  out.correlation = CompareStacked(truth, platform, dt, max_lag);
  return out;
}

void EvaluateActuators(const PlatformSpec& platform, const std::vector<McaCommand>& commands, double dt,
                       std::vector<ActuatorUsage>* usage, ActuatorLimitsCheck* check) {
  const Mechanism& m = platform.mechanism;
  const int count = m.actuator_count();
  usage->assign(static_cast<std::size_t>(count), ActuatorUsage{});
  *check = ActuatorLimitsCheck{};
  const ActuatorVector neutral = m.Neutral();
  for (int i = 0; i < count; ++i) {
    (*usage)[static_cast<std::size_t>(i)].index = i;
    (*usage)[static_cast<std::size_t>(i)].min_position = (*usage)[static_cast<std::size_t>(i)].max_position = neutral[i];
  }
  // what the axis boxes' corners ask of each actuator
  std::vector<Dof> boxed;
  for (Dof dof : kAllDofs) {
    if (platform.Has(dof) && m.Moves(dof) && std::isfinite(platform.limits(dof).travel)) boxed.push_back(dof);
  }
  for (unsigned corner = 0; corner < (1u << boxed.size()); ++corner) {
    DofArray pose{};
    for (std::size_t k = 0; k < boxed.size(); ++k) {
      const double travel = platform.limits(boxed[k]).travel;
      pose[static_cast<std::size_t>(Index(boxed[k]))] = (corner >> k) & 1u ? travel : -travel;
    }
    ActuatorVector q, use;
    if (!m.Inverse(pose, &q)) continue;
    m.StrokeUse(q, &use);
    for (int i = 0; i < count; ++i) {
      auto& u = (*usage)[static_cast<std::size_t>(i)];
      u.box_stroke_use = std::max(u.box_stroke_use, use[i]);
    }
  }
  // the command stream's positions, their differences, and FK back
  ActuatorVector q_prev = neutral, r_prev = ActuatorVector::Zero(count), q, use;
  DofArray guess{};
  auto worst = [&](double fraction, int i, const char* what) {
    if (fraction > check->worst_fraction) {
      check->worst_fraction = fraction;
      check->worst_actuator = i;
      check->worst_what = what;
    }
  };
  for (const McaCommand& c : commands) {
    if (!m.Inverse(c.pose, &q)) {
      ++check->ik_failures;
      check->within = false;
      continue;
    }
    DofArray back{};
    const KinematicsStatus fk = m.Forward(q, guess, &back);
    double residual = fk.ok ? 0.0 : kUnlimited;
    for (Dof dof : kAllDofs) {
      const auto d = static_cast<std::size_t>(Index(dof));
      if (m.Moves(dof)) residual = std::max(residual, std::abs(back[d] - c.pose[d]));
    }
    check->forward_residual = std::max(check->forward_residual, residual);
    if (!(residual <= kForwardTolerance)) check->positions_checked = false;
    guess = fk.ok ? back : c.pose;
    m.StrokeUse(q, &use);
    for (int i = 0; i < count; ++i) {
      auto& u = (*usage)[static_cast<std::size_t>(i)];
      const ActuatorLimits& lim = m.actuator(i).limits;
      const double r = (q[i] - q_prev[i]) / dt;
      const double a = (r - r_prev[i]) / dt;
      u.stroke_use = std::max(u.stroke_use, use[i]);
      u.min_position = std::min(u.min_position, q[i]);
      u.max_position = std::max(u.max_position, q[i]);
      u.speed_fraction = std::max(u.speed_fraction, std::abs(r) / lim.speed);
      u.accel_fraction = std::max(u.accel_fraction, std::abs(a) / lim.accel);
      worst(use[i], i, "stroke");
      worst(std::abs(r) / lim.speed, i, "speed");
      worst(std::abs(a) / lim.accel, i, "acceleration");
      const double stroke = std::isfinite(lim.max - lim.min) ? lim.max - lim.min : 0.0;
      if ((std::isfinite(lim.max) && q[i] > lim.max + kLimitTolerance * stroke) ||
          (std::isfinite(lim.min) && q[i] < lim.min - kLimitTolerance * stroke) ||
          std::abs(r) > lim.speed * (1.0 + kLimitTolerance) || std::abs(a) > lim.accel * (1.0 + kLimitTolerance)) {
        check->within = false;
      }
      r_prev[i] = r;
    }
    q_prev = q;
  }
}

ConsistencyReport EvaluateConsistency(const McaConfig& config, const CueingTrace& trace, double dt,
                                      double max_lag) {
  ConsistencyReport report;
  report.perceived = EvaluatePerceivedError(trace, dt, max_lag);
  EvaluateActuators(config.platform, trace.commands, dt, &report.actuators, &report.limits);
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
