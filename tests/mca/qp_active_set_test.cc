// The dual active-set QP against ALGLIB's minqp (a maintained solver, the reference): random
// strictly convex QPs with box and two-sided linear constraints, and the MPC's own QP.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mca/mpc.h"
#include "mca/qp_active_set.h"
#include "mca/qp_alglib.h"

namespace pwsim::mca {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double Objective(const Eigen::MatrixXd& h, const Eigen::VectorXd& b, const Eigen::VectorXd& z) {
  return 0.5 * z.dot(h * z) + b.dot(z);
}

struct RandomQp {
  Eigen::MatrixXd h, a;
  Eigen::VectorXd b, lo, hi, a_lo, a_hi;
};

/// A QP whose feasible set contains a known point z0 (constraints built around it).
RandomQp MakeRandomQp(std::mt19937& rng, int n, int rows) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.05, 1.0);
  RandomQp qp;
  const Eigen::MatrixXd m = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return normal(rng); });
  qp.h = m * m.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
  qp.b = Eigen::VectorXd::NullaryExpr(n, [&] { return 5.0 * normal(rng); });
  const Eigen::VectorXd z0 = Eigen::VectorXd::NullaryExpr(n, [&] { return 0.3 * normal(rng); });
  qp.lo = z0.array() - Eigen::VectorXd::NullaryExpr(n, [&] { return uniform(rng); }).array();
  qp.hi = z0.array() + Eigen::VectorXd::NullaryExpr(n, [&] { return uniform(rng); }).array();
  qp.a = Eigen::MatrixXd::NullaryExpr(rows, n, [&] { return normal(rng); });
  const Eigen::VectorXd az0 = qp.a * z0;
  qp.a_lo.resize(rows);
  qp.a_hi.resize(rows);
  for (int i = 0; i < rows; ++i) {
    qp.a_lo[i] = i % 3 == 2 ? -kInf : az0[i] - uniform(rng);
    qp.a_hi[i] = i % 3 == 1 ? kInf : az0[i] + uniform(rng);
  }
  return qp;
}

// Tests that the active-set solution has ALGLIB's objective (dense IPM, 1e-12) and satisfies
// every constraint, on 40 random QPs of 20 variables and 30 two-sided rows.
TEST(ActiveSetQpTest, MatchesAlglibOnRandomProblems) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const RandomQp qp = MakeRandomQp(rng, 20, 30);
    ActiveSetQp dut(qp.h, qp.a);
    AlglibQp reference(QpAlgorithm::kDenseIpm, qp.h, qp.a, 1e-12);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(20), z_ref = Eigen::VectorXd::Zero(20);
    const QpStatus s = dut.Solve(qp.b, qp.lo, qp.hi, qp.a_lo, qp.a_hi, z);
    const QpStatus s_ref = reference.Solve(qp.b, qp.lo, qp.hi, qp.a_lo, qp.a_hi, z_ref);
    ASSERT_TRUE(s.ok) << trial << " termination " << s.termination;
    ASSERT_TRUE(s_ref.ok) << trial;
    const double f = Objective(qp.h, qp.b, z), f_ref = Objective(qp.h, qp.b, z_ref);
    EXPECT_NEAR(f, f_ref, 1e-6 * (1.0 + std::abs(f_ref))) << trial;
    EXPECT_LT((z - z_ref).norm(), 1e-4 * (1.0 + z_ref.norm())) << trial;
    EXPECT_TRUE(((z - qp.lo).array() >= -1e-9).all());
    EXPECT_TRUE(((qp.hi - z).array() >= -1e-9).all());
    const Eigen::VectorXd az = qp.a * z;
    for (int i = 0; i < qp.a.rows(); ++i) {
      EXPECT_GE(az[i], qp.a_lo[i] - 1e-9);
      EXPECT_LE(az[i], qp.a_hi[i] + 1e-9);
    }
  }
}

// Tests that a second solve (warm: the previous active set tried first) gives the same optimum
// as a fresh solver, and that contradictory constraints are reported infeasible.
TEST(ActiveSetQpTest, WarmStartSameOptimumAndInfeasibleReported) {
  std::mt19937 rng(11);
  const RandomQp qp = MakeRandomQp(rng, 12, 16);
  ActiveSetQp warm(qp.h, qp.a);
  Eigen::VectorXd z(12);
  ASSERT_TRUE(warm.Solve(qp.b, qp.lo, qp.hi, qp.a_lo, qp.a_hi, z).ok);
  const Eigen::VectorXd b2 = qp.b * 0.9;
  Eigen::VectorXd z_warm(12), z_cold(12);
  ASSERT_TRUE(warm.Solve(b2, qp.lo, qp.hi, qp.a_lo, qp.a_hi, z_warm).ok);
  ActiveSetQp cold(qp.h, qp.a);
  ASSERT_TRUE(cold.Solve(b2, qp.lo, qp.hi, qp.a_lo, qp.a_hi, z_cold).ok);
  EXPECT_LT((z_warm - z_cold).norm(), 1e-9);

  Eigen::MatrixXd a(2, 2);
  a << 1, 1, 1, 1;
  Eigen::VectorXd lo(2), hi(2), a_lo(2), a_hi(2), b = Eigen::VectorXd::Zero(2), z2(2);
  lo << -1, -1;
  hi << 1, 1;
  a_lo << 1.5, -kInf;
  a_hi << kInf, 1.0;  // x + y >= 1.5 and x + y <= 1
  ActiveSetQp infeasible(Eigen::MatrixXd::Identity(2, 2), a);
  const QpStatus s = infeasible.Solve(b, lo, hi, a_lo, a_hi, z2);
  EXPECT_FALSE(s.ok);
}

// Tests the MPC's own QP (pw4dof, default weights, a vehicle accelerating and pitching):
// the controller's commands with the active set equal those with ALGLIB's dense IPM.
TEST(ActiveSetQpTest, MpcCommandsMatchAlglib) {
  MpcParams params;
  MpcParams reference_params = params;
  reference_params.solver = QpAlgorithm::kDenseIpm;
  MpcCueing dut(params, DefaultWashoutParams(), VestibularParams{}, MakePw4DofPlatform(), 1e-3);
  MpcCueing reference(reference_params, DefaultWashoutParams(), VestibularParams{}, MakePw4DofPlatform(), 1e-3);
  HeadMotion h;
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    h.fs[0] = k > 300 && k < 1300 ? 1.0 : 0.0;
    h.fs[2] = kGravity + (k > 800 && k < 900 ? 2.0 : 0.0);
    h.w[1] = k > 800 && k < 1000 ? -0.3 : 0.0;
    const McaCommand a = dut.Step(h);
    const McaCommand& b = reference.Step(h);
    for (int i = 0; i < kDofCount; ++i) worst = std::max(worst, std::abs(a.pose[static_cast<std::size_t>(i)] - b.pose[static_cast<std::size_t>(i)]));
  }
  EXPECT_EQ(dut.stats().fallbacks, 0);
  EXPECT_EQ(reference.stats().fallbacks, 0);
  // [m | rad]: IPM's tolerance 1e-6 on the accelerations, accumulated in closed loop over 2 s
  // (6.8e-5 measured with pw4dof's actuator rows, 1e-6 before them)
  EXPECT_LT(worst, 1e-4);
}

}  // namespace
}  // namespace pwsim::mca
