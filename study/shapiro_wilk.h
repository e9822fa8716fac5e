#pragma once
// Shapiro–Wilk W test of normality, by Royston's approximations (P. Royston, "Remark AS R94:
// A remark on algorithm AS 181: The W-test for normality", Applied Statistics 44(4), 1995,
// 547–551), the algorithm behind R's shapiro.test and scipy.stats.shapiro.
//
// Statistic. For the sorted sample x_(1) ≤ … ≤ x_(n) (3 ≤ n ≤ 5000),
//   W = (Σ_{i=1}^{⌊n/2⌋} a_i (x_(n+1−i) − x_(i)))² / Σ (x_i − x̄)²,
// with the coefficients a_i approximated as follows (m_i, a_i for the lower half):
//   m_i = Φ⁻¹((i − 3/8) / (n + 1/4))         (Blom scores; negative for i ≤ n/2)
//   M² = 2 Σ_{i ≤ n/2} m_i²,  u = 1/√n
//   a_1 = −m_1/M + P_1(u),  P_1 = 0.221157 u − 0.147981 u² − 2.071190 u³ + 4.434685 u⁴ − 2.706056 u⁵
//   n > 5: a_2 = −m_2/M + P_2(u),  P_2 = 0.042981 u − 0.293762 u² − 1.752461 u³ + 5.682633 u⁴ − 3.582633 u⁵
//          φ = (M² − 2m_1² − 2m_2²) / (1 − 2a_1² − 2a_2²),  a_i = −m_i/√φ for i ≥ 3
//   n ≤ 5: φ = (M² − 2m_1²) / (1 − 2a_1²),  a_i = −m_i/√φ for i ≥ 2
//   n = 3: a_1 = √(1/2) exactly.
// Significance (upper tail of a normal approximation to a transform of 1 − W):
//   n = 3:       p = (6/π)(asin √W − asin √(3/4)), at least 0 (exact).
//   4 ≤ n ≤ 11:  γ = −2.273 + 0.459 n; y = −ln(γ − ln(1 − W)) (p = 1e−99 when ln(1 − W) ≥ γ);
//                μ = 0.5440 − 0.39978 n + 0.025054 n² − 0.0006714 n³;
//                σ = exp(1.3822 − 0.77857 n + 0.062767 n² − 0.0020322 n³).
//   n ≥ 12:      y = ln(1 − W), with ν = ln n:
//                μ = −1.5861 − 0.31082 ν − 0.083751 ν² + 0.0038915 ν³;
//                σ = exp(−0.4803 − 0.082676 ν + 0.0030302 ν²).
//   p = 1 − Φ((y − μ)/σ).
// Φ and Φ⁻¹ come from Boost.Math. Ties in the data need no special treatment.
// The coefficients are Royston's published ones; tests/study compares W and p with R 4.2's
// shapiro.test and scipy on a generated corpus.

#include <span>
#include <string>

namespace pwsim::study {

struct ShapiroWilk {
  double w{0.0};
  double p{0.0};
};

/// Throws std::invalid_argument when n < 3, n > 5000, or all values are equal (as R).
ShapiroWilk ShapiroWilkTest(std::span<const double> values);

}  // namespace pwsim::study
