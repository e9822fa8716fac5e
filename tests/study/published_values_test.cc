// Published reference values (each checked against R 4.2.2 before use; see docs/study.md):
// - R's ?wilcox.test examples (Hollander & Wolfe 1973, depression scale, paired; and the
//   two-sample example): the help page prints one-sided p-values (alternative = "greater"),
//   V = 40, p = 0.01953 and W = 35, p = 0.1272; the two-sided p is twice that.
// - scipy's TestShapiro oracle (scipy/stats/tests/test_morestats.py): x1 gives W = 0.90047300,
//   p = 0.04208975 (scipy's single precision), x2 gives W = 0.959027, p = 0.5246.
// - Seed 000's study (section V), the rating counts reconstructed in docs/study.md: the
//   unpaired rank-sum test gives the paper's W = 180, p = 0.5045.

#include <gtest/gtest.h>

#include <vector>

#include "study/rank_sum.h"
#include "study/shapiro_wilk.h"
#include "study/signed_rank.h"

namespace pwsim::study {
namespace {

TEST(PublishedValues, WilcoxHelpPagePairedExample) {
  const std::vector<double> x{1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30};
  const std::vector<double> y{0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29};
  const SignedRank s = SignedRankTest(x, y);
  EXPECT_EQ(s.v, 40.0);
  EXPECT_TRUE(s.p_is_exact);
  EXPECT_NEAR(s.p / 2.0, 0.01953, 5e-6);  // one-sided, as printed
  EXPECT_EQ(s.method, "Wilcoxon signed rank exact test");
}

TEST(PublishedValues, WilcoxHelpPageTwoSampleExample) {
  const std::vector<double> x{0.80, 0.83, 1.89, 1.04, 1.45, 1.38, 1.91, 1.64, 0.73, 1.46};
  const std::vector<double> y{1.15, 0.88, 0.90, 0.74, 1.21};
  const RankSum u = RankSumTest(x, y);
  EXPECT_EQ(u.w, 35.0);
  EXPECT_TRUE(u.p_is_exact);
  EXPECT_NEAR(u.p / 2.0, 0.1272, 5e-5);
}

TEST(PublishedValues, ScipyShapiroOracle) {
  const std::vector<double> x1{0.11, 7.87, 4.61, 10.14, 7.95, 3.14, 0.46, 4.43, 0.21, 4.75,
                               0.71, 1.52, 3.24, 0.93, 0.42, 4.97, 9.53, 4.55, 0.47, 6.66};
  const ShapiroWilk a = ShapiroWilkTest(x1);
  EXPECT_NEAR(a.w, 0.90047299861907959, 1e-6);
  EXPECT_NEAR(a.p, 0.042089745402336121, 1e-6);
  const std::vector<double> x2{1.36, 1.14, 2.92, 2.55, 1.46, 1.06, 5.27, -1.11, 3.48, 1.10,
                               0.88, -0.51, 1.46, 0.52, 6.20, 1.69, 0.08, 3.67, 2.81, 3.49};
  const ShapiroWilk b = ShapiroWilkTest(x2);
  EXPECT_NEAR(b.w, 0.959027, 1e-6);
  EXPECT_NEAR(b.p, 0.5246, 5e-4);
}

std::vector<double> Counts(int ones, int twos, int threes) {
  std::vector<double> v;
  v.insert(v.end(), static_cast<std::size_t>(ones), 1.0);
  v.insert(v.end(), static_cast<std::size_t>(twos), 2.0);
  v.insert(v.end(), static_cast<std::size_t>(threes), 3.0);
  return v;
}

TEST(PublishedValues, SeedPaperRankSumGivesW180) {
  const std::vector<double> tm = Counts(3, 14, 1);
  const std::vector<double> tr = Counts(6, 10, 2);
  const RankSum u = RankSumTest(tm, tr);
  EXPECT_EQ(u.w, 180.0);
  EXPECT_NEAR(u.p, 0.5045, 5e-5);
  EXPECT_FALSE(u.p_is_exact);  // ties: normal approximation
  // A signed-rank statistic of 18 pairs cannot reach 180, whatever the pairing.
  const SignedRank s = SignedRankTest(tm, tr);
  EXPECT_LE(s.v + s.r_minus, 18.0 * 19.0 / 2.0);
  // Shapiro-Wilk: "not normally distributed"
  EXPECT_NEAR(ShapiroWilkTest(tm).w, 0.64201, 5e-6);
  EXPECT_LT(ShapiroWilkTest(tm).p, 0.001);
  EXPECT_NEAR(ShapiroWilkTest(tr).w, 0.78623, 5e-6);
  EXPECT_LT(ShapiroWilkTest(tr).p, 0.05);
}

TEST(ShapiroWilk, RejectsTooFewAndConstant) {
  EXPECT_THROW(ShapiroWilkTest(std::vector<double>{1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(ShapiroWilkTest(std::vector<double>{2.0, 2.0, 2.0, 2.0}), std::invalid_argument);
}

TEST(ShapiroWilk, ThreeValuesExactFormula) {
  // n = 3 (p = (6/pi)(asin sqrt W - pi/3), exact): equally spaced values give W = 1, p = 1
  const ShapiroWilk even = ShapiroWilkTest(std::vector<double>{1.0, 2.0, 3.0});
  EXPECT_NEAR(even.w, 1.0, 1e-12);
  EXPECT_NEAR(even.p, 1.0, 1e-12);
  // the most extreme n = 3 shape (two equal values) is W = 3/4, p = 0
  const ShapiroWilk worst = ShapiroWilkTest(std::vector<double>{1.0, 1.0, 2.0});
  EXPECT_NEAR(worst.w, 0.75, 1e-12);
  EXPECT_NEAR(worst.p, 0.0, 1e-6);
}

TEST(SignedRank, AllZeroDifferencesGivePOne) {
  const std::vector<double> x{1, 2, 3};
  const SignedRank s = SignedRankTest(x, x);
  EXPECT_EQ(s.n_nonzero, 0u);
  EXPECT_EQ(s.p, 1.0);
}

}  // namespace
}  // namespace pwsim::study
