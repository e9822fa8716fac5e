#include "study/exact_tails.h"

#include <algorithm>
#include <functional>
#include <numeric>
#include <vector>

namespace pwsim::study {
namespace {

Tails TailsOf(const std::vector<double>& prob, std::int64_t observed) {
  Tails t{0.0, 0.0};
  const auto size = static_cast<std::int64_t>(prob.size());
  for (std::int64_t s = 0; s < size; ++s) {
    if (s <= observed) t.le += prob[static_cast<std::size_t>(s)];
    if (s >= observed) t.ge += prob[static_cast<std::size_t>(s)];
  }
  t.le = std::min(1.0, t.le);
  t.ge = std::min(1.0, t.ge);
  return t;
}

}  // namespace

std::optional<Tails> SignedSumTails(std::span<const std::int64_t> doubled_ranks,
                                    std::int64_t observed, double max_work) {
  const std::int64_t total = std::accumulate(doubled_ranks.begin(), doubled_ranks.end(), std::int64_t{0});
  if (static_cast<double>(doubled_ranks.size()) * static_cast<double>(total + 1) > max_work)
    return std::nullopt;
  // prob[s] = P(S_k = s) after k ranks: P_k(s) = ½ P_{k−1}(s) + ½ P_{k−1}(s − r_k)
  std::vector<double> prob(static_cast<std::size_t>(total) + 1, 0.0);
  prob[0] = 1.0;
  std::int64_t reach = 0;
  for (std::int64_t r : doubled_ranks) {
    reach += r;
    for (std::int64_t s = reach; s >= 0; --s) {
      const double keep = prob[static_cast<std::size_t>(s)];
      const double add = s >= r ? prob[static_cast<std::size_t>(s - r)] : 0.0;
      prob[static_cast<std::size_t>(s)] = 0.5 * (keep + add);
    }
  }
  return TailsOf(prob, observed);
}

std::optional<Tails> SubsetSumTails(std::span<const std::int64_t> doubled_ranks, std::size_t k,
                                    std::int64_t observed, double max_work) {
  const std::size_t n_all = doubled_ranks.size();
  const std::int64_t total = std::accumulate(doubled_ranks.begin(), doubled_ranks.end(), std::int64_t{0});
  if (k > n_all) return std::nullopt;
  // Choose the smaller side: the sum of the other n_all − k values is total − S.
  if (2 * k > n_all) {
    auto t = SubsetSumTails(doubled_ranks, n_all - k, total - observed, max_work);
    if (t) std::swap(t->le, t->ge);
    return t;
  }
  std::vector<std::int64_t> sorted(doubled_ranks.begin(), doubled_ranks.end());
  std::sort(sorted.begin(), sorted.end(), std::greater<>());
  const std::int64_t max_sum = std::accumulate(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), std::int64_t{0});
  const double work = static_cast<double>(n_all) * static_cast<double>(k + 1) * static_cast<double>(max_sum + 1);
  if (work > max_work) return std::nullopt;
  const auto width = static_cast<std::size_t>(max_sum) + 1;
  // count[j][s]: number of j-subsets of the ranks seen so far with doubled sum s (in double:
  // counts up to C(N, k) are far inside its range, and only additions are used).
  std::vector<double> count((k + 1) * width, 0.0);
  count[0] = 1.0;
  std::size_t seen = 0;
  for (std::int64_t r : doubled_ranks) {
    ++seen;
    for (std::size_t j = std::min(seen, k); j >= 1; --j) {
      double* row = &count[j * width];
      const double* prev = &count[(j - 1) * width];
      for (std::int64_t s = max_sum; s >= r; --s)
        row[static_cast<std::size_t>(s)] += prev[static_cast<std::size_t>(s - r)];
    }
  }
  std::vector<double> prob(count.begin() + static_cast<std::ptrdiff_t>(k * width), count.end());
  const double all = std::accumulate(prob.begin(), prob.end(), 0.0);
  for (double& p : prob) p /= all;
  return TailsOf(prob, observed);
}

}  // namespace pwsim::study
