#pragma once
// Wilcoxon rank-sum / Mann–Whitney test for two independent samples a (size m) and b (size n),
// two-sided, with R 4.2's conventions (wilcox.test(a, b), paired = FALSE) and the exact
// conditional p-value besides.
//
// r_i = mid-rank of each value in the pooled sample (N = m + n).
//   W = Σ_{i ∈ a} r_i − m(m+1)/2      (R's W = scipy's U of a = #{a_i > b_j} + ½ #{a_i = b_j})
// Under H0 every split of the N pooled ranks into m and n is equally likely:
//   E[W] = mn/2,  Var[W] = (mn/12) ((N + 1) − Σ(t³ − t) / (N(N − 1)))
// p (R's default): exact when m < 50 and n < 50 and no ties, else the normal approximation
// with continuity correction: z = (W − mn/2 − ½ sgn(W − mn/2)) / √Var[W], p = 2 min(Φ, 1 − Φ).
// Exact null distribution by the subset-sum recursion over the pooled (doubled mid-)ranks:
//   c_k(j, s) = c_{k−1}(j, s) + c_{k−1}(j − 1, s − 2r_k)     (j ranks chosen of the first k)
//   P(2 Σ_a r = s) = c_N(m, s) / C(N, m).
// Without ties this is the Mann–Whitney distribution (R's pwilcox); with ties it is the exact
// distribution conditional on the tie pattern. Two-sided exact p:
//   W > mn/2: p = 2 P(W' ≥ W);  otherwise p = 2 P(W' ≤ W);  capped at 1   (as R).
// Rank-biserial correlation (Glass; Kerby 2014): r = 2W/(mn) − 1 = P(a > b) − P(a < b).

#include <cstddef>
#include <optional>
#include <span>
#include <string>

namespace pwsim::study {

struct RankSumOptions {
  bool correct{true};
  std::size_t exact_below_n{50};  ///< R: exact when both sizes < 50 (and no ties)
  /// Largest N · m · (sum range) the exact conditional recursion may take; beyond, no p_exact.
  double max_exact_work{4e8};
};

struct RankSum {
  std::size_t n_a{0};
  std::size_t n_b{0};
  bool ties{false};
  double w{0.0};          ///< R's W (Mann–Whitney U of a)
  double p{1.0};          ///< R 4.2's default p
  bool p_is_exact{false};
  double p_normal{1.0};
  std::optional<double> p_exact;
  double z{0.0};
  double rank_biserial{0.0};
  std::string method;
};

/// @throws std::invalid_argument when a or b is empty.
RankSum RankSumTest(std::span<const double> a, std::span<const double> b,
                    const RankSumOptions& options = {});

}  // namespace pwsim::study
