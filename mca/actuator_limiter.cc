#include "mca/actuator_limiter.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

constexpr std::size_t At(Dof dof) { return static_cast<std::size_t>(Index(dof)); }
constexpr double kCouplingTolerance = 1e-12;  ///< |∂q_leg/∂x_stage| below this: independent
constexpr int kBisections = 12;
/// The share of every limit kept free (header): figures recomputed elsewhere, with another IK's
/// rounding and differenced again, still come out at or below 1 of the limit.
constexpr double kHeadroom = 1e-9;

/// Rz(ψ) Ry(−θ) Rx(φ) and Rz(ψ) t of a pose (t = (s, w, height + z)), as mca/mechanism.h.
struct Frame {
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
};

Frame MakeFrame(const DofArray& x, double height) {
  // Ry(−θ) Rx(φ) in closed form, then Rz(ψ) (skipped at ψ = 0)
  const double yaw = x[At(Dof::kYaw)], pitch = x[At(Dof::kPitch)], roll = x[At(Dof::kRoll)];
  const double cy = std::cos(pitch), sy = std::sin(pitch);
  const double cx = std::cos(roll), sx = std::sin(roll);
  Frame f;
  f.r << cy, -sy * sx, -sy * cx,  //
      0.0, cx, -sx,               //
      sy, cy * sx, cy * cx;
  f.t = Eigen::Vector3d(x[At(Dof::kSurge)], x[At(Dof::kSway)], height + x[At(Dof::kHeave)]);
  if (yaw != 0.0) {
    const double cz = std::cos(yaw), sz = std::sin(yaw);
    Eigen::Matrix3d rz;
    rz << cz, -sz, 0.0, sz, cz, 0.0, 0.0, 0.0, 1.0;
    f.r = rz * f.r;
    f.t = rz * f.t;
  }
  return f;
}

DofArray Masked(const DofArray& x, const DofMask& mask) {
  DofArray out{};
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = mask[k] ? x[k] : 0.0;
  return out;
}

}  // namespace

double StepFollowRate(double follow_rate, double vehicle_rate, double brake_accel, double dt) {
  const double step = brake_accel * dt;
  return std::clamp(vehicle_rate, follow_rate - step, follow_rate + step);
}

RateWindow TiltBand(double follow_rate, double threshold) {
  return {std::min(0.0, follow_rate) - threshold, std::max(0.0, follow_rate) + threshold};
}

double TiltCoordinationRate(double platform_rate, double follow_rate) {
  return platform_rate - std::clamp(platform_rate, std::min(0.0, follow_rate), std::max(0.0, follow_rate));
}

std::array<RateGuard, kDofCount> TiltGuards(const PlatformSpec& platform, double threshold) {
  std::array<RateGuard, kDofCount> guards{};
  for (Dof dof : {Dof::kRoll, Dof::kPitch}) {
    if (platform.Has(dof)) guards[At(dof)] = RateGuard{threshold, platform.limits(dof).brake_accel()};
  }
  return guards;
}

