#pragma once
// A dense strictly convex QP by the dual active-set method of Goldfarb & Idnani (1983):
//
//   minimise ½ zᵀ H z + bᵀ z   subject to   n_iᵀ z + c_i ≥ 0,  i = 1..r
//
// H (n×n, positive definite) and the constraint normals n_i are fixed at construction (the MPC's
// condensed model, mca/mpc.h); b and c_i change every solve. Two-sided rows and bounds are
// given as lo ≤ A z ≤ hi (±inf = absent) and split into one-sided ones here.
// The method starts at the unconstrained minimum z = −H⁻¹ b (dual feasible) and adds violated
// constraints one at a time, dropping one whose multiplier would turn negative; each step keeps
// J = Q·L⁻ᵀ (H = L Lᵀ, Q from the QR factorisation N* = Q [R; 0] of the active normals in the
// L⁻¹ metric) and R up to date by Givens rotations, O(n²) per step:
//   primal direction  s = J₂ J₂ᵀ n_p,  dual direction  r = R⁻¹ J₁ᵀ n_p
//   full step t₂ = −(n_pᵀ z + c_p)/(sᵀ n_p),  partial step t₁ = min_{r_j>0} u_j / r_j.
// Warm start: among the violated constraints the previous solution's active ones are added
// first (any violated constraint may be chosen, so the result is the same optimum).
// Deterministic; Solve() allocates nothing (all storage is sized at construction).
// The maths is checked against ALGLIB's minqp on random and MPC problems (tests/mca/).
//
//   ActiveSetQp qp(hessian, rows);   // rows: the constraint matrix A
//   QpStatus s = qp.Solve(b, z_lo, z_hi, a_lo, a_hi, z);

#include <Eigen/Dense>

#include <algorithm>
#include <vector>

#include "mca/qp_alglib.h"  // QpStatus

namespace pwsim::mca {

class ActiveSetQp {
 public:
  /// @pre hessian positive definite; constraints.cols() == hessian.rows().
  ActiveSetQp(const Eigen::MatrixXd& hessian, const Eigen::MatrixXd& constraints);

  /// z_lo ≤ z ≤ z_hi and a_lo ≤ A z ≤ a_hi; z: solution on success (the warm start is the
  /// previous active set, kept inside). termination 1 = optimal, −3 = infeasible,
  /// −4 = iteration limit.
  QpStatus Solve(const Eigen::VectorXd& b, const Eigen::VectorXd& z_lo, const Eigen::VectorXd& z_hi,
                 const Eigen::VectorXd& a_lo, const Eigen::VectorXd& a_hi, Eigen::VectorXd& z);

  /// Forgets the previous active set (the next solve starts cold).
  void ResetWarmStart() { std::fill(was_active_.begin(), was_active_.end(), 0); }
  int variables() const { return n_; }

 private:
  bool AddConstraint(int q);
  void DropConstraint(int position);

  int n_;
  int rows_;
  Eigen::MatrixXd normals_;     ///< one-sided normals, 2·(rows + n) × n (sign folded in)
  Eigen::MatrixXd j0_;          ///< L⁻ᵀ (the start of J)
  Eigen::LLT<Eigen::MatrixXd> llt_;
  // per solve
  Eigen::VectorXd offset_;      ///< c_i per one-sided constraint (+inf: absent)
  Eigen::VectorXd slack_;       ///< n_iᵀ z + c_i
  Eigen::MatrixXd j_, r_;
  Eigen::VectorXd d_, step_, dual_, u_, np_, nz_;
  std::vector<int> active_;     ///< indices of active one-sided constraints
  std::vector<char> is_active_;
  std::vector<char> was_active_;
  int q_{0};
};

}  // namespace pwsim::mca
