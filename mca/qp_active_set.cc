#include "mca/qp_active_set.h"

#include <cmath>
#include <limits>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kFeasibility = 1e-9;   ///< ε_f: relative violation tolerance of a slack
constexpr double kDataUlps = 1e-15;     ///< ε_d: of the largest finite offset, for zero rows
constexpr double kDependence = 1e-10;   ///< ε_l: relative size of J₂ᵀ n_p below which n_p is dependent
constexpr double kBlocking = 1e-12;     ///< ε_r: relative size of r_j that blocks a step

}  // namespace

ActiveSetQp::ActiveSetQp(const Eigen::MatrixXd& hessian, const Eigen::MatrixXd& constraints)
    : n_(static_cast<int>(hessian.rows())), rows_(static_cast<int>(constraints.rows())) {
  PWSIM_DEMAND(hessian.rows() == hessian.cols() && n_ > 0);
  PWSIM_DEMAND(constraints.cols() == hessian.cols());
  llt_.compute(hessian);
  PWSIM_DEMAND(llt_.info() == Eigen::Success);
  // J0 = L⁻ᵀ
  j0_.setIdentity(n_, n_);
  llt_.matrixU().solveInPlace(j0_);
  a_ = constraints;
  row_norm1_ = a_.cwiseAbs().rowwise().sum();
  row_inv_norm2_.resize(rows_);
  for (int i = 0; i < rows_; ++i) {
    const double norm = a_.row(i).norm();
    row_inv_norm2_(i) = norm > 0.0 ? 1.0 / norm : 0.0;
  }
  const int one_sided = 2 * (rows_ + n_);
  offset_.resize(one_sided);
  present_rows_.reserve(static_cast<std::size_t>(rows_));
  present_bounds_.reserve(static_cast<std::size_t>(n_));
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

void ActiveSetQp::SetConstraintMatrix(const Eigen::MatrixXd& constraints) {
  PWSIM_DEMAND(constraints.rows() == rows_ && constraints.cols() == n_);
  a_ = constraints;
  row_norm1_ = a_.cwiseAbs().rowwise().sum();
  for (int i = 0; i < rows_; ++i) {
    const double norm = a_.row(i).norm();
    row_inv_norm2_(i) = norm > 0.0 ? 1.0 / norm : 0.0;
  }
}

void ActiveSetQp::Normal(int c, Eigen::VectorXd& normal) const {
  const double sign = c % 2 == 0 ? 1.0 : -1.0;
  if (c < 2 * rows_) {
    normal = sign * a_.row(c / 2).transpose();
  } else {
    normal.setZero();
    normal((c - 2 * rows_) / 2) = sign;
  }
}

bool ActiveSetQp::AddConstraint(int q, double min_pivot) {
  // rotate d = Jᵀ n_p so that only d(0..q) is non-zero, rotating J's columns alike
  for (int j = n_ - 1; j > q; --j) {
    const double a = d_(j - 1), b = d_(j);
    if (b == 0.0) continue;
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
  if (!(std::abs(d_(q)) > min_pivot)) return false;  // linearly dependent on the active set
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
    if (b == 0.0) continue;
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

void ActiveSetQp::Multipliers(Eigen::VectorXd& rows, Eigen::VectorXd& bounds) const {
  rows.setZero(rows_);
  bounds.setZero(n_);
  // constraint 2i is a_lo ≤ A_i z (normal +A_i), 2i+1 is A_i z ≤ a_hi (normal −A_i): H z + b =
  // Σ u_k n_k, so the signed multiplier of A_i z is u(upper) − u(lower)
  for (int k = 0; k < q_; ++k) {
    const int c = active_[static_cast<std::size_t>(k)];
    const double u = (c % 2 == 0 ? -1.0 : 1.0) * u_(k);
    if (c < 2 * rows_) {
      rows(c / 2) += u;
    } else {
      bounds((c - 2 * rows_) / 2) += u;
    }
  }
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
  const int one_sided = static_cast<int>(offset_.size());
  present_rows_.clear();
  present_bounds_.clear();
  double offset_max = 0.0;
  for (int c = 0; c < one_sided; c += 2) {
    const bool lower = offset_(c) < kInf, upper = offset_(c + 1) < kInf;
    if (!lower && !upper) continue;
    if (c < 2 * rows_) {
      present_rows_.push_back(c / 2);
    } else {
      present_bounds_.push_back((c - 2 * rows_) / 2);
    }
    if (lower) offset_max = std::max(offset_max, std::abs(offset_(c)));
    if (upper) offset_max = std::max(offset_max, std::abs(offset_(c + 1)));
  }
  const double data_tolerance = kDataUlps * offset_max;
  // unconstrained minimum, empty active set
  z = -b;
  llt_.solveInPlace(z);
  j_ = j0_;
  q_ = 0;
  for (int i : active_) {
    if (i >= 0) is_active_[static_cast<std::size_t>(i)] = 0;
  }
  std::fill(active_.begin(), active_.end(), -1);
  const int max_steps = 5 * (n_ + one_sided);
  for (int steps = 0;;) {
    // the slacks n_cᵀ z + c_c of the inactive constraints from z; choose a violated one: the
    // previous active set first (warm start), else the one farthest from its boundary
    const double z_max = z.cwiseAbs().maxCoeff();
    int p = -1, p_warm = -1;
    double worst = 0.0, slack_worst = 0.0, slack_warm = 0.0;
    bool infeasible = false;
    // one side c (normal ±n) of a row or bound with n z = value, ‖n‖₁, 1/‖n‖₂
    const auto consider = [&](int c, double value, double norm1, double inv_norm2) {
      if (!(offset_(c) < kInf) || is_active_[static_cast<std::size_t>(c)]) return;
      const double slack = (c % 2 == 0 ? value : -value) + offset_(c);
      const double tolerance = kFeasibility * (std::abs(offset_(c)) + norm1 * z_max) + data_tolerance;
      if (slack >= -tolerance) return;
      if (inv_norm2 == 0.0) infeasible = true;  // 0 ≥ −c violated: no z satisfies it
      if (p_warm < 0 && was_active_[static_cast<std::size_t>(c)]) {
        p_warm = c;
        slack_warm = slack;
      }
      const double distance = slack * inv_norm2;
      if (distance < worst) {
        worst = distance;
        p = c;
        slack_worst = slack;
      }
    };
    for (int i : present_rows_) {
      const double value = a_.row(i).dot(z);
      consider(2 * i, value, row_norm1_(i), row_inv_norm2_(i));
      consider(2 * i + 1, value, row_norm1_(i), row_inv_norm2_(i));
    }
    for (int j : present_bounds_) {
      consider(2 * (rows_ + j), z(j), 1.0, 1.0);
      consider(2 * (rows_ + j) + 1, z(j), 1.0, 1.0);
    }
    if (infeasible) {
      status.termination = -3;
      return status;
    }
    if (p_warm >= 0) p = p_warm;
    double slack_p = p_warm >= 0 ? slack_warm : slack_worst;
    if (p < 0) {  // optimal
      for (int i = 0; i < one_sided; ++i) was_active_[static_cast<std::size_t>(i)] = is_active_[static_cast<std::size_t>(i)];
      status.ok = true;
      status.termination = 1;
      return status;
    }
    Normal(p, np_);
    u_(q_) = 0.0;
    for (;;) {
      if (++steps > max_steps) {
        status.termination = -4;
        return status;
      }
      status.iterations = steps;
      d_.noalias() = j_.transpose() * np_;
      const int q = q_;
      const double d_norm = d_.norm();                        // ‖L⁻¹ n_p‖
      const double sn = d_.tail(n_ - q).squaredNorm();        // sᵀ n_p = ‖J₂ᵀ n_p‖²
      step_.noalias() = j_.rightCols(n_ - q) * d_.tail(n_ - q);
      dual_.head(q) = d_.head(q);
      r_.topLeftCorner(q, q).triangularView<Eigen::Upper>().solveInPlace(dual_.head(q));
      const double blocking = q > 0 ? kBlocking * dual_.head(q).cwiseAbs().maxCoeff() : 0.0;
      double t1 = kInf;
      int drop = -1;
      for (int k = 0; k < q; ++k) {
        if (dual_(k) > blocking) {
          const double ratio = u_(k) / dual_(k);
          if (ratio < t1) {
            t1 = ratio;
            drop = k;
          }
        }
      }
      const double min_pivot = kDependence * d_norm;
      const double t2 = sn > min_pivot * min_pivot ? -slack_p / sn : kInf;
      const double t = std::min(t1, t2);
      if (!std::isfinite(t)) {
        status.termination = -3;  // infeasible
        return status;
      }
      if (std::isfinite(t2)) {
        z.noalias() += t * step_;
        slack_p += t * sn;
      }
      u_.head(q) -= t * dual_.head(q);
      u_(q) += t;
      if (t == t2) {  // full step: p becomes active
        if (!AddConstraint(q, min_pivot)) {
          status.termination = -3;
          return status;
        }
        active_[static_cast<std::size_t>(q)] = p;
        is_active_[static_cast<std::size_t>(p)] = 1;
        q_ = q + 1;
        break;
      }
      DropConstraint(drop);  // partial step: a multiplier reached zero
    }
  }
}

}  // namespace pwsim::mca