ActuatorLimiter::ActuatorLimiter(const PlatformSpec& platform, double dt, std::array<RateGuard, kDofCount> guards,
                                 double accel_margin)
    : mechanism_(platform.mechanism),
      actuators_(platform.mechanism.actuators()),
      dt_(dt),
      guards_(guards),
      pivot_height_(platform.mechanism.pivot_height()) {
  PWSIM_DEMAND(dt > 0.0 && accel_margin >= 0.0 && accel_margin < 1.0);
  PWSIM_DEMAND(mechanism_.Validate().empty());
  const int n = mechanism_.actuator_count();
  PWSIM_DEMAND(n > 0);
  const DofMask moved = mechanism_.moved_axes();
  for (Dof dof : kAllDofs) stage_axes_[At(dof)] = moved[At(dof)] && !mechanism_.leg_axes()[At(dof)];
  brake_accel_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) brake_accel_[static_cast<std::size_t>(i)] = (1.0 - accel_margin) * mechanism_.actuator(i).limits.accel;

  // which stages a leg depends on: J's stage columns of the legs, at neutral and at a corner
  std::vector<bool> coupled(static_cast<std::size_t>(n), false);
  bool any_leg = false;
  for (int i = 0; i < n; ++i) {
    if (mechanism_.actuator(i).kind == ActuatorKind::kLeg) coupled[static_cast<std::size_t>(i)] = any_leg = true;
  }
  if (any_leg) {
    DofArray probe{};
    for (Dof dof : kAllDofs) {
      if (!moved[At(dof)]) continue;
      const Actuator* a = nullptr;
      for (int i = 0; i < n; ++i) {
        if (mechanism_.actuator(i).kind != ActuatorKind::kLeg && mechanism_.actuator(i).dof == dof) a = &mechanism_.actuator(i);
      }
      const double span = a != nullptr && std::isfinite(a->limits.max) ? 0.5 * a->limits.max : 0.05;
      probe[At(dof)] = span;
    }
    for (const DofArray& pose : {DofArray{}, probe}) {
      mechanism_.Jacobian(pose, &jacobian_);
      for (int i = 0; i < n; ++i) {
        if (mechanism_.actuator(i).kind == ActuatorKind::kLeg) continue;
        const int axis = Index(mechanism_.actuator(i).dof);
        for (int l = 0; l < n; ++l) {
          if (mechanism_.actuator(l).kind == ActuatorKind::kLeg && std::abs(jacobian_(l, axis)) > kCouplingTolerance) {
            coupled[static_cast<std::size_t>(i)] = true;
          }
        }
      }
    }
  }
  for (int i = 0; i < n; ++i) {
    const Actuator& a = mechanism_.actuator(i);
    if (coupled[static_cast<std::size_t>(i)]) {
      coupled_.push_back(i);
      continue;
    }
    Stage s;
    s.actuator = i;
    s.dof = a.dof;
    const DofLimits& box = platform.limits(a.dof);
    s.limits.present = true;
    const bool bounded = std::isfinite(a.limits.min) && std::isfinite(a.limits.max);
    s.centre = bounded ? 0.5 * (a.limits.min + a.limits.max) : 0.0;
    s.limits.travel = bounded ? 0.5 * (a.limits.max - a.limits.min) * (1.0 - kHeadroom) : kUnlimited;
    s.limits.speed = a.limits.speed * (1.0 - kHeadroom);
    s.limits.accel = a.limits.accel * (1.0 - kHeadroom);
    if (box.present && std::isfinite(box.steady_accel)) {  // the drive's sustained rating
      s.limits.steady_accel = std::min(box.steady_accel, a.limits.accel);
      s.limits.peak_time = box.peak_time;
    }
    stages_.push_back(s);
  }
  // the axes the coupled group's positions depend on: the legs' and the coupled stages'
  coupled_or_leg_axes_ = mechanism_.leg_axes();
  for (int i : coupled_) {
    const Actuator& a = mechanism_.actuator(i);
    if (a.kind == ActuatorKind::kLeg) continue;
    coupled_or_leg_axes_[At(a.dof)] = true;
    coupled_stage_axes_any_ = true;
  }
  // the coupled axes and Â_a, V̂_a at neutral
  if (!coupled_.empty()) {
    mechanism_.Jacobian(DofArray{}, &jacobian_);
    for (Dof dof : kAllDofs) {
      const std::size_t d = At(dof);
      double accel = kUnlimited, speed = kUnlimited;
      for (int i : coupled_) {
        const double j = std::abs(jacobian_(i, Index(dof)));
        if (!(j > kCouplingTolerance)) continue;
        coupled_axes_[d] = true;
        accel = std::min(accel, brake_accel_[static_cast<std::size_t>(i)] / j);
        speed = std::min(speed, mechanism_.actuator(i).limits.speed / j);
      }
      if (coupled_axes_[d]) {
        axis_accel_[d] = accel;
        axis_speed_[d] = speed;
      }
    }
    double longest = 0.0;
    for (int i : coupled_) {
      longest = std::max(longest, mechanism_.actuator(i).limits.speed / brake_accel_[static_cast<std::size_t>(i)]);
    }
    longest_brake_ = longest;
    max_brake_ticks_ = 2 * static_cast<int>(std::ceil(longest / dt_)) + 16;
  }
  q_.resize(n);
  q_prev_.resize(n);
  q_rate_.resize(n);
  q_accel_.resize(n);
  for (ActuatorVector& v : sim_q_) v.resize(n);
  Reset();
}

