// The dual active set (mca/qp_active_set.h) on QPs nobody here wrote: the MPC problems of the
// public benchmark qpsolvers/mpc_qpbenchmark in ../shared/data/qp-mpc/ (LIPMWALK 16×32,
// WHLIPBAL 50×100; docs/qp.md). The reference is R's quadprog (Goldfarb–Idnani, Turlach's
// Fortran), run as a subprocess on the same numbers (scripts/qp-quadprog.R); where R or its
// quadprog package is absent, scipy's NNLS on the least-distance form (scripts/qp-scipy.py);
// where neither runs, only the KKT certificate below (the test says which one it used). The
// scipy path is also run on its own, so that the fallback is known to work where R is present.
//
// Tolerances (u = 1.1e-16; both solvers stop at a vertex of the same active set, so they
// differ by rounding only; P positive definite, so the minimiser is unique):
//   KKT certificate of pwsim's (x, λ): λ ≥ −1e-12 max λ (the method keeps the dual feasible
//     up to its blocking threshold); ‖P x + q + Gᵀ λ‖∞ ≤ 1e-9 of its largest term; (G x − h)₊
//     ≤ 1e-9 of the problem's scale (ε_f of the solver); |G_i x − h_i| ≤ 1e-9 (|h_i| +
//     |G_i||x|) where λ_i > 0. Together they certify optimality whoever computed x.
//   against the reference: |f − f_ref| ≤ 1e-9 max(1, |f_ref|) and ‖x − x_ref‖∞ ≤ 1e-7
//     (1 + ‖x_ref‖∞). Rounding moves x by about κ(P) u ‖x‖ (κ ≤ 8.1e4 here: 1e-11, measured
//     ≤ 1.4e-11) and f only to second order; the tolerances leave three to four decades for
//     problems of the same families that are worse conditioned.
//   constraint violation no larger than the reference's plus 1e-9 of the problem's scale.
// Also: the result does not change when the problem is rescaled (P, q by 1e8; G, h by 1e-8),
// and a malformed file is rejected naming file, line and field.

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "engine/input_error.h"
#include "mca/qp_problem.h"

namespace pwsim::mca {
namespace {

namespace fs = std::filesystem;

/// PWSIM_QP_MPC_DIR in the environment, else the copy beside the source tree (CMake).
fs::path DataDir() {
  if (const char* env = std::getenv("PWSIM_QP_MPC_DIR"); env != nullptr && *env != '\0') return env;
  return fs::path(PWSIM_QP_MPC_DIR).lexically_normal();
}

int RunShell(const std::string& command) {
  const int status = std::system(command.c_str());
  if (status == -1) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string Quote(const fs::path& path) { return "'" + path.string() + "'"; }

struct Reference {
  std::string status;
  double objective{NAN};
  Eigen::VectorXd x;
};

/// Reads the line format of scripts/qp-quadprog.R (and qp-scipy.py).
std::map<std::string, Reference> ReadReference(const fs::path& file) {
  std::map<std::string, Reference> out;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string name, status, objective, seconds, iterations, value;
    fields >> name >> status >> objective >> seconds >> iterations;
    Reference r;
    r.status = status;
    if (status == "optimal") r.objective = std::stod(objective);
    std::vector<double> x;
    while (fields >> value) x.push_back(value == "NA" ? NAN : std::stod(value));
    r.x = Eigen::Map<Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
    out[name] = r;
  }
  return out;
}

class QpBenchmarkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const fs::path dir = DataDir();
    ASSERT_TRUE(fs::is_directory(dir))
        << "the MPC QP benchmark is missing: expected the directory " << dir
        << " (../shared/data/qp-mpc beside the source tree, or set PWSIM_QP_MPC_DIR)";
    for (const fs::path& file : QpProblemFiles(dir)) problems_.push_back(ReadQpProblemJson(file));
    ASSERT_GE(problems_.size(), 2u) << "no *.json problems in " << dir;
    char name[] = "/tmp/pwsim_qp_benchmark_XXXXXX";
    ASSERT_NE(mkdtemp(name), nullptr);
    tmp_ = name;
  }
  void TearDown() override {
    if (!tmp_.empty()) fs::remove_all(tmp_);
  }

