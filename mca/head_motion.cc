#include "mca/head_motion.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

using Mat3 = std::array<double, 9>;

Mat3 Multiply(const Mat3& a, const Mat3& b) {
  Mat3 out{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) s += a[static_cast<std::size_t>(3 * r + k)] * b[static_cast<std::size_t>(3 * k + c)];
      out[static_cast<std::size_t>(3 * r + c)] = s;
    }
  }
  return out;
}

/// Rᵀ v.
std::array<double, 3> TransposeTimes(const Mat3& r, const std::array<double, 3>& v) {
  return {r[0] * v[0] + r[3] * v[1] + r[6] * v[2], r[1] * v[0] + r[4] * v[1] + r[7] * v[2],
          r[2] * v[0] + r[5] * v[1] + r[8] * v[2]};
}

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
  m.attitude = {0.0, pitch};
  return m;
}

}  // namespace

PointPose PointOnBody(const DofArray& pose, const std::array<double, 3>& p_B) {
  const double roll = pose[Index(Dof::kRoll)];
  const double pitch = pose[Index(Dof::kPitch)];
  const double yaw = pose[Index(Dof::kYaw)];
  const double cr = std::cos(roll), sr = std::sin(roll);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const Mat3 rz{cy, -sy, 0, sy, cy, 0, 0, 0, 1};
  const Mat3 ry{cp, 0, -sp, 0, 1, 0, sp, 0, cp};  // Ry(-pitch): nose-up lifts x
  const Mat3 rx{1, 0, 0, 0, cr, -sr, 0, sr, cr};
  PointPose out;
  out.r = Multiply(Multiply(rz, ry), rx);
  for (std::size_t i = 0; i < 3; ++i) {
    out.p[i] = pose[i] + out.r[3 * i] * p_B[0] + out.r[3 * i + 1] * p_B[1] + out.r[3 * i + 2] * p_B[2];
  }
  return out;
}

HeadMotion HeadMotionAt(const PointPose& prev, const PointPose& now, const PointPose& next, double dt) {
  HeadMotion out;
  std::array<double, 3> f{};
  for (std::size_t i = 0; i < 3; ++i) f[i] = (next.p[i] - 2.0 * now.p[i] + prev.p[i]) / (dt * dt);
  f[2] += kGravity;
  out.fs = TransposeTimes(now.r, f);
  // Ω = Rᵀ Ṙ (skew), Ṙ by central difference
  Mat3 rdot{};
  for (std::size_t i = 0; i < 9; ++i) rdot[i] = (next.r[i] - prev.r[i]) / (2.0 * dt);
  Mat3 rt{};
  for (std::size_t r = 0; r < 3; ++r) {
    for (std::size_t c = 0; c < 3; ++c) rt[3 * r + c] = now.r[3 * c + r];
  }
  const Mat3 omega = Multiply(rt, rdot);
  out.w = {0.5 * (omega[7] - omega[5]), 0.5 * (omega[2] - omega[6]), 0.5 * (omega[3] - omega[1])};
  // R = Rz(ψ) Ry(−θ) Rx(φ): R₂₀ = sin θ, R₂₁ = cos θ sin φ, R₂₂ = cos θ cos φ
  out.attitude = {std::atan2(now.r[7], now.r[8]), std::atan2(now.r[6], std::hypot(now.r[7], now.r[8]))};
  return out;
}

std::vector<HeadMotion> HeadMotionFromPoses(const std::vector<PointPose>& head, double dt) {
  PWSIM_DEMAND(dt > 0.0);
  const std::size_t n = head.size();
  std::vector<HeadMotion> out(n);
  if (n < 3) return out;
  for (std::size_t k = 1; k + 1 < n; ++k) out[k] = HeadMotionAt(head[k - 1], head[k], head[k + 1], dt);
  out[0] = out[1];
  out[n - 1] = out[n - 2];
  return out;
}

std::vector<HeadMotion> HeadMotionFromBodyTrack(const std::vector<DofArray>& body,
                                                const std::array<double, 3>& head_offset, double dt) {
  std::vector<PointPose> head(body.size());
  for (std::size_t k = 0; k < body.size(); ++k) head[k] = PointOnBody(body[k], head_offset);
  return HeadMotionFromPoses(head, dt);
}

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
