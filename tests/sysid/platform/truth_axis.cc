#include "tests/sysid/platform/truth_axis.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace pwsim::test {
namespace {

// A trapezoidal (or triangular) move from a to b, sampled on demand.
struct Move {
  double t0, a, b, v, acc, t_acc, t_flat, dwell;
  double Duration() const { return 2.0 * t_acc + t_flat + dwell; }
  double At(double t) const {  // t relative to t0
    const double d = b > a ? 1.0 : -1.0;
    const double dist = std::abs(b - a);
    if (t <= 0) return a;
    if (t < t_acc) return a + d * 0.5 * acc * t * t;
    const double x1 = 0.5 * acc * t_acc * t_acc;
    if (t < t_acc + t_flat) return a + d * (x1 + v * (t - t_acc));
    const double t2 = t - t_acc - t_flat;
    if (t2 < t_acc) return a + d * (x1 + v * t_flat + v * t2 - 0.5 * acc * t2 * t2);
    return a + d * dist;
  }
};

}  // namespace

sysid::platform::AxisRecording SimulateTruthAxis(const TruthAxisParams& p) {
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  const double T = 0.001;
  const int n = static_cast<int>(std::lround(p.duration / T)) + 1;
  // Reference: moves until the duration is covered.
  std::vector<Move> moves;
  double t = 0.3, x = 0.02;
  while (t < p.duration) {
    Move m{};
    m.t0 = t;
    m.a = x;
    do {
      m.b = 0.01 + 0.22 * u01(rng);
    } while (std::abs(m.b - m.a) < 0.02);
    m.v = 0.03 * std::pow(10.0, u01(rng));  // 0.03 .. 0.3 m/s, log-uniform
    m.acc = 0.5 + 2.5 * u01(rng);
    const double dist = std::abs(m.b - m.a);
    m.t_acc = m.v / m.acc;
    if (m.acc * m.t_acc * m.t_acc > dist) {  // triangular
      m.t_acc = std::sqrt(dist / m.acc);
      m.v = m.acc * m.t_acc;
    }
    m.t_flat = (dist - m.acc * m.t_acc * m.t_acc) / m.v;
    m.dwell = 0.3 * u01(rng);
    moves.push_back(m);
    t += m.Duration();
    x = m.b;
  }
  auto reference = [&](double tt) {
    if (tt < moves.front().t0) return moves.front().a;
    for (const Move& m : moves)
      if (tt < m.t0 + m.Duration()) return m.At(tt - m.t0);
    return moves.back().b;
  };

  const bool two_body = p.stiffness > 0.0;
  const double m_total = p.motor_mass + p.load_mass;
  double xm = 0.02, vm = 0.0, xl = 0.02, vl = 0.0;
  const int sub = 100;  // 10 µs
  const double h = T / sub;
  double prev_meas = 0.02, prev_filtered = 0.02;

  sysid::platform::AxisRecording rec;
  rec.file = "truth-" + std::to_string(p.seed) + ".yaml";
  rec.dt = T;
  rec.experiment = "excitation";
  sysid::platform::JointRecording j;
  j.name = "axis";
  j.kind = sysid::platform::JointKind::kPrismatic;
  j.command_to_effort = p.gain;
  sysid::platform::LoopGains loop;
  loop.kp = p.kp;
  loop.kv = p.kv;
  loop.command_limit = p.limit;
  loop.delay_samples = p.delay_samples;
  rec.loop = loop;

  auto friction_force = [&](double v, double pos, double drive) {
    // Karnopp: inside the stick band the friction cancels the driving force up to breakaway.
    const double fc_dir = v > 0 ? p.fc_pos : p.fc_neg;
    const double scale = 1.0 + p.coulomb_slope * (pos - 0.12);
    const double band = 1e-4;
    if (std::abs(v) < band) {
      const double breakaway = (std::max(p.fc_pos, p.fc_neg) + p.stribeck_extra) * scale;
      const double need = drive - p.offset;
      return p.offset + std::clamp(need, -breakaway, breakaway);
    }
    const double s = v > 0 ? 1.0 : -1.0;
    const double r = v / p.stribeck_speed;
    const double coulomb = (fc_dir + p.stribeck_extra * std::exp(-r * r)) * scale;
    const double viscous = (v > 0 ? p.fv_pos : p.fv_neg) * v;
    return p.offset + s * coulomb + viscous;
  };

  // The controller runs at the half samples t_k − T/2 (it reads the encoder there) and its
  // command acts over [t_k − T/2, t_k + T/2) (or one sample later with delay_samples = 1); the
  // logger records position at t_k and the command that acts around t_k, so the recorded
  // effort is centred on its sample instant, as the inverse model assumes.
  double nu_prev = 0.0;       // computed at the previous half sample
  double nu_current = 0.0;    // acting now (before delay handling)
  auto control = [&](double tk) {
    const double meas = std::round(xm / p.encoder_quantum) * p.encoder_quantum;
    const double filtered = 0.5 * (meas + prev_meas);
    double nu = p.kv * (p.kp * (reference(tk) - meas) - (filtered - prev_filtered) / T);
    prev_meas = meas;
    prev_filtered = filtered;
    return std::clamp(nu, -p.limit, p.limit);
  };
  auto step = [&](double drive, double disturbance) {
    if (!two_body) {
      const double cog = p.cogging_amplitude * std::sin(2.0 * M_PI * xm / p.cogging_period);
      const double f = friction_force(vm, xm, drive + disturbance - cog);
      const double a = (drive + disturbance - cog - f) / m_total;
      vm += a * h;
      if (std::abs(vm) < 1e-4 && std::abs(drive + disturbance - cog - p.offset) <=
                                     std::max(p.fc_pos, p.fc_neg) + p.stribeck_extra)
        vm = 0.0;  // stuck
      xm += vm * h;
      xl = xm;
      vl = vm;
      return;
    }
    const double half_gap = 0.5 * p.backlash_gap;
    double stretch = xm - xl;
    if (stretch > half_gap)
      stretch -= half_gap;
    else if (stretch < -half_gap)
      stretch += half_gap;
    else
      stretch = 0.0;
    double spring = p.stiffness * stretch;
    if (stretch != 0.0 || p.backlash_gap == 0.0) spring += p.damping * (vm - vl);
    if (p.backlash_gap > 0.0 && stretch == 0.0) spring = 0.0;
    const double cog = p.cogging_amplitude * std::sin(2.0 * M_PI * xm / p.cogging_period);
    const double am = (drive + disturbance - cog - spring) / p.motor_mass;
    const double f = friction_force(vl, xl, spring);
    const double al = (spring - f) / p.load_mass;
    vm += am * h;
    vl += al * h;
    if (std::abs(vl) < 1e-4 &&
        std::abs(spring - p.offset) <= std::max(p.fc_pos, p.fc_neg) + p.stribeck_extra)
      vl = 0.0;
    xm += vm * h;
    xl += vl * h;
  };
  nu_current = 0.0;
  for (int k = 0; k < n; ++k) {
    const double tk = k * T;
    const double meas = std::round(xm / p.encoder_quantum) * p.encoder_quantum;
    rec.t.push_back(tk);
    j.position.push_back(meas);
    j.reference.push_back(reference(tk));
    j.command.push_back(nu_current);
    j.effort.push_back(p.gain * nu_current);
    const double disturbance = p.force_noise * noise(rng);
    const double acting = p.delay_samples > 0 ? nu_prev : nu_current;
    for (int s = 0; s < sub / 2; ++s) step(p.gain * acting, disturbance);
    const double next = control(tk + 0.5 * T);
    nu_prev = nu_current;
    nu_current = next;
    const double acting2 = p.delay_samples > 0 ? nu_prev : nu_current;
    for (int s = sub / 2; s < sub; ++s) step(p.gain * acting2, disturbance);
  }
  rec.joints.push_back(std::move(j));
  return rec;
}

}  // namespace pwsim::test