  /// Runs the reference on every problem; fills reference_ and names it in used_. R's quadprog
  /// first unless `scipy_only`; empty when neither runs here.
  void RunReference(bool scipy_only = false) {
    const fs::path in = tmp_ / "problems.txt", out = tmp_ / "reference.txt";
    {
      std::ofstream text(in);
      WriteQpTextHeader(text);
      for (const QpProblem& p : problems_) WriteQpProblemText(p, text);
    }
    const fs::path scripts = fs::path(PWSIM_SOURCE_DIR) / "scripts";
    if (!scipy_only &&
        RunShell("Rscript -e 'suppressPackageStartupMessages(library(quadprog))' > /dev/null 2>&1") == 0) {
      ASSERT_EQ(RunShell("Rscript " + Quote(scripts / "qp-quadprog.R") + " " + Quote(in) + " " + Quote(out)), 0);
      used_ = "R quadprog (scripts/qp-quadprog.R)";
    } else {
      for (const char* python : {"/usr/bin/python3", "python3"}) {
        if (RunShell(std::string(python) + " -c 'import scipy.optimize' > /dev/null 2>&1") != 0) continue;
        ASSERT_EQ(RunShell(std::string(python) + " " + Quote(scripts / "qp-scipy.py") + " " + Quote(in) + " " + Quote(out)), 0);
        used_ = scipy_only ? "scipy NNLS least-distance form (scripts/qp-scipy.py)"
                           : "scipy NNLS least-distance form (scripts/qp-scipy.py; R's quadprog not found)";
        break;
      }
    }
    if (!used_.empty()) reference_ = ReadReference(out);
  }

  /// Checks every problem against reference_ (when there is one) and by its KKT certificate.
  void CheckAll() {
    std::cout << "QP benchmark: " << problems_.size() << " problems from " << DataDir().string() << "; reference: "
              << (used_.empty() ? "none (neither Rscript with quadprog nor python3 with scipy): KKT certificate only"
                                : used_)
              << "\n";
    if (!used_.empty()) RecordProperty("reference", used_);
    double worst_objective = 0.0, worst_x = 0.0, worst_stationarity = 0.0;
    for (const QpProblem& p : problems_) {
      SCOPED_TRACE(p.name);
      const QpSolution s = SolveQpProblem(p);
      ASSERT_TRUE(s.status.ok) << "termination " << s.status.termination;
      const QpResiduals kkt = KktResiduals(p, s.x, s.multipliers);
      EXPECT_LE(kkt.dual, 1e-12 * s.multipliers.maxCoeff());
      EXPECT_LE(kkt.stationarity_relative, 1e-9);
      EXPECT_LE(kkt.primal, ViolationAllowance(p, s.x));
      const Eigen::VectorXd gap = p.g * s.x - p.h, row_scale = p.h.cwiseAbs() + p.g.cwiseAbs() * s.x.cwiseAbs();
      for (int i = 0; i < p.constraints(); ++i) {
        if (s.multipliers(i) > 0.0) {
          EXPECT_LE(std::abs(gap(i)), 1e-9 * row_scale(i)) << "complementarity of row " << i;
        }
      }
      worst_stationarity = std::max(worst_stationarity, kkt.stationarity_relative);
      if (used_.empty()) continue;
      const auto it = reference_.find(p.name);
      ASSERT_NE(it, reference_.end()) << "the reference wrote no line for it";
      const Reference& r = it->second;
      ASSERT_EQ(r.status, "optimal");
      ASSERT_EQ(r.x.size(), p.variables());
      const double f = p.Objective(s.x), f_ref = p.Objective(r.x);
      const double objective_error = std::abs(f - f_ref) / std::max(1.0, std::abs(f_ref));
      const double x_error = (s.x - r.x).lpNorm<Eigen::Infinity>() / (1.0 + r.x.lpNorm<Eigen::Infinity>());
      EXPECT_LE(objective_error, 1e-9) << "f " << f << " reference " << f_ref;
      EXPECT_LE(x_error, 1e-7);
      EXPECT_LE(kkt.primal, ConstraintViolation(p, r.x) + ViolationAllowance(p, s.x));
      worst_objective = std::max(worst_objective, objective_error);
      worst_x = std::max(worst_x, x_error);
    }
    std::cout << "QP benchmark: worst relative objective difference " << worst_objective
              << ", worst relative x difference " << worst_x << ", worst relative stationarity " << worst_stationarity
              << "\n";
  }

