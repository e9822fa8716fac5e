#include "study/ranks.h"

#include <algorithm>
#include <numeric>

namespace pwsim::study {

double Ranking::TieSum() const {
  double sum = 0.0;
  for (std::size_t t : tie_sizes) {
    const double td = static_cast<double>(t);
    sum += td * td * td - td;
  }
  return sum;
}

Ranking MidRanks(std::span<const double> values) {
  const std::size_t n = values.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  Ranking r;
  r.rank.assign(n, 0.0);
  std::size_t i = 0;
  while (i < n) {
    std::size_t j = i + 1;
    while (j < n && values[order[j]] == values[order[i]]) ++j;
    // ranks i+1 .. j share their mean (i + 1 + j) / 2
    const double mid = 0.5 * static_cast<double>(i + 1 + j);
    for (std::size_t k = i; k < j; ++k) r.rank[order[k]] = mid;
    r.tie_sizes.push_back(j - i);
    if (j - i > 1) r.has_ties = true;
    i = j;
  }
  return r;
}

}  // namespace pwsim::study
