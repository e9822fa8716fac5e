#include "mca/qp_active_set.h"

#include <cmath>
#include <limits>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kViolation = 1e-9;   ///< a constraint counts as violated below −this
constexpr double kTiny = 1e-12;

}  // namespace

ActiveSetQp::ActiveSetQp(const Eigen::MatrixXd& hessian, const Eigen::MatrixXd& constraints)
    : n_(static_cast<int>(hessian.rows())), rows_(static_cast<int>(constraints.rows())) {
  PWSIM_DEMAND(hessian.rows() == hessian.cols() && n_ > 0);
  PWSIM_DEMAND(constraints.cols() == hessian.cols());
  llt_.compute(hessian);
  PWSIM_DEMAND(llt_.info() == Eigen::Success);
  // J0 = L⁻ᵀ
  const Eigen::MatrixXd l = llt_.matrixL();
  j0_ = l.transpose().triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(n_, n_));
  const int one_sided = 2 * (rows_ + n_);
  normals_.resize(one_sided, n_);
  for (int i = 0; i < rows_; ++i) {
    normals_.row(2 * i) = constraints.row(i);
    normals_.row(2 * i + 1) = -constraints.row(i);
  }
  for (int j = 0; j < n_; ++j) {
    normals_.row(2 * (rows_ + j)).setZero();
    normals_(2 * (rows_ + j), j) = 1.0;
    normals_.row(2 * (rows_ + j) + 1).setZero();
    normals_(2 * (rows_ + j) + 1, j) = -1.0;
  }
  offset_.resize(one_sided);
  slack_.resize(one_sided);
  nz_.resize(one_sided);
  j_.resize(n_, n_);
  r_ = Eigen::MatrixXd::Zero(n_, n_);
  d_.resize(n_);
  step_.resize(n_);
  dual_.resize(n_);
  u_.resize(n_ + 1);
  np_.resize(n_);
  active_.assign(static_cast<std::size_t>(n_), -1);
  is_active_.assign(static_cast<std::size_t>(one_sided), 0);
  was_active_.assign(static_cast<std::size_t>(one_sided), 0);
}

bool ActiveSetQp::AddConstraint(int q) {
  // rotate d = Jᵀ n_p so that only d(0..q) is non-zero, rotating J's columns alike
  for (int j = n_ - 1; j > q; --j) {
    const double a = d_(j - 1), b = d_(j);
    if (std::abs(b) < kTiny) continue;
    const double h = std::hypot(a, b);
    const double cs = a / h, sn = b / h;
    d_(j - 1) = h;
    d_(j) = 0.0;
    for (int k = 0; k < n_; ++k) {
      const double x = j_(k, j - 1), y = j_(k, j);
      j_(k, j - 1) = cs * x + sn * y;
      j_(k, j) = -sn * x + cs * y;
    }
  }
  if (std::abs(d_(q)) < kTiny) return false;  // linearly dependent on the active set
  for (int k = 0; k <= q; ++k) r_(k, q) = d_(k);
  return true;
}

void ActiveSetQp::DropConstraint(int position) {
  const int q = q_;
  is_active_[static_cast<std::size_t>(active_[static_cast<std::size_t>(position)])] = 0;
  for (int k = position; k < q - 1; ++k) {
    active_[static_cast<std::size_t>(k)] = active_[static_cast<std::size_t>(k + 1)];
    u_(k) = u_(k + 1);
    for (int row = 0; row < q; ++row) r_(row, k) = r_(row, k + 1);
  }
  u_(q - 1) = u_(q);  // the multiplier of the constraint being added moves down with it
  // R is upper Hessenberg from `position` on: restore it by rotations of rows k, k+1
  for (int k = position; k < q - 1; ++k) {
    const double a = r_(k, k), b = r_(k + 1, k);
    if (std::abs(b) < kTiny) continue;
    const double h = std::hypot(a, b);
    const double cs = a / h, sn = b / h;
    for (int c = k; c < q - 1; ++c) {
      const double x = r_(k, c), y = r_(k + 1, c);
      r_(k, c) = cs * x + sn * y;
      r_(k + 1, c) = -sn * x + cs * y;
    }
    for (int row = 0; row < n_; ++row) {
      const double x = j_(row, k), y = j_(row, k + 1);
      j_(row, k) = cs * x + sn * y;
      j_(row, k + 1) = -sn * x + cs * y;
    }
  }
  q_ = q - 1;
}

