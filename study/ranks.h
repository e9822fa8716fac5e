#pragma once
// Mid-ranks, the ranking every rank test here uses (R's rank(ties.method = "average"),
// scipy.stats.rankdata(method = "average")): sorted ascending, a run of t equal values that
// would occupy ranks k+1 .. k+t all get the mean rank k + (t+1)/2. Mid-ranks are integers or
// half-integers, so twice a mid-rank is an integer: the exact null distributions below are
// built on these doubled ranks and stay exact with ties.
//
// Tie correction: the variance of a rank statistic shrinks by a term in Σ (t³ − t) over the
// tie groups (sizes t); TieSum returns that sum.

#include <cstddef>
#include <span>
#include <vector>

namespace pwsim::study {

struct Ranking {
  std::vector<double> rank;             ///< mid-rank of each value, in input order (1-based)
  std::vector<std::size_t> tie_sizes;   ///< size t of every group of equal values (t = 1 too)
  bool has_ties{false};
  /// Σ (t³ − t) over the tie groups.
  double TieSum() const;
};

/// Mid-ranks of `values` (finite numbers). Equal means ==.
Ranking MidRanks(std::span<const double> values);

}  // namespace pwsim::study
