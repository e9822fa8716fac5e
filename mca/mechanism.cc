#include "mca/mechanism.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <utility>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

using Matrix36 = Eigen::Matrix<double, 3, 6>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using MovedJacobian = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxActuators, 6>;

constexpr std::size_t At(Dof dof) { return static_cast<std::size_t>(Index(dof)); }

/// The rotations of X_BP(x): Rz(ψ), Ry(−θ), Rx(φ).
struct Rotations {
  Eigen::Matrix3d rz, ry, rx;
  explicit Rotations(const DofArray& x) {
    const double cz = std::cos(x[At(Dof::kYaw)]), sz = std::sin(x[At(Dof::kYaw)]);
    const double cy = std::cos(x[At(Dof::kPitch)]), sy = std::sin(x[At(Dof::kPitch)]);
    const double cx = std::cos(x[At(Dof::kRoll)]), sx = std::sin(x[At(Dof::kRoll)]);
    rz << cz, -sz, 0.0, sz, cz, 0.0, 0.0, 0.0, 1.0;
    // Ry(−θ): a rotation by −θ about y (nose-up for θ > 0, y pointing left)
    ry << cy, 0.0, -sy, 0.0, 1.0, 0.0, sy, 0.0, cy;
    rx << 1.0, 0.0, 0.0, 0.0, cx, -sx, 0.0, sx, cx;
  }
  Eigen::Matrix3d R() const { return rz * ry * rx; }
};

/// p = Rz (t + Ry(−θ) Rx a) with t = (s, w, height + z), and ∂p/∂x on the axes of `mask`
/// (other columns 0). See the header for the derivatives.
void PointAndJacobian(const DofArray& x, double height, const Eigen::Vector3d& a, const DofMask& mask,
                      Eigen::Vector3d* p, Matrix36* dp) {
  const Rotations r(x);
  const Eigen::Vector3d t(x[At(Dof::kSurge)], x[At(Dof::kSway)], height + x[At(Dof::kHeave)]);
  const Eigen::Vector3d v = r.rx * a;
  *p = r.rz * (t + r.ry * v);
  if (dp == nullptr) return;
  dp->setZero();
  if (mask[At(Dof::kSurge)]) dp->col(Index(Dof::kSurge)) = r.rz.col(0);
  if (mask[At(Dof::kSway)]) dp->col(Index(Dof::kSway)) = r.rz.col(1);
  if (mask[At(Dof::kHeave)]) dp->col(Index(Dof::kHeave)) = r.rz.col(2);
  if (mask[At(Dof::kRoll)]) dp->col(Index(Dof::kRoll)) = r.rz * (r.ry * (r.rx * Eigen::Vector3d::UnitX().cross(a)));
  if (mask[At(Dof::kPitch)]) dp->col(Index(Dof::kPitch)) = -(r.rz * (r.ry * Eigen::Vector3d::UnitY().cross(v)));
  if (mask[At(Dof::kYaw)]) dp->col(Index(Dof::kYaw)) = Eigen::Vector3d::UnitZ().cross(*p);
}

DofArray Masked(const DofArray& x, const DofMask& mask) {
  DofArray out{};
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = mask[k] ? x[k] : 0.0;
  return out;
}

std::string Format(const char* format, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, format, a, b, c, d);
  return buffer;
}

}  // namespace

const char* ActuatorKindName(ActuatorKind kind) {
  switch (kind) {
    case ActuatorKind::kLeg: return "leg";
    case ActuatorKind::kRail: return "rail";
    case ActuatorKind::kRotary: return "rotary";
  }
  return "?";
}

