#include "sysid/identify/fitness.h"

#include <cmath>
#include <limits>

#include "engine/check.h"

namespace pwsim {
namespace {

struct Norms {
  double error_squared{0.0};
  double deviation_squared{0.0};
};

Norms ComputeNorms(std::span<const double> measured, std::span<const double> model) {
  PWSIM_DEMAND(measured.size() == model.size() && !measured.empty());
  double mean = 0.0;
  for (double y : measured) mean += y;
  mean /= static_cast<double>(measured.size());
  Norms norms;
  for (std::size_t k = 0; k < measured.size(); ++k) {
    const double error = measured[k] - model[k];
    const double deviation = measured[k] - mean;
    norms.error_squared += error * error;
    norms.deviation_squared += deviation * deviation;
  }
  return norms;
}

double Percent(double error_squared, double deviation_squared) {
  if (deviation_squared == 0.0) {
    return error_squared == 0.0 ? 100.0 : -std::numeric_limits<double>::infinity();
  }
  return 100.0 * (1.0 - std::sqrt(error_squared) / std::sqrt(deviation_squared));
}

}  // namespace

double FitPercent(std::span<const double> measured, std::span<const double> model) {
  const Norms norms = ComputeNorms(measured, model);
  return Percent(norms.error_squared, norms.deviation_squared);
}

void PooledFit::Add(std::span<const double> measured, std::span<const double> model) {
  const Norms norms = ComputeNorms(measured, model);
  error_squared_ += norms.error_squared;
  deviation_squared_ += norms.deviation_squared;
  ++records_;
}

double PooledFit::Percent() const {
  if (records_ == 0) return std::numeric_limits<double>::quiet_NaN();
  return pwsim::Percent(error_squared_, deviation_squared_);
}

}  // namespace pwsim