void ActuatorLimiter::Reset() {
  pose_ = pose_prev_ = rate_ = accel_ = DofArray{};
  q_ = mechanism_.Neutral();
  q_prev_ = q_;
  q_rate_.setZero();
  q_accel_.setZero();
  stage_state_ = {};
  for (const Stage& s : stages_) stage_state_[At(s.dof)].pose = -s.centre;
  stats_ = ActuatorLimiterStats{};
}

bool ActuatorLimiter::StageLimits(Dof dof, DofLimits* limits, double* centre) const {
  for (const Stage& s : stages_) {
    if (s.dof != dof) continue;
    *limits = s.limits;
    *centre = s.centre;
    return true;
  }
  return false;
}

bool ActuatorLimiter::CoupledPositions(const DofArray& pose, ActuatorVector* q) const {
  // the independent stages' axes are left out (at 0): no leg depends on them (the constructor's
  // coupling test), so the floor frame is the identity unless a coupled stage moves it
  const DofArray x = Masked(pose, coupled_or_leg_axes_);
  const Frame plate = MakeFrame(x, pivot_height_);
  const bool floor_moves = coupled_stage_axes_any_;
  const Frame floor = floor_moves ? MakeFrame(Masked(x, stage_axes_), 0.0) : Frame{Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()};
  for (int i : coupled_) {
    const Actuator& a = actuators_[static_cast<std::size_t>(i)];
    if (a.kind != ActuatorKind::kLeg) {
      (*q)[i] = x[At(a.dof)];
      continue;
    }
    const Eigen::Vector3d leg = floor_moves ? Eigen::Vector3d(plate.r * a.plate_anchor + plate.t - (floor.r * a.base_anchor + floor.t))
                                            : Eigen::Vector3d(plate.r * a.plate_anchor + plate.t - a.base_anchor);
    const double length = leg.norm();
    if (!(length > 0.0) || !std::isfinite(length)) return false;
    (*q)[i] = length;
  }
  return true;
}

double ActuatorLimiter::BrakeTime(const ActuatorVector& q_now, const ActuatorVector& q_prev) const {
  double t = 0.0;
  for (int i : coupled_) {
    const double r = (q_now[i] - q_prev[i]) / dt_;
    t = std::max(t, std::abs(r) / brake_accel_[static_cast<std::size_t>(i)]);
  }
  return t;
}

void ActuatorLimiter::BrakeStep(const DofArray& x_now, const DofArray& x_prev, const ActuatorVector& q_now,
                                const ActuatorVector& q_prev, DofArray* x_next, double* brake_time) const {
  const double t = BrakeTime(q_now, q_prev);
  const double lambda = t > dt_ ? 1.0 - dt_ / t : 0.0;
  *x_next = x_now;
  for (std::size_t d = 0; d < kDofCount; ++d) {
    if (!coupled_axes_[d]) continue;
    const double rate = (x_now[d] - x_prev[d]) / dt_;
    (*x_next)[d] = x_now[d] + (lambda * rate) * dt_;
  }
  *brake_time = t;
}

