#include "study/signed_rank.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <boost/math/distributions/normal.hpp>

#include "study/exact_tails.h"
#include "study/ranks.h"

namespace pwsim::study {
namespace {

double TwoSidedNormal(double z) {
  const boost::math::normal normal;
  const double lower = boost::math::cdf(normal, z);
  const double upper = boost::math::cdf(boost::math::complement(normal, z));
  return std::min(1.0, 2.0 * std::min(lower, upper));
}

}  // namespace

SignedRank SignedRankTest(std::span<const double> a, std::span<const double> b,
                          const SignedRankOptions& options) {
  if (a.size() != b.size())
    throw std::invalid_argument("signed-rank test: the paired samples differ in length");
  if (a.empty()) throw std::invalid_argument("signed-rank test: no pairs");
  SignedRank r;
  r.n_pairs = a.size();
  std::vector<double> d;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double diff = a[i] - b[i];
    if (diff == 0.0) {
      ++r.n_zero;
    } else {
      d.push_back(diff);
    }
  }
  r.n_nonzero = d.size();
  const double n = static_cast<double>(d.size());
  if (d.empty()) {
    r.method = "all differences are zero: no test (R returns NaN; reported as p = 1)";
    r.p = r.p_normal = 1.0;
    r.p_exact = 1.0;
    return r;
  }
  std::vector<double> abs_d(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) abs_d[i] = std::abs(d[i]);
  const Ranking ranking = MidRanks(abs_d);
  r.ties = ranking.has_ties;
  std::vector<std::int64_t> doubled(d.size());
  std::int64_t v2 = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    doubled[i] = std::llround(2.0 * ranking.rank[i]);
    if (d[i] > 0) {
      r.v += ranking.rank[i];
      v2 += doubled[i];
    } else {
      r.r_minus += ranking.rank[i];
    }
  }
  r.matched_rank_biserial = (r.v - r.r_minus) / (r.v + r.r_minus);

  const double mean = n * (n + 1.0) / 4.0;
  const double var = n * (n + 1.0) * (2.0 * n + 1.0) / 24.0 - ranking.TieSum() / 48.0;
  const double dev = r.v - mean;
  const double correction = options.correct ? 0.5 * ((dev > 0) - (dev < 0)) : 0.0;
  r.z = (dev - correction) / std::sqrt(var);
  r.p_normal = TwoSidedNormal(r.z);

  if (const auto tails = SignedSumTails(doubled, v2, options.max_exact_work)) {
    // 2V vs 2E[V] = n(n+1)/2, both integers
    const double side = 2.0 * r.v > n * (n + 1.0) / 2.0 ? tails->ge : tails->le;
    r.p_exact = std::min(1.0, 2.0 * side);
  }
  const bool exact = d.size() < options.exact_below_n && !r.ties && r.n_zero == 0 && r.p_exact;
  if (exact) {
    r.p = *r.p_exact;
    r.p_is_exact = true;
    r.method = "Wilcoxon signed rank exact test";
  } else {
    r.p = r.p_normal;
    r.method = options.correct ? "Wilcoxon signed rank test with continuity correction"
                               : "Wilcoxon signed rank test";
  }
  return r;
}

}  // namespace pwsim::study
