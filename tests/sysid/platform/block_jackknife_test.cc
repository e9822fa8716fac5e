// The delete-one-block jackknife against closed forms: for the mean of B numbers its standard
// error is the textbook s/√B, and the bound uses Student's t (table value t_{0.95, 6} = 1.943,
// e.g. Abramowitz & Stegun table 26.10).
#include "sysid/platform/block_jackknife.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace pwsim::sysid::platform {
namespace {

TEST(BlockJackknife, MeanHasTheTextbookStandardError) {
  const std::vector<double> v{3.0, -1.0, 4.5, 2.0, 0.5, 6.0, 1.0};
  const int b = static_cast<int>(v.size());
  auto mean_without = [&](int excluded) {
    double s = 0.0;
    int n = 0;
    for (int i = 0; i < b; ++i)
      if (i != excluded) {
        s += v[static_cast<std::size_t>(i)];
        ++n;
      }
    return s / n;
  };
  const JackknifeBound j = BlockJackknife(b, mean_without, 0.95);
  double mean = 0.0, ss = 0.0;
  for (double x : v) mean += x / b;
  for (double x : v) ss += (x - mean) * (x - mean);
  const double se = std::sqrt(ss / (b - 1)) / std::sqrt(static_cast<double>(b));
  EXPECT_NEAR(j.estimate, mean, 1e-12);
  EXPECT_NEAR(j.se, se, 1e-12);
  EXPECT_NEAR(j.lower, mean - 1.943 * se, 5e-4 * se);
  EXPECT_EQ(j.blocks, b);
}

TEST(BlockJackknife, OneBlockHasNoBound) {
  const JackknifeBound j = BlockJackknife(1, [](int) { return 2.0; });
  EXPECT_EQ(j.estimate, 2.0);
  EXPECT_TRUE(std::isinf(j.se));
  EXPECT_TRUE(std::isinf(j.lower) && j.lower < 0.0);
}

TEST(BlockJackknife, RejectsALevelOutsideTheOpenInterval) {
  EXPECT_THROW(BlockJackknife(3, [](int) { return 0.0; }, 1.0), std::invalid_argument);
  EXPECT_THROW(BlockJackknife(3, [](int) { return 0.0; }, 0.4), std::invalid_argument);
}

}  // namespace
}  // namespace pwsim::sysid::platform
