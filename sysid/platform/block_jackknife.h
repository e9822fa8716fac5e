#pragma once
// Uncertainty of a statistic over blocks of data: the delete-one-block jackknife
// (Quenouille 1956, Tukey 1958; Efron & Tibshirani, An Introduction to the Bootstrap, 1993,
// ch. 11). With B blocks, θ̂ the statistic on all of them and θ̂₍b₎ the statistic without
// block b, θ̄ = (1/B) Σ_b θ̂₍b₎:
//   se = sqrt((B − 1)/B · Σ_b (θ̂₍b₎ − θ̄)²),
//   lower bound at one-sided level L:  θ̂ − t_{L, B−1} · se   (Student t, B − 1 degrees of freedom).
// For the mean of B numbers the jackknife se is exactly the textbook s/√B.
// Blocks of contiguous samples, not single rows, are left out, so that the autocorrelation
// inside a block (filters, slow disturbances) is carried by the block-to-block spread.

#include <functional>

namespace pwsim::sysid::platform {

struct JackknifeBound {
  double estimate{0.0};  ///< θ̂ on all blocks
  double se{0.0};        ///< jackknife standard error (+inf with fewer than 2 blocks)
  double lower{0.0};     ///< θ̂ − t·se (−inf with fewer than 2 blocks)
  int blocks{0};
};

/// `statistic(excluded)`: the statistic without block `excluded` (−1: on every block).
/// @throws std::invalid_argument unless 0.5 < level < 1.
JackknifeBound BlockJackknife(int blocks, const std::function<double(int excluded)>& statistic,
                              double level = 0.95);

}  // namespace pwsim::sysid::platform
