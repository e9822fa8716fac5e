#include "study/rank_sum.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <boost/math/distributions/normal.hpp>

#include "study/exact_tails.h"
#include "study/ranks.h"

namespace pwsim::study {

RankSum RankSumTest(std::span<const double> a, std::span<const double> b,
                    const RankSumOptions& options) {
  if (a.empty() || b.empty()) throw std::invalid_argument("rank-sum test: an empty sample");
  RankSum r;
  r.n_a = a.size();
  r.n_b = b.size();
  std::vector<double> pooled(a.begin(), a.end());
  pooled.insert(pooled.end(), b.begin(), b.end());
  const Ranking ranking = MidRanks(pooled);
  r.ties = ranking.has_ties;
  const double m = static_cast<double>(r.n_a);
  const double n = static_cast<double>(r.n_b);
  const double big_n = m + n;
  std::vector<std::int64_t> doubled(pooled.size());
  std::int64_t sum2 = 0;
  double rank_sum_a = 0.0;
  for (std::size_t i = 0; i < pooled.size(); ++i) {
    doubled[i] = std::llround(2.0 * ranking.rank[i]);
    if (i < r.n_a) {
      rank_sum_a += ranking.rank[i];
      sum2 += doubled[i];
    }
  }
  r.w = rank_sum_a - m * (m + 1.0) / 2.0;
  r.rank_biserial = 2.0 * r.w / (m * n) - 1.0;

  const double var = (m * n / 12.0) * ((big_n + 1.0) - ranking.TieSum() / (big_n * (big_n - 1.0)));
  const double dev = r.w - m * n / 2.0;
  if (var > 0.0) {
    const double correction = options.correct ? 0.5 * ((dev > 0) - (dev < 0)) : 0.0;
    r.z = (dev - correction) / std::sqrt(var);
    const boost::math::normal normal;
    r.p_normal = std::min(1.0, 2.0 * std::min(boost::math::cdf(normal, r.z),
                                             boost::math::cdf(boost::math::complement(normal, r.z))));
  } else {
    r.p_normal = 1.0;  // every value equal: R returns NaN
  }
  if (const auto tails = SubsetSumTails(doubled, r.n_a, sum2, options.max_exact_work)) {
    const double side = 2.0 * r.w > m * n ? tails->ge : tails->le;
    r.p_exact = std::min(1.0, 2.0 * side);
  }
  const bool exact = r.n_a < options.exact_below_n && r.n_b < options.exact_below_n && !r.ties && r.p_exact;
  if (exact) {
    r.p = *r.p_exact;
    r.p_is_exact = true;
    r.method = "Wilcoxon rank sum exact test";
  } else {
    r.p = r.p_normal;
    r.method = options.correct ? "Wilcoxon rank sum test with continuity correction"
                               : "Wilcoxon rank sum test";
    if (var <= 0.0) r.method = "all values are equal: no test (R returns NaN; reported as p = 1)";
  }
  return r;
}

}  // namespace pwsim::study
