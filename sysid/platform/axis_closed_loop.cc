#include "sysid/platform/axis_closed_loop.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pwsim::sysid::platform {

ClosedLoopRun SimulateClosedLoop(const AxisRecording& recording, const AxisForwardModel& model,
                                 int substeps) {
  if (recording.joints.size() != 1 || recording.joints[0].reference.empty() || !recording.loop)
    throw std::invalid_argument(recording.file.string() +
                                ": a closed-loop simulation needs one joint with its reference "
                                "and the loop gains (kp, kv)");
  const JointRecording& j = recording.joints[0];
  const LoopGains& g = *recording.loop;
  const std::size_t n = recording.size();
  const double T = recording.dt;
  const double h = T / std::max(1, substeps);
  ClosedLoopRun run;
  run.q.resize(n);
  run.qd.resize(n);
  run.effort.resize(n);
  // Initial velocity: slope of a straight line through the first 11 samples (a recording cut
  // out of a longer one starts in motion).
  double q = j.position[0], qd = 0.0;
  {
    const std::size_t m = std::min<std::size_t>(11, n);
    double st = 0, sq = 0, stt = 0, stq = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const double ti = static_cast<double>(i) * T;
      st += ti;
      sq += j.position[i];
      stt += ti * ti;
      stq += ti * j.position[i];
    }
    const double md = static_cast<double>(m);
    const double den = md * stt - st * st;
    if (den > 0.0) qd = (md * stq - st * sq) / den;
  }
  double q_prev = q, qf_prev = q;
  const auto d = static_cast<std::size_t>(std::max(0, g.delay_samples));
  std::vector<double> nu_history(n, 0.0);
  auto accel = [&](double qq, double vv, double tau) {
    return (tau - model.friction(qq, vv)) / model.inertia;
  };
  for (std::size_t k = 0; k < n; ++k) {
    run.q[k] = q;
    run.qd[k] = qd;
    const double qf = 0.5 * (q + q_prev);
    const double nu = g.kv * (g.kp * (j.reference[k] - q) - (qf - qf_prev) / T);
    nu_history[k] = std::clamp(nu, -g.command_limit, g.command_limit);
    q_prev = q;
    qf_prev = qf;
    const double applied = k >= d ? nu_history[k - d] : j.command[k];
    const double tau = j.command_to_effort * applied;
    run.effort[k] = tau;
    for (int s = 0; s < substeps; ++s) {  // RK4, τ held
      const double k1v = accel(q, qd, tau), k1q = qd;
      const double k2v = accel(q + 0.5 * h * k1q, qd + 0.5 * h * k1v, tau), k2q = qd + 0.5 * h * k1v;
      const double k3v = accel(q + 0.5 * h * k2q, qd + 0.5 * h * k2v, tau), k3q = qd + 0.5 * h * k2v;
      const double k4v = accel(q + h * k3q, qd + h * k3v, tau), k4q = qd + h * k3v;
      q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q);
      qd += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    }
  }
  return run;
}

void ClosedLoopSums::Add(const ClosedLoopSums& o) {
  position_err2 += o.position_err2;
  position2 += o.position2;
  velocity_err2 += o.velocity_err2;
  velocity2 += o.velocity2;
  effort_err2 += o.effort_err2;
  effort2 += o.effort2;
}

ClosedLoopErrors ClosedLoopSums::Pct() const {
  auto pct = [](double err2, double meas2) {
    return meas2 > 0.0 ? 100.0 * std::sqrt(err2 / meas2) : 0.0;
  };
  return {pct(position_err2, position2), pct(velocity_err2, velocity2), pct(effort_err2, effort2)};
}

ClosedLoopSums CompareClosedLoopSums(const AxisRecording& recording,
                                     const std::vector<double>& measured_qd,
                                     std::size_t measured_offset, const ClosedLoopRun& run,
                                     std::size_t run_offset) {
  const JointRecording& j = recording.joints.at(0);
  // Σ (meas_i − sim_{at + i})², Σ meas_i² over the samples both have.
  auto add = [](const std::vector<double>& meas, const std::vector<double>& sim, std::size_t at,
                double* err2, double* meas2) {
    for (std::size_t i = 0; i < meas.size() && at + i < sim.size(); ++i) {
      const double d = meas[i] - sim[at + i];
      *err2 += d * d;
      *meas2 += meas[i] * meas[i];
    }
  };
  ClosedLoopSums s;
  add(j.position, run.q, run_offset, &s.position_err2, &s.position2);
  add(measured_qd, run.qd, run_offset + measured_offset, &s.velocity_err2, &s.velocity2);
  add(j.effort, run.effort, run_offset, &s.effort_err2, &s.effort2);
  return s;
}

ClosedLoopErrors CompareClosedLoop(const AxisRecording& recording,
                                   const std::vector<double>& measured_qd,
                                   std::size_t measured_offset, const ClosedLoopRun& run) {
  return CompareClosedLoopSums(recording, measured_qd, measured_offset, run).Pct();
}

}  // namespace pwsim::sysid::platform
