#include "sysid/diagnose/greybox_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/check.h"

namespace pwsim::diagnose {
namespace {

constexpr double kLogBound = 2.5;  ///< LM multipliers within e^±2.5 of the start

/// u (optimiser vector) <-> ExtendedParams.
struct Mapper {
  std::optional<effects::EffectId> effect;
  LumpedParams start;
  const std::vector<effects::ParamSpec>* specs{nullptr};

  int Size() const { return 4 + (specs ? static_cast<int>(specs->size()) : 0); }

  effects::ExtendedParams Params(const double* u) const {
    effects::ExtendedParams p;
    p.lm.k_z = start.k_z * std::exp(u[0]);
    p.lm.c_z = start.c_z * std::exp(u[1]);
    p.lm.k_theta = start.k_theta * std::exp(u[2]);
    p.lm.c_theta = start.c_theta * std::exp(u[3]);
    if (effect) {
      std::vector<double> v(specs->size());
      for (std::size_t j = 0; j < v.size(); ++j) v[j] = u[4 + j] * (*specs)[j].scale;
      effects::SetEffectValues(*effect, v, p.fx);
    }
    return p;
  }
};

struct TrialFunctor {
  const FitTrial* trial;
  const Mapper* map;
  ChannelWeights w;

  bool operator()(double const* const* u, double* r) const {
    const TrialResidual res = ComputeResidual(*trial, map->Params(u[0]));
    if (!res.finite) return false;
    for (std::size_t k = 0; k < res.e_z.size(); ++k) {
      r[2 * k] = w.z * res.e_z[k];
      r[2 * k + 1] = w.pitch * res.e_pitch[k];
    }
    return true;
  }
};

double Centre(const std::vector<double>& measured, const std::vector<double>& model,
              std::size_t count) {
  double sum = 0.0;
  for (std::size_t k = 0; k < count; ++k) sum += measured[k] - model[k];
  return sum / static_cast<double>(count);
}

}  // namespace

FitTrial MakeFitTrial(const effects::TrialRecord& record, const Chair& chair, double rest_window) {
  FitTrial fit;
  fit.name = record.name;
  fit.prepared = effects::PrepareTrial(chair, record.terrain, record.load_kg, record.t, record.x);
  fit.z = record.z;
  fit.pitch = record.pitch;
  fit.speed = record.speed;
  std::size_t count = 0;
  while (count < record.t.size() && (count == 0 || record.t[count] - record.t[0] <= rest_window))
    ++count;
  fit.rest_samples = std::max<std::size_t>(1, count);
  return fit;
}

ChannelWeights MakeChannelWeights(const std::vector<FitTrial>& trials) {
  double sz = 0.0, sp = 0.0;
  std::size_t n = 0;
  for (const FitTrial& t : trials) {
    double mz = 0.0, mp = 0.0;
    for (std::size_t k = 0; k < t.z.size(); ++k) {
      mz += t.z[k];
      mp += t.pitch[k];
    }
    mz /= static_cast<double>(t.z.size());
    mp /= static_cast<double>(t.z.size());
    for (std::size_t k = 0; k < t.z.size(); ++k) {
      sz += (t.z[k] - mz) * (t.z[k] - mz);
      sp += (t.pitch[k] - mp) * (t.pitch[k] - mp);
    }
    n += t.z.size();
  }
  ChannelWeights w;
  const double nz = std::max<double>(1.0, static_cast<double>(n));
  w.z = 1.0 / std::max(1e-6, std::sqrt(sz / nz));
  w.pitch = 1.0 / std::max(1e-5, std::sqrt(sp / nz));
  return w;
}

TrialResidual ComputeResidual(const FitTrial& trial, const effects::ExtendedParams& params) {
  TrialResidual res;
  res.model = effects::SimulateExtended(trial.prepared, params);
  const std::size_t n = trial.z.size();
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(res.model.z[k]) || !std::isfinite(res.model.pitch[k]) ||
        std::abs(res.model.z[k]) > 10.0 || std::abs(res.model.pitch[k]) > 3.0) {
      res.finite = false;
      return res;
    }
  }
  const double oz = Centre(trial.z, res.model.z, trial.rest_samples);
  const double op = Centre(trial.pitch, res.model.pitch, trial.rest_samples);
  res.z_model.resize(n);
  res.pitch_model.resize(n);
  res.e_z.resize(n);
  res.e_pitch.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    res.z_model[k] = res.model.z[k] + oz;
    res.pitch_model[k] = res.model.pitch[k] + op;
    res.e_z[k] = trial.z[k] - res.z_model[k];
    res.e_pitch[k] = trial.pitch[k] - res.pitch_model[k];
  }
  return res;
}

