#include "sysid/diagnose/paired_test.h"

#include <algorithm>
#include <cmath>

namespace pwsim::diagnose {

double NeweyWestSumVariance(const std::vector<double>& u, std::size_t bandwidth) {
  const std::size_t n = u.size();
  double variance = 0.0;
  for (std::size_t lag = 0; lag <= std::min(bandwidth, n); ++lag) {
    double g = 0.0;
    for (std::size_t k = 0; k + lag < n; ++k) g += u[k] * u[k + lag];
    variance += lag == 0 ? g : 2.0 * (1.0 - static_cast<double>(lag) / (static_cast<double>(bandwidth) + 1.0)) * g;
  }
  return variance;
}

void AddLossDifferential(const std::vector<double>& e_a, const std::vector<double>& e_b, double weight,
                         std::size_t bandwidth, LossDifferential& total) {
  const std::size_t n = std::min(e_a.size(), e_b.size());
  if (n == 0) return;
  std::vector<double> d(n);
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double a = weight * e_a[k], b = weight * e_b[k];
    d[k] = b * b - a * a;
    sum += d[k];
  }
  const double mean = sum / static_cast<double>(n);
  for (double& v : d) v -= mean;
  total.sum += sum;
  total.variance += NeweyWestSumVariance(d, bandwidth);
}

bool ClearlySmaller(const LossDifferential& d) {
  return d.sum - kOneSidedZ95 * std::sqrt(std::max(0.0, d.variance)) > 0.0;
}

}  // namespace pwsim::diagnose
