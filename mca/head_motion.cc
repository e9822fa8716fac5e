#include "mca/head_motion.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

/// Sagittal kinematics of the head from O_V's acceleration and the pitch state.
HeadMotion Kinematics(double ax, double az, double pitch, double pitch_rate, double pitch_acc,
                      const std::array<double, 3>& p) {
  const double c = std::cos(pitch);
  const double s = std::sin(pitch);
  // R p and dR/dθ p in W's x-z plane (nose-up θ: x_V = (c, s), z_V = (-s, c)).
  const double rp_x = p[0] * c - p[2] * s;
  const double rp_z = p[0] * s + p[2] * c;
  const double drp_x = -p[0] * s - p[2] * c;
  const double drp_z = p[0] * c - p[2] * s;
  const double a_x = ax + pitch_acc * drp_x - pitch_rate * pitch_rate * rp_x;
  const double a_z = az + pitch_acc * drp_z - pitch_rate * pitch_rate * rp_z;
  // fs_W = a - g_W with g_W = (0, 0, -g); expressed in H = V: fs_H = R^T fs_W.
  const double f_x = a_x;
  const double f_z = a_z + kGravity;
  HeadMotion m;
  m.fs = {c * f_x + s * f_z, 0.0, -s * f_x + c * f_z};
  m.w = {0.0, -pitch_rate, 0.0};
  return m;
}

}  // namespace

HeadMotion HeadMotionFromChair(const ChairSample& sample, const std::array<double, 3>& head_offset) {
  return Kinematics(sample.drive.a, sample.lm_acc.z, sample.lm.pitch, sample.lm.pitch_rate,
                    sample.lm_acc.pitch, head_offset);
}

HeadPose HeadPoseFromChair(const ChairSample& sample, const std::array<double, 3>& head_offset) {
  const double c = std::cos(sample.lm.pitch);
  const double s = std::sin(sample.lm.pitch);
  return {sample.drive.x + head_offset[0] * c - head_offset[2] * s,
          sample.lm.z + head_offset[0] * s + head_offset[2] * c, sample.lm.pitch};
}

std::vector<HeadMotion> HeadMotionFromTrack(const SagittalTrack& track,
                                            const std::array<double, 3>& head_offset,
                                            int smooth_ticks) {
  const std::size_t n = track.x.size();
  PWSIM_DEMAND(track.z.size() == n && track.pitch.size() == n && track.dt > 0.0);
  PWSIM_DEMAND(smooth_ticks >= 0);
  std::vector<HeadMotion> out(n);
  if (n < 3) return out;
  // moving average of a series over ±smooth_ticks (shrinking at the ends)
  auto smooth = [&](const std::vector<double>& v) {
    if (smooth_ticks == 0) return v;
    std::vector<double> prefix(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + v[i];
    std::vector<double> s(n);
    const auto h = static_cast<std::size_t>(smooth_ticks);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t lo = i >= h ? i - h : 0;
      const std::size_t hi = std::min(n - 1, i + h);
      s[i] = (prefix[hi + 1] - prefix[lo]) / static_cast<double>(hi - lo + 1);
    }
    return s;
  };
  auto derivative = [&](const std::vector<double>& v) {
    std::vector<double> d(n);
    for (std::size_t i = 1; i + 1 < n; ++i) d[i] = (v[i + 1] - v[i - 1]) / (2.0 * track.dt);
    d[0] = (v[1] - v[0]) / track.dt;
    d[n - 1] = (v[n - 1] - v[n - 2]) / track.dt;
    return smooth(d);
  };
  const std::vector<double> x = smooth(track.x);
  const std::vector<double> z = smooth(track.z);
  const std::vector<double> pitch = smooth(track.pitch);
  const std::vector<double> vx = derivative(x);
  const std::vector<double> vz = derivative(z);
  const std::vector<double> q = derivative(pitch);
  const std::vector<double> ax = derivative(vx);
  const std::vector<double> az = derivative(vz);
  const std::vector<double> qd = derivative(q);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = Kinematics(ax[i], az[i], pitch[i], q[i], qd[i], head_offset);
  }
  return out;
}

}  // namespace pwsim::mca
