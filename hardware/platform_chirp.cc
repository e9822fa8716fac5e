#include "hardware/platform_chirp.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pwsim::hw {

ChirpRecord RunChirp(const ChirpParams& c, const PlatformParams& platform) {
  if (c.joint != 0 && c.joint != 1) throw std::invalid_argument("chirp joint: expected 0 or 1");
  if (!(c.w0_rad_s > 0.0 && c.w1_rad_s > c.w0_rad_s))
    throw std::invalid_argument("chirp frequencies: expected 0 < w0 < w1 rad/s");
  if (!(c.sweep_s > 0.0) || c.sweeps < 1 || !(c.amplitude > 0.0) || c.max_accel < 0.0 ||
      !(c.sample_s > 0.0) || !(c.substep_s > 0.0))
    throw std::invalid_argument("chirp: sweep_s, sweeps, amplitude, sample_s and substep_s "
                                "must be > 0, max_accel >= 0");
  PlatformPlant plant(platform, c.substep_s);
  plant.ResetTarget({0.0, 0.0});
  const double ratio = std::log(c.w1_rad_s / c.w0_rad_s);
  const std::size_t jc = static_cast<std::size_t>(c.joint);
  double m[2][2];
  PlatformMassMatrix(platform, {0.0, 0.0}, m);
  const double limit = jc == 0 ? platform.tau1_max : platform.tau2_max;
  const double a_max = c.max_accel > 0.0 ? c.max_accel : 0.5 * limit / m[jc][jc];
  auto reference = [&](double t) {
    const double ts = std::fmod(t, c.sweep_s);
    const double growth = std::exp(ts / c.sweep_s * ratio);
    const double w = c.w0_rad_s * growth;
    const double phase = c.w0_rad_s * c.sweep_s / ratio * (growth - 1.0);
    // Raised-cosine fade over the first and last 2 % of each sweep: the sweeps join without a
    // velocity step (the frequency jumps from ω1 back to ω0 there).
    const double fade_s = 0.02 * c.sweep_s;
    const double edge = std::min(ts, c.sweep_s - ts) / fade_s;
    const double envelope = edge >= 1.0 ? 1.0 : 0.5 - 0.5 * std::cos(M_PI * std::max(edge, 0.0));
    return envelope * std::min(c.amplitude, a_max / (w * w)) * std::sin(phase);
  };
  ChirpRecord rec;
  rec.max_accel = a_max;

  const auto n = static_cast<long>(std::lround(c.sweeps * c.sweep_s / c.sample_s));
  for (long k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * c.sample_s;
    const PlatformState& s = plant.state();
    rec.t.push_back(t);
    for (std::size_t j = 0; j < 2; ++j) {
      rec.q[j].push_back(s.q[j]);
      rec.tau[j].push_back(s.tau[j]);
      rec.q_ref[j].push_back(static_cast<int>(j) == c.joint ? reference(t) : 0.0);
    }
    std::array<double, 2> target{0.0, 0.0};
    target[static_cast<std::size_t>(c.joint)] = reference(t + c.sample_s);
    plant.Advance(c.sample_s, target, true);
    if (std::abs(plant.state().tau[jc]) >= limit * (1.0 - 1e-9)) ++rec.saturated_samples;
  }
  return rec;
}

}  // namespace pwsim::hw