double WeightedSse(const std::vector<FitTrial>& trials, const effects::ExtendedParams& params,
                   const ChannelWeights& w, std::size_t* residual_count) {
  double sse = 0.0;
  std::size_t count = 0;
  for (const FitTrial& trial : trials) {
    const TrialResidual res = ComputeResidual(trial, params);
    count += 2 * trial.z.size();
    if (!res.finite) return std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < res.e_z.size(); ++k) {
      sse += w.z * w.z * res.e_z[k] * res.e_z[k] + w.pitch * w.pitch * res.e_pitch[k] * res.e_pitch[k];
    }
  }
  if (residual_count) *residual_count = count;
  return sse;
}

double FitStep(std::optional<effects::EffectId>) {
  // One step for every candidate, so no extension gains from integration accuracy alone; the
  // catalogue's bounds keep every admissible tyre mode and friction law stable at this step.
  return 0.004;
}

std::vector<FitTrial> WithFitStep(const std::vector<FitTrial>& trials,
                                  std::optional<effects::EffectId> effect) {
  std::vector<FitTrial> out = trials;
  for (FitTrial& t : out) {
    t.prepared.max_step = FitStep(effect);
    effects::CacheInputs(t.prepared);
  }
  return out;
}

FitResult FitModel(const std::vector<FitTrial>& training_in, std::optional<effects::EffectId> effect,
                   const LumpedParams& start, const ChannelWeights& weights,
                   const FitOptions& options) {
  PWSIM_DEMAND(!training_in.empty());
  const std::vector<FitTrial> training = WithFitStep(training_in, effect);

  Mapper map{effect, start, effect ? &effects::EffectParameters(*effect) : nullptr};
  const int size = map.Size();
  std::vector<double> u(static_cast<std::size_t>(size), 0.0);

  // Multi-start over the catalogue's starting points (Cartesian product), LM at the start.
  if (effect) {
    const auto& specs = *map.specs;
    std::vector<std::size_t> index(specs.size(), 0);
    double best = std::numeric_limits<double>::infinity();
    std::vector<double> best_u = u;
    while (true) {
      for (std::size_t j = 0; j < specs.size(); ++j) u[4 + j] = specs[j].starts[index[j]] / specs[j].scale;
      const double sse = WeightedSse(training, map.Params(u.data()), weights);
      if (sse < best) {
        best = sse;
        best_u = u;
      }
      std::size_t j = 0;
      while (j < specs.size() && ++index[j] == specs[j].starts.size()) index[j++] = 0;
      if (j == specs.size()) break;
    }
    u = best_u;
  }

  ceres::Problem problem;
  for (const FitTrial& trial : training) {
    auto* cost = new ceres::DynamicNumericDiffCostFunction<TrialFunctor, ceres::FORWARD>(
        new TrialFunctor{&trial, &map, weights});
    cost->AddParameterBlock(size);
    cost->SetNumResiduals(static_cast<int>(2 * trial.z.size()));
    problem.AddResidualBlock(cost, nullptr, u.data());
  }
  for (int j = 0; j < 4; ++j) {
    problem.SetParameterLowerBound(u.data(), j, -kLogBound);
    problem.SetParameterUpperBound(u.data(), j, kLogBound);
  }
  if (effect) {
    const auto& specs = *map.specs;
    for (std::size_t j = 0; j < specs.size(); ++j) {
      const int col = 4 + static_cast<int>(j);
      problem.SetParameterLowerBound(u.data(), col, specs[j].lower / specs[j].scale);
      problem.SetParameterUpperBound(u.data(), col, specs[j].upper / specs[j].scale);
    }
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = options.threads;
  solver.function_tolerance = options.function_tolerance;
  solver.parameter_tolerance = 1e-7;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  FitResult result;
  result.effect = effect;
  result.params = map.Params(u.data());
  if (effect) result.effect_values = effects::GetEffectValues(*effect, result.params.fx);
  result.parameter_count = size;
  result.iterations = static_cast<int>(summary.iterations.size());
  result.sse = WeightedSse(training, result.params, weights, &result.residual_count);
  const double n = static_cast<double>(result.residual_count);
  result.bic = n * std::log(std::max(1e-300, result.sse / n)) + size * std::log(n);
  return result;
}

}  // namespace pwsim::diagnose
