#pragma once
// A strictly convex QP in the benchmark form of outside test sets (docs/qp.md):
//
//   minimise ½ xᵀ P x + qᵀ x   subject to   G x ≤ h        (P n×n positive definite, G m×n)
//
// read from a JSON file {"name", "P": [[...]], "q": [...], "G": [[...]], "h": [...]} (row-major
// nested lists; the MPC set in ../shared/data/qp-mpc/), solved with pwsim's dual active set
// (mca/qp_active_set.h: A = G, a_lo = −∞, a_hi = h, no bounds), and checked by its KKT
// residuals; written as plain text for the reference solver (scripts/qp-quadprog.R).
//
//   QpProblem p = ReadQpProblemJson("LIPMWALK0.json");   // @throws InputError
//   QpSolution s = SolveQpProblem(p);
//   QpResiduals r = KktResiduals(p, s.x, s.multipliers);
// Off the real-time path (allocates, reads files).

#include <Eigen/Dense>

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "mca/qp_alglib.h"  // QpStatus

namespace pwsim::mca {

struct QpProblem {
  std::string name;
  Eigen::MatrixXd p;   ///< n×n, symmetric positive definite
  Eigen::VectorXd q;   ///< n
  Eigen::MatrixXd g;   ///< m×n
  Eigen::VectorXd h;   ///< m
  int variables() const { return static_cast<int>(q.size()); }
  int constraints() const { return static_cast<int>(h.size()); }
  double Objective(const Eigen::VectorXd& x) const { return 0.5 * x.dot(p * x) + q.dot(x); }
};

/// @throws InputError naming the file, the line and the field (missing, not a number, sizes
/// that disagree, P not symmetric).
QpProblem ReadQpProblemJson(const std::filesystem::path& file);
/// The *.json files of a directory, sorted by name. @throws InputError when it is not a directory.
std::vector<std::filesystem::path> QpProblemFiles(const std::filesystem::path& dir);

/// scripts/qp-quadprog.R's input: the header line "pwsim-qp-text/1" once, then per problem
/// "problem NAME n m" and one line each of P (row-major), q, G (row-major), h, every number
/// with 17 significant digits (a double read back is the same double).
void WriteQpTextHeader(std::ostream& out);
void WriteQpProblemText(const QpProblem& problem, std::ostream& out);

struct QpSolution {
  QpStatus status;
  Eigen::VectorXd x;            ///< n
  Eigen::VectorXd multipliers;  ///< m, λ ≥ 0 with P x + q + Gᵀ λ = 0 at the optimum
};

/// A cold solve (ActiveSetQp built, H factorised, solved once).
QpSolution SolveQpProblem(const QpProblem& problem);

/// The KKT conditions of a candidate (x, λ), each as an absolute residual and scaled:
struct QpResiduals {
  double primal{0.0};        ///< max(0, max_i (G x − h)_i)
  double dual{0.0};          ///< max(0, −min_i λ_i)
  double stationarity{0.0};  ///< ‖P x + q + Gᵀ λ‖∞
  double complementarity{0.0};  ///< max_i λ_i |(G x − h)_i|
  /// stationarity / max(‖P x‖∞, ‖q‖∞, ‖Gᵀ λ‖∞): relative to the largest term it sums
  double stationarity_relative{0.0};
  /// max_i max(0, (G x − h)_i) / (|h_i| + Σ_j |G_ij x_j|): relative to the sizes the rounding
  /// of row i scales with
  double primal_relative{0.0};
};
QpResiduals KktResiduals(const QpProblem& problem, const Eigen::VectorXd& x,
                         const Eigen::VectorXd& multipliers);
/// Only the constraint violation max(0, max_i (G x − h)_i) (a reference solver's x, no λ).
double ConstraintViolation(const QpProblem& problem, const Eigen::VectorXd& x);

}  // namespace pwsim::mca
