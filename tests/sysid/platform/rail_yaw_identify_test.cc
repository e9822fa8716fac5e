// The seed-001 rail + yaw regressor (sysid/platform/idim.h, RailYawModel) identifies the
// inertial parameters θ1..θ4 and both joints' friction jointly from a recording of an
// independent truth (tests/sysid/platform/truth_rail_yaw.*).
#include <gtest/gtest.h>

#include <cmath>

#include "sysid/platform/idim.h"
#include "tests/sysid/platform/truth_rail_yaw.h"

namespace pwsim::sysid::platform {
namespace {

TEST(RailYawIdentify, RecoversThetaAndFrictionJointly) {
  const test::RailYawTruth truth;
  const AxisRecording rec = test::SimulateRailYaw(truth);
  IdimOptions o;
  o.end_border_samples = 49;  // the truth recording ends in motion
  const PlatformFit fit = IdentifyPlatform({rec}, {}, "", o);
  ASSERT_EQ(fit.model.name, "rail-yaw");
  ASSERT_EQ(fit.ls.theta.size(), 10);
  const double expected[10] = {truth.Theta1(), truth.Theta2(), truth.Theta3(), truth.Theta4(),
                               truth.fv1,      truth.fc1,      0.0,            truth.fv2,
                               truth.fc2,      0.0};
  // Within 1 % (θ4 = −m2 yG2 = 3.8 kg m and the offsets: 0.2 kg m, 0.2 N).
  for (int i = 0; i < 10; ++i) {
    const double tol = (i == 3 || i == 6 || i == 9) ? 0.2 : 0.01 * std::abs(expected[i]);
    EXPECT_NEAR(fit.ls.theta(i), expected[i], tol) << fit.model.params[static_cast<std::size_t>(i)].name;
  }
  EXPECT_LT(fit.ls.relative_error_pct, 0.5);
}

TEST(RailYawIdentify, PaperTypoRegressorFitsWorse) {
  // Eq. (20) of the seed prints C1(1,3) as q̈2 q̈1; the derivation gives q2² q̈1. Replacing the
  // column by the printed one must make the fit measurably worse on the same data.
  const test::RailYawTruth truth;
  const AxisRecording rec = test::SimulateRailYaw(truth);
  IdimOptions o;
  o.end_border_samples = 49;
  const ProcessedRecording p = Preprocess(rec, o);
  LinearModel derived = RailYawModel(p);
  LinearModel printed = derived;
  printed.columns = [derived](const ProcessedRecording& r, std::size_t j, Eigen::MatrixXd& x) {
    derived.columns(r, j, x);
    if (r.joints[j].kind == JointKind::kRevolute)
      for (Eigen::Index i = 0; i < x.rows(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        const double qdd1 = r.joints[0].qdd[k], qdd2 = r.joints[1].qdd[k];
        const double q2 = r.joints[1].q[k], qd1 = r.joints[0].qd[k], qd2 = r.joints[1].qd[k];
        x(i, 2) = qdd2 * qdd1 + 2.0 * q2 * qd1 * qd2;
      }
  };
  const LsFit good = SolveLeastSquares(BuildRegression(p, derived, o), 2);
  const LsFit bad = SolveLeastSquares(BuildRegression(p, printed, o), 2);
  EXPECT_GT(bad.relative_error_pct, 1.5 * good.relative_error_pct);
}

}  // namespace
}  // namespace pwsim::sysid::platform
