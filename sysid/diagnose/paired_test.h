#pragma once
// Paired comparisons of two models' residuals on the same samples, with the residuals' colour
// taken into account (a model's error is correlated over neighbouring samples).
//
// For a series u_1..u_n, the variance of its sum S = Σ u_k by Newey and West (1987), Bartlett
// weights over `bandwidth` lags L:
//   Var(S) ≈ Σ_{|j|≤L} (1 − |j|/(L+1)) Σ_k u_k u_{k+|j|}
// (u as given: the caller centres it where the test asks for it). Checked against R's
// sandwich::NeweyWest (tests/sysid/diagnose/paired_test_test.cc).
//
// Diebold and Mariano (1995): model a predicts better than model b when the loss differential
// d_k = e_b,k² − e_a,k², summed over every series, is positive beyond its noise:
//   Σ d − z Sqrt(Σ Var(Σ d − its mean)) > 0,   z = 1.645 (one-sided 95 %).

#include <cstddef>
#include <vector>

namespace pwsim::diagnose {

/// The one-sided 95 % point of the standard normal distribution.
inline constexpr double kOneSidedZ95 = 1.6448536269514722;

/// Newey-West variance of the sum of `u` (Bartlett weights, `bandwidth` lags; no centring).
double NeweyWestSumVariance(const std::vector<double>& u, std::size_t bandwidth);

/// The loss differential of two residual series of one sample grid, each weighted by `weight`
/// (a channel's 1/scale): its sum and the Newey-West variance of that sum (d centred).
struct LossDifferential {
  double sum{0.0};
  double variance{0.0};
};

/// Adds the differential (e_b² − e_a²)·weight² of one series pair (the shorter length) to `total`.
void AddLossDifferential(const std::vector<double>& e_a, const std::vector<double>& e_b, double weight,
                         std::size_t bandwidth, LossDifferential& total);

/// True when Σ d − 1.645 √Var > 0: the series of a have the smaller error beyond the noise.
bool ClearlySmaller(const LossDifferential& d);

}  // namespace pwsim::diagnose
