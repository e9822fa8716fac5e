#include "mca/qp_alglib.h"

#include <optimization.h>

#include <cmath>
#include <limits>

#include "engine/check.h"

namespace pwsim::mca {

std::string_view QpAlgorithmName(QpAlgorithm algorithm) {
  switch (algorithm) {
    case QpAlgorithm::kActiveSet: return "active_set";
    case QpAlgorithm::kBleic: return "bleic";
    case QpAlgorithm::kDenseAul: return "dense_aul";
    case QpAlgorithm::kDenseIpm: return "dense_ipm";
  }
  return "?";
}

struct AlglibQp::Impl {
  alglib::minqpstate state;
  alglib::minqpreport report;
  alglib::real_2d_array constraint_matrix;  ///< r × n (set once, passed on every solve)
  alglib::real_1d_array b, lo, hi, c_lo, c_hi, start, solution;
};

namespace {

void Fill(alglib::real_1d_array& dst, const Eigen::VectorXd& src) {
  for (Eigen::Index i = 0; i < src.size(); ++i) dst[i] = src[i];
}

/// ALGLIB takes ±inf as "no bound" in its own representation.
void FillBound(alglib::real_1d_array& dst, const Eigen::VectorXd& src) {
  for (Eigen::Index i = 0; i < src.size(); ++i) {
    const double v = src[i];
    dst[i] = std::isinf(v) ? (v > 0 ? alglib::fp_posinf : alglib::fp_neginf) : v;
  }
}

}  // namespace

AlglibQp::AlglibQp(QpAlgorithm algorithm, const Eigen::MatrixXd& hessian,
                   const Eigen::MatrixXd& constraints, double tolerance)
    : algorithm_(algorithm),
      n_(static_cast<int>(hessian.rows())),
      r_(static_cast<int>(constraints.rows())),
      impl_(std::make_unique<Impl>()) {
  PWSIM_DEMAND(hessian.rows() == hessian.cols() && hessian.rows() > 0);
  PWSIM_DEMAND(constraints.cols() == hessian.cols());
  Impl& m = *impl_;
  alglib::minqpcreate(n_, m.state);
  alglib::real_2d_array h;
  h.setlength(n_, n_);
  for (int i = 0; i < n_; ++i) {
    for (int j = 0; j < n_; ++j) h(i, j) = hessian(i, j);
  }
  alglib::minqpsetquadraticterm(m.state, h, true);
  m.constraint_matrix.setlength(r_, n_);
  for (int i = 0; i < r_; ++i) {
    for (int j = 0; j < n_; ++j) m.constraint_matrix(i, j) = constraints(i, j);
  }
  for (auto* v : {&m.b, &m.lo, &m.hi, &m.start, &m.solution}) v->setlength(n_);
  for (auto* v : {&m.c_lo, &m.c_hi}) v->setlength(r_);
  // the variables are scaled by the caller (accelerations over their limits are O(1))
  alglib::real_1d_array scale;
  scale.setlength(n_);
  for (int i = 0; i < n_; ++i) scale[i] = 1.0;
  alglib::minqpsetscale(m.state, scale);
  switch (algorithm_) {
    case QpAlgorithm::kActiveSet: PWSIM_DEMAND(false && "AlglibQp is one of minqp's algorithms"); break;
    case QpAlgorithm::kBleic: alglib::minqpsetalgobleic(m.state, 0.0, 0.0, tolerance, 200); break;
    case QpAlgorithm::kDenseAul: alglib::minqpsetalgodenseaul(m.state, tolerance, 1e4, 10); break;
    case QpAlgorithm::kDenseIpm: alglib::minqpsetalgodenseipm(m.state, tolerance); break;
  }
}

AlglibQp::~AlglibQp() = default;

void AlglibQp::SetConstraintMatrix(const Eigen::MatrixXd& constraints) {
  PWSIM_DEMAND(constraints.rows() == r_ && constraints.cols() == n_);
  for (int i = 0; i < r_; ++i) {
    for (int j = 0; j < n_; ++j) impl_->constraint_matrix(i, j) = constraints(i, j);
  }
}

QpStatus AlglibQp::Solve(const Eigen::VectorXd& b, const Eigen::VectorXd& lo,
                         const Eigen::VectorXd& hi, const Eigen::VectorXd& c_lo,
                         const Eigen::VectorXd& c_hi, Eigen::VectorXd& z) {
  PWSIM_DEMAND(b.size() == n_ && lo.size() == n_ && hi.size() == n_ && z.size() == n_);
  PWSIM_DEMAND(c_lo.size() == r_ && c_hi.size() == r_);
  Impl& m = *impl_;
  QpStatus status;
  try {
    Fill(m.b, b);
    FillBound(m.lo, lo);
    FillBound(m.hi, hi);
    FillBound(m.c_lo, c_lo);
    FillBound(m.c_hi, c_hi);
    for (int i = 0; i < n_; ++i) m.start[i] = std::clamp(z[i], lo[i], hi[i]);
    alglib::minqpsetlinearterm(m.state, m.b);
    alglib::minqpsetbc(m.state, m.lo, m.hi);
    alglib::minqpsetlc2dense(m.state, m.constraint_matrix, m.c_lo, m.c_hi, r_);
    alglib::minqpsetstartingpoint(m.state, m.start);
    alglib::minqpoptimize(m.state);
    alglib::minqpresults(m.state, m.solution, m.report);
  } catch (const alglib::ap_error&) {
    return status;  // ok = false: the caller falls back
  }
  status.termination = static_cast<int>(m.report.terminationtype);
  status.iterations = static_cast<int>(m.report.inneriterationscount + m.report.outeriterationscount);
  status.ok = m.report.terminationtype > 0;
  if (status.ok) {
    for (int i = 0; i < n_; ++i) {
      if (!std::isfinite(m.solution[i])) {
        status.ok = false;
        return status;
      }
    }
    for (int i = 0; i < n_; ++i) z[i] = m.solution[i];
  }
  return status;
}

}  // namespace pwsim::mca