QpStatus ActiveSetQp::Solve(const Eigen::VectorXd& b, const Eigen::VectorXd& z_lo,
                            const Eigen::VectorXd& z_hi, const Eigen::VectorXd& a_lo,
                            const Eigen::VectorXd& a_hi, Eigen::VectorXd& z) {
  PWSIM_DEMAND(b.size() == n_ && z.size() == n_ && z_lo.size() == n_ && z_hi.size() == n_);
  PWSIM_DEMAND(a_lo.size() == rows_ && a_hi.size() == rows_);
  QpStatus status;
  for (int i = 0; i < rows_; ++i) {
    offset_(2 * i) = std::isfinite(a_lo(i)) ? -a_lo(i) : kInf;
    offset_(2 * i + 1) = std::isfinite(a_hi(i)) ? a_hi(i) : kInf;
  }
  for (int j = 0; j < n_; ++j) {
    offset_(2 * (rows_ + j)) = std::isfinite(z_lo(j)) ? -z_lo(j) : kInf;
    offset_(2 * (rows_ + j) + 1) = std::isfinite(z_hi(j)) ? z_hi(j) : kInf;
  }
  // unconstrained minimum, empty active set
  Eigen::VectorXd& x = step_;  // reuse as the iterate until the loop needs step_
  x = -b;
  llt_.solveInPlace(x);
  z = x;
  j_ = j0_;
  q_ = 0;
  for (int i : active_) {
    if (i >= 0) is_active_[static_cast<std::size_t>(i)] = 0;
  }
  std::fill(active_.begin(), active_.end(), -1);
  slack_.noalias() = normals_ * z;
  slack_ += offset_;
  const int one_sided = static_cast<int>(offset_.size());
  const int max_steps = 5 * (n_ + one_sided);
  for (int steps = 0;;) {
    // choose a violated constraint: the previous active set first (warm start), else the worst
    int p = -1;
    double worst = -kViolation;
    for (int i = 0; i < one_sided; ++i) {
      if (was_active_[static_cast<std::size_t>(i)] && !is_active_[static_cast<std::size_t>(i)] &&
          slack_(i) < -kViolation) {
        p = i;
        break;
      }
    }
    if (p < 0) {
      for (int i = 0; i < one_sided; ++i) {
        if (slack_(i) < worst && !is_active_[static_cast<std::size_t>(i)]) {
          worst = slack_(i);
          p = i;
        }
      }
    }
    if (p < 0) {  // optimal
      for (int i = 0; i < one_sided; ++i) was_active_[static_cast<std::size_t>(i)] = is_active_[static_cast<std::size_t>(i)];
      status.ok = true;
      status.termination = 1;
      return status;
    }
    np_ = normals_.row(p).transpose();
    u_(q_) = 0.0;
    for (;;) {
      if (++steps > max_steps) {
        status.termination = -4;
        return status;
      }
      status.iterations = steps;
      d_.noalias() = j_.transpose() * np_;
      const int q = q_;
      step_.noalias() = j_.rightCols(n_ - q) * d_.tail(n_ - q);
      dual_.head(q) = d_.head(q);
      r_.topLeftCorner(q, q).triangularView<Eigen::Upper>().solveInPlace(dual_.head(q));
      double t1 = kInf;
      int drop = -1;
      for (int k = 0; k < q; ++k) {
        if (dual_(k) > kTiny) {
          const double ratio = u_(k) / dual_(k);
          if (ratio < t1) {
            t1 = ratio;
            drop = k;
          }
        }
      }
      const double sn = step_.dot(np_);
      const double t2 = std::abs(sn) > kTiny * (1.0 + np_.squaredNorm()) ? -slack_(p) / sn : kInf;
      const double t = std::min(t1, t2);
      if (!std::isfinite(t)) {
        status.termination = -3;  // infeasible
        return status;
      }
      if (std::isfinite(t2)) {
        z.noalias() += t * step_;
        nz_.noalias() = normals_ * step_;
        slack_.noalias() += t * nz_;
      }
      u_.head(q) -= t * dual_.head(q);
      u_(q) += t;
      if (t == t2) {  // full step: p becomes active
        if (!AddConstraint(q)) {
          status.termination = -3;
          return status;
        }
        active_[static_cast<std::size_t>(q)] = p;
        is_active_[static_cast<std::size_t>(p)] = 1;
        q_ = q + 1;
        slack_(p) = 0.0;
        break;
      }
      DropConstraint(drop);  // partial step: a multiplier reached zero
    }
  }
}

}  // namespace pwsim::mca
