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
// first (any violated constraint may be chosen, so the result is the same optimum); otherwise
// the one farthest from its boundary, min_i (n_iᵀ z + c_i)/‖n_i‖ (a distance in z, so rows of
// different scales compete fairly).
// Numerics (every test is relative, so scaling H, b or a row with its bounds changes nothing):
//   violated      n_iᵀ z + c_i < −(ε_f (|c_i| + ‖n_i‖₁ ‖z‖∞) + ε_d c_max),  ε_f = 1e-9: the
//                 rounding of the slack, plus a few ulps ε_d = 1e-15 of the largest finite
//                 offset c_max for rows whose normal is (near) zero; a violated zero row = infeasible
//   dependent     ‖J₂ᵀ n_p‖ ≤ ε_l ‖Jᵀ n_p‖, ε_l = 1e-10: n_p (in the L⁻¹ metric) within 1e-10 rad
//                 of the span of the active normals; no full step is taken along it
//   blocking      r_j > ε_r ‖r‖∞, ε_r = 1e-12: entries of r at rounding level block nothing
// The slacks are recomputed from z before each constraint is chosen (no drift from updates).
// Deterministic; Solve() allocates nothing (all storage is sized at construction).
// The maths is checked against ALGLIB's minqp on random and MPC problems and against R's
// quadprog on an outside MPC benchmark (tests/mca/, docs/qp.md).
//
//   ActiveSetQp qp(hessian, rows);   // rows: the constraint matrix A
//   QpStatus s = qp.Solve(b, z_lo, z_hi, a_lo, a_hi, z);   // s.iterations: steps taken

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
  /// −4 = iteration limit. status.iterations: the steps taken (each adds or drops one
  /// constraint), the measure of the work (O(n²) each, plus O(r n) per constraint chosen).
  QpStatus Solve(const Eigen::VectorXd& b, const Eigen::VectorXd& z_lo, const Eigen::VectorXd& z_hi,
                 const Eigen::VectorXd& a_lo, const Eigen::VectorXd& a_hi, Eigen::VectorXd& z);

  /// After an optimal Solve: the signed multipliers y of the rows (size rows) and y_z of the
  /// bounds (size n) with  H z + b + Aᵀ y + y_z = 0;  y_i ≥ 0 where A_i z = a_hi_i, ≤ 0 where
  /// A_i z = a_lo_i, 0 on inactive rows (bounds alike). Allocates only to resize the outputs.
  void Multipliers(Eigen::VectorXd& rows, Eigen::VectorXd& bounds) const;

  /// Replaces the constraint matrix A (same size as at construction): the MPC's actuator rows,
  /// linearised about the pose of each solve (mca/mpc.h). H, its factorisation and the warm
  /// start are kept. No allocation.
  void SetConstraintMatrix(const Eigen::MatrixXd& constraints);

  /// Forgets the previous active set (the next solve starts cold).
  void ResetWarmStart() { std::fill(was_active_.begin(), was_active_.end(), 0); }
  int variables() const { return n_; }

 private:
  bool AddConstraint(int q, double min_pivot);
  void DropConstraint(int position);
  /// n_c of one-sided constraint c: 2i is a_lo_i ≤ A_i z (+A_i), 2i+1 is A_i z ≤ a_hi_i (−A_i),
  /// 2(rows+j) and 2(rows+j)+1 the bounds of z_j (±e_j).
  void Normal(int c, Eigen::VectorXd& normal) const;

  int n_;
  int rows_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> a_;  ///< A, rows × n
  Eigen::VectorXd row_norm1_;       ///< ‖A_i‖₁
  Eigen::VectorXd row_inv_norm2_;   ///< 1/‖A_i‖₂ (0 for a zero row)
  Eigen::MatrixXd j0_;          ///< L⁻ᵀ (the start of J)
  Eigen::LLT<Eigen::MatrixXd> llt_;
  // per solve
  Eigen::VectorXd offset_;      ///< c per one-sided constraint (+inf: absent)
  std::vector<int> present_rows_;    ///< rows with a finite a_lo or a_hi
  std::vector<int> present_bounds_;  ///< variables with a finite z_lo or z_hi
  Eigen::MatrixXd j_, r_;
  Eigen::VectorXd d_, step_, dual_, u_, np_;
  std::vector<int> active_;     ///< indices of active one-sided constraints
  std::vector<char> is_active_;
  std::vector<char> was_active_;
  int q_{0};
};

}  // namespace pwsim::mca
