#pragma once
// Descriptive statistics of one sample: n, mean, sample standard deviation (divisor n − 1),
// median and quartiles, extremes.
//
// Quantiles are R's default (quantile(type = 7), numpy's "linear"): for sorted x_(1..n) and
// probability p, h = (n − 1) p, Q(p) = x_(⌊h⌋+1) + (h − ⌊h⌋) (x_(⌊h⌋+2) − x_(⌊h⌋+1)).
// The median is Q(0.5) (the usual median), q1 = Q(0.25), q3 = Q(0.75).

#include <cstddef>
#include <span>

namespace pwsim::study {

struct Descriptive {
  std::size_t n{0};
  double mean{0.0};
  double sd{0.0};      ///< sample standard deviation (n − 1); 0 when n < 2
  double median{0.0};
  double q1{0.0};
  double q3{0.0};
  double min{0.0};
  double max{0.0};
};

/// @pre values non-empty and finite.
Descriptive Describe(std::span<const double> values);

/// Q(p) of type 7 for p in [0, 1]. @pre sorted non-empty.
double QuantileType7(std::span<const double> sorted, double p);

}  // namespace pwsim::study
