#pragma once
// A dense convex QP with a constant Hessian and a constant constraint matrix, solved by ALGLIB's
// minqp (Debian's libalglib-dev 3.19):
//
//   minimise ½ zᵀ H z + bᵀ z   subject to   lo ≤ z ≤ hi,   c_lo ≤ C z ≤ c_hi
//
// H (n×n, positive definite) and C (r×n) are set once; each Solve() gets the linear term, the
// bounds (±inf allowed in c_lo, c_hi, and hi for slack variables) and a warm start.
// The MPC (mca/mpc.h) solves one such QP per control step. Three of minqp's algorithms handle
// general linear constraints, and all three can be chosen (docs/mca.md compares them):
//   kBleic     active set on the boundary (BLEIC), warm-started from the previous plan
//   kDenseAul  augmented Lagrangian on a dense problem (ignores the start point)
//   kDenseIpm  primal-dual interior point on a dense problem (ignores the start point)
// Deterministic (ALGLIB's serial core; no threads are started). The ALGLIB arrays are members,
// sized once; minqp itself may allocate while it solves.
//
//   AlglibQp qp(QpAlgorithm::kBleic, hessian, constraints);
//   QpStatus s = qp.Solve(b, lo, hi, c_lo, c_hi, z);   // z: warm start in, solution out

#include <Eigen/Dense>

#include <memory>
#include <string>
#include <string_view>

namespace pwsim::mca {

/// The MPC's QP solvers: pwsim's dual active set (mca/qp_active_set.h) or one of minqp's.
enum class QpAlgorithm { kActiveSet, kBleic, kDenseAul, kDenseIpm };
/// "active_set", "bleic", "dense_aul", "dense_ipm".
std::string_view QpAlgorithmName(QpAlgorithm algorithm);

struct QpStatus {
  bool ok{false};          ///< a solution within tolerance was returned
  int termination{0};      ///< ALGLIB's terminationtype (> 0 converged; -3 infeasible; ...)
  int iterations{0};
};

class AlglibQp {
 public:
  /// @pre hessian square and positive definite; constraints.cols() == hessian.rows();
  /// algorithm is not kActiveSet.
  /// `tolerance`: the stopping tolerance handed to minqp (the MPC uses 1e-6).
  AlglibQp(QpAlgorithm algorithm, const Eigen::MatrixXd& hessian, const Eigen::MatrixXd& constraints,
           double tolerance = 1e-6);
  ~AlglibQp();
  AlglibQp(const AlglibQp&) = delete;
  AlglibQp& operator=(const AlglibQp&) = delete;

  /// Solves with linear term b; z holds the warm start on entry and the solution on exit
  /// (unchanged when the solver fails).
  QpStatus Solve(const Eigen::VectorXd& b, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                 const Eigen::VectorXd& c_lo, const Eigen::VectorXd& c_hi, Eigen::VectorXd& z);

  /// Replaces the constraint matrix (same size as at construction). No allocation.
  void SetConstraintMatrix(const Eigen::MatrixXd& constraints);

  QpAlgorithm algorithm() const { return algorithm_; }
  int variables() const { return n_; }
  int constraints() const { return r_; }

 private:
  struct Impl;  // ALGLIB's types stay out of this header
  QpAlgorithm algorithm_;
  int n_;
  int r_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pwsim::mca