bool ActuatorLimiter::TickWithinLimits(const DofArray& x_now, const DofArray& x_next, const ActuatorVector& q_prev,
                                       const ActuatorVector& q_now, const ActuatorVector& q_next) const {
  double brake_time = 0.0;
  for (int i : coupled_) {
    const ActuatorLimits& lim = actuators_[static_cast<std::size_t>(i)].limits;
    const double r_now = (q_now[i] - q_prev[i]) / dt_;
    const double r_next = (q_next[i] - q_now[i]) / dt_;
    const double inset = kHeadroom * 0.5 * (lim.max - lim.min);
    if (!(q_next[i] >= lim.min + inset && q_next[i] <= lim.max - inset)) return false;
    if (!(std::abs(r_next) <= lim.speed * (1.0 - kHeadroom))) return false;
    if (!(std::abs((r_next - r_now) / dt_) <= lim.accel * (1.0 - kHeadroom))) return false;
    brake_time = std::max(brake_time, std::abs(r_next) / brake_accel_[static_cast<std::size_t>(i)]);
  }
  if (brake_time <= dt_) return true;
  for (std::size_t d = 0; d < kDofCount; ++d) {  // the guards of invariant S
    if (!coupled_axes_[d] || !std::isfinite(guards_[d].core)) continue;
    const double rate = std::abs((x_next[d] - x_now[d]) / dt_);
    if (rate > guards_[d].core && guards_[d].edge_accel * brake_time > rate) return false;
  }
  return true;
}

bool ActuatorLimiter::CoupledFeasible(const DofArray& rho, const std::array<RateWindow, kDofCount>* windows,
                                      DofArray* next_pose, ActuatorVector* next_q) {
  DofArray x1 = pose_;
  for (std::size_t d = 0; d < kDofCount; ++d) {
    if (!coupled_axes_[d]) continue;
    if (!std::isfinite(rho[d])) return false;
    x1[d] = pose_[d] + rho[d] * dt_;
    if (windows != nullptr) {
      const double rate = (x1[d] - pose_[d]) / dt_;
      if (rate < (*windows)[d].lo || rate > (*windows)[d].hi) return false;
    }
  }
  ActuatorVector* q[3] = {&sim_q_[0], &sim_q_[1], &sim_q_[2]};  // (previous, current, next)
  *q[0] = q_;
  *q[1] = q_;
  if (!CoupledPositions(x1, q[1])) return false;
  if (!TickWithinLimits(pose_, x1, q_prev_, q_, *q[1])) return false;
  *next_pose = x1;
  *next_q = *q[1];
  // invariant S at the next state: its brake sequence, simulated
  DofArray xa = pose_, xb = x1;  // (previous, current) poses of the sequence
  for (int step = 0;; ++step) {
    if (step > max_brake_ticks_) return false;
    DofArray xc;
    double brake_time = 0.0;
    BrakeStep(xb, xa, *q[1], *q[0], &xc, &brake_time);
    if (brake_time == 0.0) return true;  // at rest: it stays there
    ++stats_.simulated;
    *q[2] = *q[1];
    if (!CoupledPositions(xc, q[2])) return false;
    if (!TickWithinLimits(xb, xc, *q[0], *q[1], *q[2])) return false;
    std::rotate(q, q + 1, q + 3);
    xa = xb;
    xb = xc;
  }
}