Mechanism::Mechanism(double pivot_height_m, std::vector<Actuator> actuators, DofMask leg_axes, Payload payload)
    : actuators_(std::move(actuators)), pivot_height_(pivot_height_m), leg_axes_(leg_axes), payload_(payload) {
  for (int i = 0; i < static_cast<int>(actuators_.size()); ++i) {
    const Actuator& a = actuators_[static_cast<std::size_t>(i)];
    if (a.kind == ActuatorKind::kLeg) continue;
    stage_axes_[At(a.dof)] = true;
    if (stage_of_axis_[At(a.dof)] < 0) stage_of_axis_[At(a.dof)] = i;
  }
  bool any_leg = false;
  for (const Actuator& a : actuators_) any_leg = any_leg || a.kind == ActuatorKind::kLeg;
  if (!any_leg) leg_axes_ = DofMask{};
  if (actuators_.size() <= static_cast<std::size_t>(kMaxActuators)) {
    neutral_.setZero(actuator_count());
    Inverse(DofArray{}, &neutral_);
  }
}

int Mechanism::actuator_count() const { return static_cast<int>(actuators_.size()); }

const Actuator& Mechanism::actuator(int i) const {
  PWSIM_DEMAND(i >= 0 && i < actuator_count());
  return actuators_[static_cast<std::size_t>(i)];
}

bool Mechanism::Moves(Dof dof) const { return stage_axes_[At(dof)] || leg_axes_[At(dof)]; }

double Mechanism::pivot_height() const { return pivot_height_; }

DofMask Mechanism::moved_axes() const {
  DofMask mask{};
  for (Dof dof : kAllDofs) mask[At(dof)] = Moves(dof);
  return mask;
}

int Mechanism::moved_axis_count() const {
  int n = 0;
  for (Dof dof : kAllDofs) n += Moves(dof) ? 1 : 0;
  return n;
}

int Mechanism::Find(const std::string& name) const {
  for (int i = 0; i < actuator_count(); ++i) {
    if (actuators_[static_cast<std::size_t>(i)].name == name) return i;
  }
  return -1;
}

bool Mechanism::LegEndpoints(int i, const DofArray& pose, Eigen::Vector3d* base_B, Eigen::Vector3d* plate_B) const {
  if (i < 0 || i >= actuator_count()) return false;
  const Actuator& a = actuators_[static_cast<std::size_t>(i)];
  if (a.kind != ActuatorKind::kLeg) return false;
  const DofArray x = Masked(pose, moved_axes());
  PointAndJacobian(x, pivot_height_, a.plate_anchor, leg_axes_, plate_B, nullptr);
  PointAndJacobian(Masked(x, stage_axes_), 0.0, a.base_anchor, stage_axes_, base_B, nullptr);
  return true;
}

bool Mechanism::LegGeometry(int i, const DofArray& pose, Eigen::Vector3d* u, Eigen::Vector3d* r) const {
  Eigen::Vector3d b, p;
  if (!LegEndpoints(i, pose, &b, &p)) return false;
  const double length = (p - b).norm();
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  *u = (p - b) / length;
  const DofArray x = Masked(pose, moved_axes());
  const Rotations rot(x);
  const Eigen::Vector3d pivot =
      rot.rz * Eigen::Vector3d(x[At(Dof::kSurge)], x[At(Dof::kSway)], pivot_height_ + x[At(Dof::kHeave)]);
  *r = p - pivot;
  return true;
}

bool Mechanism::Inverse(const DofArray& pose, ActuatorVector* q) const {
  const DofArray x = Masked(pose, moved_axes());
  for (double v : x) {
    if (!std::isfinite(v)) return false;
  }
  const DofArray xs = Masked(x, stage_axes_);
  ActuatorVector out(actuator_count());
  for (int i = 0; i < actuator_count(); ++i) {
    const Actuator& a = actuators_[static_cast<std::size_t>(i)];
    if (a.kind != ActuatorKind::kLeg) {
      out[i] = x[At(a.dof)];
      continue;
    }
    Eigen::Vector3d p, b;
    PointAndJacobian(x, pivot_height_, a.plate_anchor, leg_axes_, &p, nullptr);
    PointAndJacobian(xs, 0.0, a.base_anchor, stage_axes_, &b, nullptr);
    out[i] = (p - b).norm();
    if (!(out[i] > 0.0) || !std::isfinite(out[i])) return false;
  }
  *q = out;
  return true;
}

