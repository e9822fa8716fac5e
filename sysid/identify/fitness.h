#pragma once
// Model fitness as MATLAB's `compare` reports it (seed 000 §IV-3, the 79.3 % / 57.6 %):
//   fit = 100 (1 - ||y - ŷ|| / ||y - mean(y)||)   [%]
// 100 is a perfect model, 0 is no better than the mean of the data, and it can be negative.

#include <span>
#include <vector>

namespace pwsim {

/// MATLAB compare's fitness [%] of `model` against `measured` (same length, ≥ 1 sample).
/// A constant measured signal gives -inf unless the model matches it exactly (then 100).
double FitPercent(std::span<const double> measured, std::span<const double> model);

/// Fitness pooled over several records: 100 (1 - sqrt(Σ||y_r - ŷ_r||²) / sqrt(Σ||y_r - ȳ_r||²)),
/// each record centred on its own mean in the denominator (used for validation_fit_pct, so a
/// trial with no excitation does not drown the others).
class PooledFit {
 public:
  void Add(std::span<const double> measured, std::span<const double> model);
  double Percent() const;  ///< NaN when nothing was added
  bool empty() const { return records_ == 0; }

 private:
  double error_squared_{0.0};
  double deviation_squared_{0.0};
  int records_{0};
};

}  // namespace pwsim