void ActuatorLimiter::Step(const DofArray& target, const DofArray& target_rate,
                           const std::array<RateWindow, kDofCount>& windows, double speed_fraction) {
  ++stats_.ticks;
  const DofArray old_pose = pose_, old_rate = rate_;
  // independent stages: the 1-D limiter about the stroke's centre
  for (const Stage& s : stages_) {
    const std::size_t d = At(s.dof);
    const double cap = speed_fraction * s.limits.speed;
    const RateWindow window{std::max(-cap, windows[d].lo), std::min(cap, windows[d].hi)};
    stage_state_[d] = StepLimiter(s.limits, stage_state_[d], target[d] - s.centre, target_rate[d], window, dt_);
    pose_[d] = stage_state_[d].pose + s.centre;
  }
  ActuatorVector next_q = q_;
  for (const Stage& s : stages_) next_q[s.actuator] = pose_[At(s.dof)];
  // the coupled group
  if (!coupled_.empty()) {
    DofArray current{}, brake{}, candidate{};
    double brake_time = 0.0;
    DofArray brake_pose;
    BrakeStep(pose_, pose_prev_, q_, q_prev_, &brake_pose, &brake_time);
    for (std::size_t d = 0; d < kDofCount; ++d) {
      if (!coupled_axes_[d]) continue;
      current[d] = (pose_[d] - pose_prev_[d]) / dt_;
      brake[d] = (brake_pose[d] - pose_[d]) / dt_;
      double desired = 0.0;
      if (std::isfinite(target[d]) && std::isfinite(target_rate[d])) {
        const double gap = (target[d] - target_rate[d] * dt_) - pose_[d];
        const double size = std::abs(gap);
        const double close = size < 1e-12 ? size / dt_ : StoppableSpeed(size, axis_accel_[d], dt_);
        desired = target_rate[d] + std::copysign(close, gap);
      } else {
        desired = brake[d];
      }
      const double cap = speed_fraction * axis_speed_[d];
      desired = std::clamp(desired, -cap, cap);
      candidate[d] = std::clamp(desired, windows[d].lo, windows[d].hi);
    }
    DofArray chosen_pose = brake_pose;
    ActuatorVector chosen_q = next_q;
    DofArray trial_pose;
    ActuatorVector trial_q = next_q;
    bool taken = CoupledFeasible(candidate, &windows, &trial_pose, &trial_q);
    if (!taken) {
      // the candidate's change of rate, scaled to the linearised actuator accelerations
      mechanism_.Jacobian(pose_, &jacobian_);
      double scale = 1.0;
      for (int i : coupled_) {
        double change = 0.0;
        for (std::size_t d = 0; d < kDofCount; ++d) {
          if (coupled_axes_[d]) change += jacobian_(i, static_cast<Eigen::Index>(d)) * (candidate[d] - current[d]);
        }
        const double allowed = mechanism_.actuator(i).limits.accel * dt_;
        if (std::abs(change) > allowed) scale = std::min(scale, allowed / std::abs(change));
      }
      if (scale < 1.0) {
        for (std::size_t d = 0; d < kDofCount; ++d) {
          if (coupled_axes_[d]) candidate[d] = current[d] + scale * (candidate[d] - current[d]);
        }
        taken = CoupledFeasible(candidate, &windows, &trial_pose, &trial_q);
      }
    }
    if (taken) {
      chosen_pose = trial_pose;
      chosen_q = trial_q;
    } else {
      ++stats_.reduced;
      double lo = 0.0, hi = 1.0;
      for (int k = 0; k < kBisections; ++k) {
        const double mid = 0.5 * (lo + hi);
        DofArray rho{};
        for (std::size_t d = 0; d < kDofCount; ++d) {
          if (coupled_axes_[d]) rho[d] = brake[d] + mid * (candidate[d] - brake[d]);
        }
        if (CoupledFeasible(rho, &windows, &trial_pose, &trial_q)) {
          lo = mid;
          chosen_pose = trial_pose;
          chosen_q = trial_q;
        } else {
          hi = mid;
        }
      }
      if (lo == 0.0) {
        ++stats_.braked;
        chosen_q = q_;
        CoupledPositions(brake_pose, &chosen_q);  // s = 0: the brake step, vouched for by S
      }
    }
    for (std::size_t d = 0; d < kDofCount; ++d) {
      if (coupled_axes_[d]) pose_[d] = chosen_pose[d];
    }
    for (int i : coupled_) next_q[i] = chosen_q[i];
  }
  pose_prev_ = old_pose;
  for (std::size_t d = 0; d < kDofCount; ++d) {
    rate_[d] = (pose_[d] - old_pose[d]) / dt_;
    accel_[d] = (rate_[d] - old_rate[d]) / dt_;
  }
  for (int i = 0; i < q_.size(); ++i) {
    const double r = (next_q[i] - q_[i]) / dt_;
    q_accel_[i] = (r - q_rate_[i]) / dt_;
    q_rate_[i] = r;
  }
  q_prev_ = q_;
  q_ = next_q;
}

}  // namespace pwsim::mca