void Mechanism::Jacobian(const DofArray& pose, ActuatorJacobian* jacobian) const {
  const DofMask moved = moved_axes();
  const DofArray x = Masked(pose, moved);
  const DofArray xs = Masked(x, stage_axes_);
  jacobian->resize(actuator_count(), 6);
  jacobian->setZero();
  for (int i = 0; i < actuator_count(); ++i) {
    const Actuator& a = actuators_[static_cast<std::size_t>(i)];
    if (a.kind != ActuatorKind::kLeg) {
      (*jacobian)(i, Index(a.dof)) = 1.0;
      continue;
    }
    Eigen::Vector3d p, b;
    Matrix36 dp, db;
    PointAndJacobian(x, pivot_height_, a.plate_anchor, moved, &p, &dp);
    PointAndJacobian(xs, 0.0, a.base_anchor, stage_axes_, &b, &db);
    const double length = (p - b).norm();
    if (!(length > 0.0)) continue;  // degenerate: a zero row (Reachability reports it singular)
    const Eigen::Vector3d u = (p - b) / length;
    jacobian->row(i) = u.transpose() * (dp - db);
  }
}

KinematicsStatus Mechanism::Forward(const ActuatorVector& q, const DofArray& guess, DofArray* pose) const {
  KinematicsStatus status;
  if (q.size() != actuator_count()) {
    status.reason = "q has the wrong number of actuator positions";
    return status;
  }
  if (!q.allFinite()) {
    status.reason = "q is not finite";
    return status;
  }
  DofArray x = Masked(guess, leg_axes_);
  for (Dof dof : kAllDofs) {
    if (stage_axes_[At(dof)]) x[At(dof)] = q[stage_of_axis_[At(dof)]];
  }
  bool any_leg = false;
  for (bool b : leg_axes_) any_leg = any_leg || b;
  if (!any_leg) {
    *pose = x;
    status.ok = true;
    return status;
  }

  const DofArray xs = Masked(x, stage_axes_);
  const int n = actuator_count();
  // the base anchors do not depend on the leg axes: computed once
  std::array<Eigen::Vector3d, kMaxActuators> base{};
  for (int i = 0; i < n; ++i) {
    const Actuator& a = actuators_[static_cast<std::size_t>(i)];
    if (a.kind == ActuatorKind::kLeg) PointAndJacobian(xs, 0.0, a.base_anchor, stage_axes_, &base[static_cast<std::size_t>(i)], nullptr);
  }
  // residual r_i = length_i(x) − q_i over the legs; optionally J_L rows (leg axes only)
  auto residual = [&](const DofArray& at, ActuatorVector* r, ActuatorJacobian* jl) {
    r->resize(n);
    if (jl != nullptr) {
      jl->resize(n, 6);
      jl->setZero();
    }
    double cost = 0.0;
    for (int i = 0; i < n; ++i) {
      const Actuator& a = actuators_[static_cast<std::size_t>(i)];
      if (a.kind != ActuatorKind::kLeg) {
        (*r)[i] = 0.0;
        continue;
      }
      Eigen::Vector3d p;
      Matrix36 dp;
      PointAndJacobian(at, pivot_height_, a.plate_anchor, leg_axes_, &p, jl != nullptr ? &dp : nullptr);
      const Eigen::Vector3d d = p - base[static_cast<std::size_t>(i)];
      const double length = d.norm();
      (*r)[i] = length - q[i];
      cost += (*r)[i] * (*r)[i];
      if (jl != nullptr && length > 0.0) jl->row(i) = (d / length).transpose() * dp;
    }
    return cost;
  };

  ActuatorVector r;
  ActuatorJacobian jl;
  bool converged = false;
  int it = 0;
  double cost = residual(x, &r, &jl);
  for (; it < kMaxIterations && std::isfinite(cost); ++it) {
    Matrix6 a = jl.transpose() * jl;
    const Vector6 g = jl.transpose() * r;
    for (Dof dof : kAllDofs) {
      if (!leg_axes_[At(dof)]) {
        a.row(Index(dof)).setZero();
        a.col(Index(dof)).setZero();
        a(Index(dof), Index(dof)) = 1.0;
      }
    }
    const Eigen::SelfAdjointEigenSolver<Matrix6> eigen(a);
    if (eigen.info() != Eigen::Success || eigen.eigenvalues()[0] < kSingularTolerance * kSingularTolerance) {
      *pose = x;
      status.iterations = it;
      status.residual = r.cwiseAbs().maxCoeff();
      status.reason = "singular: the legs' Jacobian on the leg axes has lost rank";
      return status;
    }
    const Vector6 step = -(eigen.eigenvectors() *
                           (eigen.eigenvalues().cwiseInverse().asDiagonal() * (eigen.eigenvectors().transpose() * g)));
    // halving line search on |r|² (Gauss–Newton's step is a descent direction)
    double t = 1.0;
    DofArray trial = x;
    double trial_cost = cost;
    for (int halving = 0; halving < 30; ++halving) {
      for (std::size_t k = 0; k < trial.size(); ++k) trial[k] = x[k] + t * step[static_cast<Eigen::Index>(k)];
      trial_cost = residual(trial, &r, nullptr);
      if (trial_cost <= cost) break;
      t *= 0.5;
    }
    const double moved = t * step.cwiseAbs().maxCoeff();
    if (trial_cost > cost) {  // no decrease at any step length: x is the (local) least-squares point
      residual(x, &r, nullptr);
      converged = true;
      break;
    }
    x = trial;
    cost = residual(x, &r, &jl);
    if (moved < kStepTolerance) {
      converged = true;
      ++it;
      break;
    }
  }
  *pose = x;
  status.iterations = it;
  status.residual = r.size() > 0 ? r.cwiseAbs().maxCoeff() : 0.0;
  if (!std::isfinite(cost)) {
    status.reason = "the iteration diverged";
    return status;
  }
  if (!converged) {
    status.reason = "no convergence within the iteration limit";
    return status;
  }
  status.ok = true;
  status.reason = status.residual <= 1e-9 ? ""
                                          : "least squares: the leg lengths are inconsistent by `residual` [m]";
  return status;
}

