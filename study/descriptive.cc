#include "study/descriptive.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace pwsim::study {

double QuantileType7(std::span<const double> sorted, double p) {
  if (sorted.empty()) throw std::invalid_argument("QuantileType7: empty sample");
  const double h = static_cast<double>(sorted.size() - 1) * p;
  const double lo = std::floor(h);
  const auto i = static_cast<std::size_t>(lo);
  if (i + 1 >= sorted.size()) return sorted.back();
  return sorted[i] + (h - lo) * (sorted[i + 1] - sorted[i]);
}

Descriptive Describe(std::span<const double> values) {
  if (values.empty()) throw std::invalid_argument("Describe: empty sample");
  std::vector<double> x(values.begin(), values.end());
  std::sort(x.begin(), x.end());
  Descriptive d;
  d.n = x.size();
  double sum = 0.0;
  for (double v : x) sum += v;
  d.mean = sum / static_cast<double>(d.n);
  if (d.n > 1) {
    double ss = 0.0;
    for (double v : x) ss += (v - d.mean) * (v - d.mean);
    d.sd = std::sqrt(ss / static_cast<double>(d.n - 1));
  }
  d.median = QuantileType7(x, 0.5);
  d.q1 = QuantileType7(x, 0.25);
  d.q3 = QuantileType7(x, 0.75);
  d.min = x.front();
  d.max = x.back();
  return d;
}

}  // namespace pwsim::study
