#pragma once
// Exact permutation tails of rank statistics on doubled mid-ranks (integers), the recursions
// documented in signed_rank.h and rank_sum.h.

#include <cstdint>
#include <optional>
#include <span>

namespace pwsim::study {

struct Tails {
  double le{1.0};  ///< P(S ≤ s_obs)
  double ge{1.0};  ///< P(S ≥ s_obs)
};

/// S = Σ ε_i r_i with independent ε_i ∈ {0, 1} of probability ½ each (the signed-rank null).
/// nullopt when n · Σ r_i exceeds max_work.
std::optional<Tails> SignedSumTails(std::span<const std::int64_t> doubled_ranks,
                                    std::int64_t observed, double max_work);

/// S = sum of `k` of the values drawn without replacement, every subset equally likely (the
/// rank-sum null). nullopt when N · k · (sum range) exceeds max_work.
std::optional<Tails> SubsetSumTails(std::span<const std::int64_t> doubled_ranks, std::size_t k,
                                    std::int64_t observed, double max_work);

}  // namespace pwsim::study