double Mechanism::SmallestSingularValue(const DofArray& pose) const {
  const int m = moved_axis_count();
  if (m == 0 || actuator_count() == 0) return 0.0;
  ActuatorJacobian j;
  Jacobian(pose, &j);
  MovedJacobian jm(actuator_count(), m);
  int c = 0;
  for (Dof dof : kAllDofs) {
    if (Moves(dof)) jm.col(c++) = j.col(Index(dof));
  }
  if (actuator_count() < m) return 0.0;
  const Eigen::JacobiSVD<MovedJacobian> svd(jm);
  return svd.singularValues().minCoeff();
}

std::string Mechanism::Reachability(const DofArray& pose, double margin_fraction) const {
  for (Dof dof : kAllDofs) {
    if (!Moves(dof) && pose[At(dof)] != 0.0) {
      return std::string(DofName(dof)) + " = " + Format("%.6g", pose[At(dof)]) + " " + std::string(DofUnit(dof)) +
             ", but this mechanism does not move " + std::string(DofName(dof));
    }
  }
  ActuatorVector q;
  if (!Inverse(pose, &q)) return "not computable: a pose entry is not finite or a leg would have zero length";
  for (int i = 0; i < actuator_count(); ++i) {
    const Actuator& a = actuators_[static_cast<std::size_t>(i)];
    const double lo = a.limits.min, hi = a.limits.max;
    const double span = hi - lo;
    const double margin = std::isfinite(span) ? margin_fraction * span : 0.0;
    const double in_lo = std::isfinite(lo) ? lo + margin : lo;
    const double in_hi = std::isfinite(hi) ? hi - margin : hi;
    if (q[i] < in_lo || q[i] > in_hi) {
      const bool rad = a.kind == ActuatorKind::kRotary;
      const double scale = rad ? 1.0 / kDegToRad : 1.0;
      const char* unit = rad ? "deg" : "m";
      std::string msg = std::string(ActuatorKindName(a.kind)) + " '" + a.name + "' at " + Format("%.4f", q[i] * scale) +
                        " " + unit + " is outside its stroke [" + Format("%.4f, %.4f", lo * scale, hi * scale) + "] " +
                        unit;
      if (margin > 0.0) {
        msg += " less a " + Format("%g", 100.0 * margin_fraction) + " % margin, i.e. [" +
               Format("%.4f, %.4f", in_lo * scale, in_hi * scale) + "] " + unit;
      }
      msg += " (" + Format("%.4f", (q[i] < in_lo ? in_lo - q[i] : q[i] - in_hi) * scale) + " " + unit + " beyond)";
      return msg;
    }
  }
  const double sigma = SmallestSingularValue(pose);
  if (sigma < kSingularTolerance) {
    return "singular: the smallest singular value of the Jacobian on the moved axes is " + Format("%.3g", sigma) +
           " < " + Format("%.3g", kSingularTolerance) + " (m per m or rad)";
  }
  return {};
}

