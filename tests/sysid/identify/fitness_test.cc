#include "sysid/identify/fitness.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace pwsim {
namespace {

TEST(FitPercentTest, HandComputedCase) {
  // y = [1, 2, 3, 4], mean 2.5, ||y - mean|| = sqrt(2.25 + 0.25 + 0.25 + 2.25) = sqrt(5).
  // ŷ = [1, 2, 3, 3]: ||y - ŷ|| = 1. fit = 100 (1 - 1/sqrt(5)) = 55.27864045...
  const std::vector<double> y{1.0, 2.0, 3.0, 4.0};
  const std::vector<double> model{1.0, 2.0, 3.0, 3.0};
  EXPECT_NEAR(FitPercent(y, model), 55.27864045000421, 1e-12);
}

TEST(FitPercentTest, PerfectMeanAndScaledModels) {
  const std::vector<double> y{0.0, 1.0, 0.0, -1.0};
  EXPECT_DOUBLE_EQ(FitPercent(y, y), 100.0);
  const std::vector<double> mean(4, 0.0);
  EXPECT_DOUBLE_EQ(FitPercent(y, mean), 0.0);
  // A zero-mean shape at gain g scores 100 (1 - |1 - g|): the 57.6 % of the paper ≈ g 0.58.
  std::vector<double> scaled;
  for (double v : y) scaled.push_back(0.576 * v);
  EXPECT_NEAR(FitPercent(y, scaled), 57.6, 1e-9);
  std::vector<double> opposite;
  for (double v : y) opposite.push_back(-v);
  EXPECT_DOUBLE_EQ(FitPercent(y, opposite), -100.0);
}

TEST(FitPercentTest, ConstantMeasurement) {
  const std::vector<double> y{2.0, 2.0};
  EXPECT_DOUBLE_EQ(FitPercent(y, y), 100.0);
  EXPECT_TRUE(std::isinf(FitPercent(y, std::vector<double>{2.0, 2.5})));
}

TEST(PooledFitTest, PoolsNormsAcrossRecords) {
  PooledFit pooled;
  EXPECT_TRUE(std::isnan(pooled.Percent()));
  // Record 1: error² 1, deviation² 5. Record 2 (each centred on its own mean 10):
  // y = [9, 11], ŷ = [9, 12]: error² 1, deviation² 2. Pooled: 100 (1 - sqrt(2)/sqrt(7)).
  pooled.Add(std::vector<double>{1, 2, 3, 4}, std::vector<double>{1, 2, 3, 3});
  pooled.Add(std::vector<double>{9, 11}, std::vector<double>{9, 12});
  EXPECT_NEAR(pooled.Percent(), 100.0 * (1.0 - std::sqrt(2.0) / std::sqrt(7.0)), 1e-12);
}

}  // namespace
}  // namespace pwsim
