#pragma once
// Wilcoxon signed-rank test for paired samples a, b (two-sided), with R 4.2's conventions
// (wilcox.test(a, b, paired = TRUE)) and the exact conditional p-value besides.
//
// Differences d_i = a_i − b_i; zero differences are dropped (Wilcoxon's method, as R < 4.6
// and scipy's default), leaving n non-zero ones. r_i = mid-rank of |d_i| among them.
//   V = Σ_{d_i > 0} r_i                                   (R's statistic V)
//   R− = n(n+1)/2 − V; scipy reports min(V, R−).
// Under H0 each rank carries a + or − sign with probability 1/2, independently.
//   E[V] = n(n+1)/4,  Var[V] = n(n+1)(2n+1)/24 − Σ(t³ − t)/48   (t: sizes of tied |d| groups)
// p (R's default): exact when n < 50 and there are neither ties nor zeros, else the normal
// approximation with continuity correction:
//   z = (V − E[V] − ½ sgn(V − E[V])) / √Var[V],  p = 2 min(Φ(z), 1 − Φ(z)).
// Exact null distribution by the recursion over ranks (one rank at a time, sign + or −):
//   c_k(s) = c_{k−1}(s) + c_{k−1}(s − r_k),  c_0(0) = 1,  P(V = s) = c_n(s) / 2ⁿ,
// run on doubled mid-ranks 2r_k (integers), so the same recursion gives the exact distribution
// conditional on the observed ties (the permutation distribution). Two-sided exact p:
//   V > E[V]: p = 2 P(V' ≥ V);  otherwise p = 2 P(V' ≤ V);  capped at 1   (as R's psignrank).
// Without ties this is R's exact p; with ties it is the exact conditional p (p_exact).
// Matched-pairs rank-biserial correlation (Kerby 2014): r = (V − R−) / (V + R−).

#include <cstddef>
#include <optional>
#include <span>
#include <string>

namespace pwsim::study {

struct SignedRankOptions {
  bool correct{true};            ///< continuity correction in the normal approximation
  std::size_t exact_below_n{50}; ///< R: exact when n < 50 (and no ties/zeros)
  /// Largest work n · (Σ 2r_i + 1) of the exact conditional recursion; beyond, no p_exact
  /// (about n = 600 without ties).
  double max_exact_work{4e8};
};

struct SignedRank {
  std::size_t n_pairs{0};
  std::size_t n_nonzero{0};
  std::size_t n_zero{0};
  bool ties{false};
  double v{0.0};          ///< R's V: sum of ranks of the positive differences
  double r_minus{0.0};    ///< sum of ranks of the negative differences
  double p{1.0};          ///< R 4.2's default p
  bool p_is_exact{false}; ///< whether p came from the exact (no-tie) distribution
  double p_normal{1.0};   ///< normal approximation (correction as options.correct)
  std::optional<double> p_exact;  ///< exact conditional p (absent when too large to enumerate)
  double z{0.0};          ///< the normal deviate of p_normal
  double matched_rank_biserial{0.0};
  std::string method;     ///< R's method text
};

/// @throws std::invalid_argument when a and b differ in length or are empty.
SignedRank SignedRankTest(std::span<const double> a, std::span<const double> b,
                          const SignedRankOptions& options = {});

}  // namespace pwsim::study