Eigen::Matrix<double, 6, 1> Mechanism::GeneralizedForce(const DofArray& pose, const Wrench& wrench) const {
  const DofArray x = Masked(pose, moved_axes());
  const Rotations r(x);
  const Eigen::Vector3d pivot =
      r.rz * Eigen::Vector3d(x[At(Dof::kSurge)], x[At(Dof::kSway)], pivot_height_ + x[At(Dof::kHeave)]);
  const Eigen::Vector3d force = wrench.head<3>();
  const Eigen::Vector3d moment = wrench.tail<3>();
  Vector6 q = Vector6::Zero();
  // columns of T = ∂(ȯ, ω)/∂ẋ
  q[Index(Dof::kSurge)] = force.dot(r.rz.col(0));
  q[Index(Dof::kSway)] = force.dot(r.rz.col(1));
  q[Index(Dof::kHeave)] = force.dot(r.rz.col(2));
  q[Index(Dof::kRoll)] = moment.dot(r.rz * (r.ry * Eigen::Vector3d::UnitX()));
  q[Index(Dof::kPitch)] = -moment.dot(r.rz.col(1));
  q[Index(Dof::kYaw)] = force.dot(Eigen::Vector3d::UnitZ().cross(pivot)) + moment.z();
  for (Dof dof : kAllDofs) {
    if (!Moves(dof)) q[Index(dof)] = 0.0;
  }
  return q;
}

Wrench Mechanism::PayloadWrench(const DofArray& pose) const {
  const DofArray x = Masked(pose, moved_axes());
  const Eigen::Vector3d com = Rotations(x).R() * payload_.com_from_pivot;
  const Eigen::Vector3d weight(0.0, 0.0, payload_.mass * kGravity);  // held up: upwards
  Wrench w;
  w << weight, com.cross(weight);
  return w;
}

bool Mechanism::ActuatorForces(const DofArray& pose, const Eigen::Matrix<double, 6, 1>& wrench,
                               ActuatorVector* f) const {
  if (actuator_count() == 0) return false;
  ActuatorJacobian j;
  Jacobian(pose, &j);
  const Vector6 g = GeneralizedForce(pose, wrench);
  Matrix6 a = j.transpose() * j;
  for (Dof dof : kAllDofs) {
    if (!Moves(dof)) {
      a.row(Index(dof)).setZero();
      a.col(Index(dof)).setZero();
      a(Index(dof), Index(dof)) = 1.0;
    }
  }
  const Eigen::SelfAdjointEigenSolver<Matrix6> eigen(a);
  if (eigen.info() != Eigen::Success || eigen.eigenvalues()[0] < kSingularTolerance * kSingularTolerance) return false;
  // minimum norm: f = J_m λ with J_mᵀ J_m λ = g
  const Vector6 lambda =
      eigen.eigenvectors() * (eigen.eigenvalues().cwiseInverse().asDiagonal() * (eigen.eigenvectors().transpose() * g));
  *f = j * lambda;
  return true;
}

ActuatorVector Mechanism::Neutral() const { return neutral_; }

