// The paired comparison of sysid/diagnose/paired_test.h: the Newey-West variance against R's
// sandwich::NeweyWest (computed at test time by tests/sysid/diagnose/newey_west.R; skipped with
// a message where Rscript or the package is missing), and the Diebold-Mariano decision on
// residuals of known make-up.

#include "sysid/diagnose/paired_test.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>

namespace pwsim::diagnose {
namespace {

int RunShell(const std::string& command) {
  const int status = std::system(command.c_str());
  return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// AR(1) series x_k = φ x_{k-1} + ε_k, ε ~ N(0, 1), with a mean `offset`.
std::vector<double> Ar1(std::mt19937_64& rng, std::size_t n, double phi, double offset) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> x(n);
  double state = 0.0;
  for (double& v : x) {
    state = phi * state + normal(rng);
    v = state + offset;
  }
  return x;
}

TEST(PairedTestTest, NeweyWestVarianceMatchesRSandwich) {
  if (RunShell("Rscript -e 'suppressPackageStartupMessages(library(sandwich))' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "Rscript with the sandwich package not found: install r-base-core and r-cran-sandwich "
                    "(scripts/install-deps.sh) to compare with R";
  const std::filesystem::path dir = std::filesystem::path(PWSIM_BINARY_DIR) / "test_out" / "paired_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  // White, coloured and strongly coloured series; lags from 0 to beyond the series' length.
  std::mt19937_64 rng(20261127);
  struct Case {
    std::size_t n, lag;
    double phi;
  };
  const std::vector<Case> cases{{5, 0, 0.0},   {5, 10, 0.5},  {40, 3, 0.0},    {40, 25, 0.8},
                                {300, 25, 0.9}, {300, 1, -0.5}, {1000, 25, 0.95}, {1000, 60, 0.3}};
  std::map<int, double> ours;
  {
    std::ofstream csv(dir / "series.csv");
    csv << "id,lag,value\n";
    csv.precision(17);
    for (std::size_t i = 0; i < cases.size(); ++i) {
      std::vector<double> d = Ar1(rng, cases[i].n, cases[i].phi, 0.7);
      for (double v : d) csv << i << ',' << cases[i].lag << ',' << v << '\n';
      double mean = 0.0;
      for (double v : d) mean += v / static_cast<double>(d.size());
      for (double& v : d) v -= mean;  // NeweyWest on lm(d ~ 1) works on the centred series
      ours[static_cast<int>(i)] = NeweyWestSumVariance(d, cases[i].lag);
    }
  }
  const std::filesystem::path script = std::filesystem::path(PWSIM_SOURCE_DIR) / "tests/sysid/diagnose/newey_west.R";
  ASSERT_EQ(RunShell("Rscript '" + script.string() + "' '" + (dir / "series.csv").string() + "' '" +
                     (dir / "r.csv").string() + "'"),
            0);
  std::ifstream in(dir / "r.csv");
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line, "id,var_sum");
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string id, value;
    std::getline(s, id, ',');
    std::getline(s, value, ',');
    const double r = std::stod(value);
    EXPECT_NEAR(ours.at(std::stoi(id)), r, 1e-9 * std::abs(r)) << "series " << id;
    ++rows;
  }
  EXPECT_EQ(rows, cases.size());
}

TEST(PairedTestTest, AModelOnlyBetterByNoiseIsNotClearlyBetter) {
  // Two models whose residuals are the same coloured noise but for independent small noise:
  // neither is clearly better, either way round.
  std::mt19937_64 rng(7);
  const std::vector<double> common = Ar1(rng, 2000, 0.9, 0.0);
  std::vector<double> a = common, b = common;
  const std::vector<double> na = Ar1(rng, 2000, 0.5, 0.0), nb = Ar1(rng, 2000, 0.5, 0.0);
  for (std::size_t k = 0; k < a.size(); ++k) {
    a[k] += 0.1 * na[k];
    b[k] += 0.1 * nb[k];
  }
  LossDifferential ab, ba;
  AddLossDifferential(a, b, 1.0, 25, ab);
  AddLossDifferential(b, a, 1.0, 25, ba);
  EXPECT_FALSE(ClearlySmaller(ab));
  EXPECT_FALSE(ClearlySmaller(ba));
  EXPECT_DOUBLE_EQ(ab.sum, -ba.sum);
  // Identical residuals: a zero differential is never clearly smaller.
  LossDifferential same;
  AddLossDifferential(a, a, 1.0, 25, same);
  EXPECT_FALSE(ClearlySmaller(same));
}

TEST(PairedTestTest, AModelThatRemovesStructureIsClearlyBetter) {
  // b's residual carries a slow structured error beside the noise that a's also has.
  std::mt19937_64 rng(11);
  const std::vector<double> noise = Ar1(rng, 2000, 0.7, 0.0);
  std::vector<double> a = noise, b = noise;
  for (std::size_t k = 0; k < b.size(); ++k) b[k] += 0.8 * std::sin(0.01 * static_cast<double>(k));
  LossDifferential ab, ba;
  AddLossDifferential(a, b, 2.0, 25, ab);  // the weight scales both alike
  AddLossDifferential(b, a, 2.0, 25, ba);
  EXPECT_TRUE(ClearlySmaller(ab));
  EXPECT_FALSE(ClearlySmaller(ba));
  // Summed over two series: the differentials and their variances add.
  LossDifferential twice;
  AddLossDifferential(a, b, 2.0, 25, twice);
  AddLossDifferential(a, b, 2.0, 25, twice);
  EXPECT_DOUBLE_EQ(twice.sum, 2.0 * ab.sum);
  EXPECT_DOUBLE_EQ(twice.variance, 2.0 * ab.variance);
}

}  // namespace
}  // namespace pwsim::diagnose
