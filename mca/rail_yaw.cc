#include "mca/rail_yaw.h"

#include <cmath>

#include "engine/check.h"

namespace pwsim::mca {

PlatformHeadPose HeadPoseOnRailYaw(const PlatformSpec& platform, const DofArray& pose) {
  const double x = pose[Index(Dof::kSurge)];
  const double yaw = pose[Index(Dof::kYaw)];
  const double c = std::cos(yaw), s = std::sin(yaw);
  const auto& h = platform.head_from_pivot;
  PlatformHeadPose out;
  out.r = {c, -s, 0, s, c, 0, 0, 0, 1};
  out.p = {c * (x + h[0]) - s * h[1], s * (x + h[0]) + c * h[1], h[2]};
  return out;
}

std::vector<HeadMotion> DeliveredRailYawHeadMotion(const PlatformSpec& platform,
                                                   const std::vector<DofArray>& poses, double dt) {
  PWSIM_DEMAND(dt > 0.0);
  const std::size_t n = poses.size();
  std::vector<HeadMotion> out(n);
  if (n < 3) return out;
  std::vector<PlatformHeadPose> head(n);
  for (std::size_t k = 0; k < n; ++k) head[k] = HeadPoseOnRailYaw(platform, poses[k]);
  for (std::size_t k = 1; k + 1 < n; ++k) {
    std::array<double, 3> a{};
    for (std::size_t i = 0; i < 3; ++i) a[i] = (head[k + 1].p[i] - 2.0 * head[k].p[i] + head[k - 1].p[i]) / (dt * dt);
    a[2] += kGravity;
    const auto& r = head[k].r;  // Rz(ψ): fs_H = Rᵀ a
    out[k].fs = {r[0] * a[0] + r[3] * a[1], r[1] * a[0] + r[4] * a[1], a[2]};
    double dyaw = poses[k + 1][Index(Dof::kYaw)] - poses[k - 1][Index(Dof::kYaw)];
    out[k].w = {0.0, 0.0, dyaw / (2.0 * dt)};
  }
  out[0] = out[1];
  out[n - 1] = out[n - 2];
  return out;
}

namespace {

struct Episodes {
  int count{0};
  double seconds{0.0};
};

Episodes Above(const std::vector<double>& v, double threshold, double dt) {
  Episodes e;
  bool inside = false;
  for (double x : v) {
    const bool now = std::abs(x) > threshold;
    if (now && !inside) ++e.count;
    if (now) e.seconds += dt;
    inside = now;
  }
  return e;
}

}  // namespace

RailYawFalseCues RailYawFalseCue(const VestibularParams& vestibular,
                                 const std::vector<McaCommand>& commands, double dt) {
  RailYawFalseCues cues;
  const std::size_t n = commands.size();
  cues.surge.resize(n);
  cues.sway.resize(n);
  double ss = 0.0, sy = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const McaCommand& c = commands[k];
    const double x = c.pose[Index(Dof::kSurge)];
    const double xdot = c.rate[Index(Dof::kSurge)];
    const double r = c.rate[Index(Dof::kYaw)];
    const double rdot = c.accel[Index(Dof::kYaw)];
    cues.surge[k] = -r * r * x;
    cues.sway[k] = rdot * x + 2.0 * r * xdot;
    cues.peak_surge = std::max(cues.peak_surge, std::abs(cues.surge[k]));
    cues.peak_sway = std::max(cues.peak_sway, std::abs(cues.sway[k]));
    ss += cues.surge[k] * cues.surge[k];
    sy += cues.sway[k] * cues.sway[k];
  }
  if (n > 0) {
    cues.rms_surge = std::sqrt(ss / static_cast<double>(n));
    cues.rms_sway = std::sqrt(sy / static_cast<double>(n));
  }
  const Episodes es = Above(cues.surge, vestibular.thresholds.fs[0], dt);
  const Episodes ey = Above(cues.sway, vestibular.thresholds.fs[1], dt);
  cues.surge_above_threshold_count = es.count;
  cues.surge_above_threshold_s = es.seconds;
  cues.sway_above_threshold_count = ey.count;
  cues.sway_above_threshold_s = ey.seconds;
  return cues;
}

CueingTrace RunRailYawCueing(const McaConfig& config, const std::vector<HeadMotion>& truth, double dt,
                             VehiclePredictor* predictor) {
  CueingTrace trace = RunCueing(config, truth, dt, predictor);
  std::vector<DofArray> poses;
  poses.reserve(trace.commands.size());
  for (const McaCommand& c : trace.commands) poses.push_back(c.pose);
  trace.delivered = DeliveredRailYawHeadMotion(config.platform, poses, dt);
  VestibularModel platform(config.vestibular, dt);
  trace.perceived_platform.clear();
  trace.perceived_platform.reserve(trace.delivered.size());
  for (const HeadMotion& m : trace.delivered) trace.perceived_platform.push_back(platform.Step(m));
  return trace;
}

}  // namespace pwsim::mca