void Mechanism::StrokeUse(const ActuatorVector& q, ActuatorVector* use) const {
  use->resize(actuator_count());
  for (int i = 0; i < actuator_count(); ++i) {
    const ActuatorLimits& l = actuators_[static_cast<std::size_t>(i)].limits;
    const double q0 = neutral_.size() == actuator_count() ? neutral_[i] : 0.0;
    const double d = q[i] - q0;
    const double room = d >= 0.0 ? l.max - q0 : q0 - l.min;
    (*use)[i] = std::isfinite(room) && room > 0.0 ? std::abs(d) / room : 0.0;
  }
}

std::string Mechanism::Validate() const {
  const int n = actuator_count();
  if (n == 0) return "a mechanism needs at least one actuator";
  if (n > kMaxActuators) return "at most " + std::to_string(kMaxActuators) + " actuators, got " + std::to_string(n);
  std::set<std::string> names;
  std::array<int, kDofCount> stages{};
  int legs = 0;
  for (const Actuator& a : actuators_) {
    const std::string who = std::string(ActuatorKindName(a.kind)) + " '" + a.name + "'";
    if (a.name.empty()) return "an actuator without a name";
    if (!names.insert(a.name).second) return "two actuators named '" + a.name + "'";
    const ActuatorLimits& l = a.limits;
    const bool may_be_free = a.kind == ActuatorKind::kRotary;
    if (!(l.min < l.max)) return who + ": stroke min must be < max";
    if (!may_be_free && (!std::isfinite(l.min) || !std::isfinite(l.max))) return who + ": stroke must be finite";
    if (!(l.speed > 0.0) || !std::isfinite(l.speed)) return who + ": speed must be finite and > 0";
    if (!(l.accel > 0.0) || !std::isfinite(l.accel)) return who + ": accel must be finite and > 0";
    if (!(l.force > 0.0)) return who + ": force limit must be > 0";
    if (a.kind == ActuatorKind::kLeg) {
      ++legs;
      if (!a.base_anchor.allFinite() || !a.plate_anchor.allFinite()) return who + ": anchors must be finite";
      continue;
    }
    if (a.kind == ActuatorKind::kRail && IsRotational(a.dof)) {
      return who + ": a rail drives a translation, not " + std::string(DofName(a.dof));
    }
    if (a.kind == ActuatorKind::kRotary && !IsRotational(a.dof)) {
      return who + ": a rotary stage drives a rotation, not " + std::string(DofName(a.dof));
    }
    if (++stages[At(a.dof)] > 1) return "two stages drive " + std::string(DofName(a.dof));
    if (leg_axes_[At(a.dof)]) return who + " drives " + std::string(DofName(a.dof)) + ", which the legs also move";
  }
  int leg_axis_count = 0;
  for (bool b : leg_axes_) leg_axis_count += b ? 1 : 0;
  if (legs > 0 && leg_axis_count == 0) return "legs but no leg axes (which plate axes do the legs move?)";
  if (legs < leg_axis_count) {
    return std::to_string(legs) + " legs cannot move " + std::to_string(leg_axis_count) + " axes";
  }
  if (!(payload_.mass >= 0.0) || !std::isfinite(payload_.mass)) return "payload mass must be >= 0";
  if (!std::isfinite(pivot_height_)) return "pivot height must be finite";
  ActuatorVector q;
  if (!Inverse(DofArray{}, &q)) return "a leg has zero length at neutral";
  for (int i = 0; i < n; ++i) {
    const Actuator& a = actuators_[static_cast<std::size_t>(i)];
    if (!(q[i] > a.limits.min && q[i] < a.limits.max)) {
      return std::string(ActuatorKindName(a.kind)) + " '" + a.name + "': its neutral position " +
             Format("%.4f", q[i]) + " " + a.unit() + " is not inside its stroke [" +
             Format("%.4f, %.4f", a.limits.min, a.limits.max) + "] " + a.unit();
    }
  }
  const double sigma = SmallestSingularValue(DofArray{});
  if (sigma < kSingularTolerance) {
    return "the actuators cannot move every moved axis independently at neutral (smallest singular value of "
           "the Jacobian " + Format("%.3g", sigma) + " < " + Format("%.3g", kSingularTolerance) + ")";
  }
  return {};
}

}  // namespace pwsim::mca