  /// 1e-9 of the problem's scale: the largest |h_i| + Σ_j |G_ij x_j|.
  static double ViolationAllowance(const QpProblem& p, const Eigen::VectorXd& x) {
    return 1e-9 * (p.h.cwiseAbs() + p.g.cwiseAbs() * x.cwiseAbs()).maxCoeff();
  }

  std::vector<QpProblem> problems_;
  fs::path tmp_;
  std::string used_;
  std::map<std::string, Reference> reference_;
};

// Tests that every problem is solved, with a KKT certificate, to the reference's objective,
// solution and constraint violation (R's quadprog where it runs).
TEST_F(QpBenchmarkTest, SolvesEveryProblemAsTheReferenceDoes) {
  RunReference();
  CheckAll();
}

// Tests the same against the fallback reference, scipy's NNLS on the least-distance form, so
// that the path taken where R is absent is known to work (skipped only without scipy).
TEST_F(QpBenchmarkTest, SolvesEveryProblemAsScipyDoes) {
  RunReference(/*scipy_only=*/true);
  if (used_.empty()) GTEST_SKIP() << "python3 with scipy not found (Debian python3-scipy)";
  CheckAll();
}

// Tests that the result does not depend on the units: P, q scaled by 1e8 (the same minimiser)
// and G, h by 1e-8 (the same feasible set) give the same x, and every one carries its KKT
// certificate (absolute thresholds in the solver would stop or fail here).
TEST_F(QpBenchmarkTest, ResultDoesNotDependOnScaling) {
  for (const QpProblem& p : problems_) {
    SCOPED_TRACE(p.name);
    const QpSolution base = SolveQpProblem(p);
    ASSERT_TRUE(base.status.ok);
    for (const auto& [objective_scale, constraint_scale] : {std::pair{1e8, 1.0}, std::pair{1.0, 1e-8}, std::pair{1e8, 1e-8}}) {
      QpProblem scaled = p;
      scaled.p *= objective_scale;
      scaled.q *= objective_scale;
      scaled.g *= constraint_scale;
      scaled.h *= constraint_scale;
      const QpSolution s = SolveQpProblem(scaled);
      ASSERT_TRUE(s.status.ok) << objective_scale << " " << constraint_scale;
      EXPECT_LE((s.x - base.x).lpNorm<Eigen::Infinity>(), 1e-9 * (1.0 + base.x.lpNorm<Eigen::Infinity>()));
      const QpResiduals kkt = KktResiduals(scaled, s.x, s.multipliers);
      EXPECT_LE(kkt.stationarity_relative, 1e-9);
      EXPECT_LE(kkt.primal, ViolationAllowance(scaled, s.x));
    }
  }
}

// Tests that a malformed problem file is rejected naming the file, the line and the field.
TEST_F(QpBenchmarkTest, MalformedFileNamesFileLineAndField) {
  const fs::path file = tmp_ / "bad.json";
  {
    std::ofstream out(file);
    out << "{\n  \"name\": \"bad\",\n  \"P\": [[1, 0], [0, 1]],\n  \"q\": [1, 2],\n  \"G\": [[1, 0, 3]],\n  \"h\": [1]\n}\n";
  }
  try {
    ReadQpProblemJson(file);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_EQ(e.line(), 5);
    EXPECT_EQ(e.field(), "G");
    EXPECT_NE(std::string(e.what()).find("2 numbers"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pwsim::mca
