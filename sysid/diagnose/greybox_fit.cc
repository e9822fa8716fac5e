#include "sysid/diagnose/greybox_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "engine/check.h"
#include "sysid/diagnose/parallel_for.h"

namespace pwsim::diagnose {
namespace {

constexpr double kLogBound = 2.5;  ///< LM multipliers within e^±2.5 of the start
constexpr int kScreenIterations = 5;  ///< first-pass iterations when many starts are solved

/// u (optimiser vector) <-> ExtendedParams: 4 LM log multipliers, then each effect's values/scale.
struct Mapper {
  std::vector<effects::EffectId> effects;
  LumpedParams start;
  effects::EffectParams base_fx;  ///< settings not optimised (e.g. the cushion's load basis)

  int Size() const {
    int n = 4;
    for (effects::EffectId id : effects) n += static_cast<int>(effects::EffectParameters(id).size());
    return n;
  }

  effects::ExtendedParams Params(const double* u) const {
    effects::ExtendedParams p;
    p.fx = base_fx;
    p.lm.k_z = start.k_z * std::exp(u[0]);
    p.lm.c_z = start.c_z * std::exp(u[1]);
    p.lm.k_theta = start.k_theta * std::exp(u[2]);
    p.lm.c_theta = start.c_theta * std::exp(u[3]);
    int col = 4;
    for (effects::EffectId id : effects) {
      const auto& specs = effects::EffectParameters(id);
      std::vector<double> v(specs.size());
      for (std::size_t j = 0; j < v.size(); ++j) v[j] = u[col++] * specs[j].scale;
      effects::SetEffectValues(id, v, p.fx);
    }
    return p;
  }
};

/// Adds a trial's weighted squared residuals to `sse` (the criterion's one formula).
void AddWeightedSquares(const std::vector<double>& e_z, const std::vector<double>& e_pitch,
                        const ChannelWeights& w, double& sse) {
  for (std::size_t k = 0; k < e_z.size(); ++k)
    sse += w.z * w.z * e_z[k] * e_z[k] + w.pitch * w.pitch * e_pitch[k] * e_pitch[k];
}

/// Σ over trials of their weighted squared residuals, in trial order; ∞ when one is not finite.
double SumWeightedSquares(const std::vector<TrialResidual>& residuals, const ChannelWeights& w) {
  double sse = 0.0;
  for (const TrialResidual& res : residuals) {
    if (!res.finite) return std::numeric_limits<double>::infinity();
    AddWeightedSquares(res.e_z, res.e_pitch, w, sse);
  }
  return sse;
}

/// Every trial's residual for `params`, the simulations run concurrently (parallel_for.h).
std::vector<TrialResidual> ComputeResiduals(const std::vector<FitTrial>& trials,
                                            const effects::ExtendedParams& params) {
  std::vector<TrialResidual> out(trials.size());
  ParallelFor(trials.size(), [&](std::size_t i) { out[i] = ComputeResidual(trials[i], params); });
  return out;
}

/// The training trials at the optimiser's points, for one solve. Ceres asks for the residuals
/// (and Jacobian) of one trial's residual block at a time; the first request at a point
/// simulates every trial at it, and for a Jacobian every trial at every perturbed point, all
/// concurrently, and the other blocks read what it found. The Jacobian is the forward
/// difference of Ceres' DynamicNumericDiffCostFunction<FORWARD> to the bit: for u_j the step
///   δ_j = max(√ε, 10⁻⁶ |u_j|),   J_·j = (r(u + δ_j e_j) − r(u)) · (1 / δ_j),
/// r the weighted residuals (w_Z e_Z, w_θ e_θ interleaved). The last points' residuals are
/// kept: Ceres evaluates a candidate point, then, when it accepts it, the same point again with
/// its Jacobian, and the fit scores the point it ends at; neither is simulated again.
class TrialBatch {
 public:
  TrialBatch(const std::vector<FitTrial>& trials, const Mapper& map, const ChannelWeights& w)
      : trials_(trials), map_(map), w_(w) {}

  /// Trial `i`'s weighted residuals at u and, when `jacobian` is not null, its Jacobian
  /// (row-major, residual × parameter). False where a simulation is not finite.
  bool Evaluate(std::size_t i, const double* u, double* residuals, double* jacobian) {
    Point& p = At(u, jacobian != nullptr);
    if (!p.residuals[i].finite) return false;
    const std::vector<double> r = Weighted(p.residuals[i]);
    std::copy(r.begin(), r.end(), residuals);
    if (!jacobian) return true;
    if (!p.jacobian_finite[i]) return false;
    std::copy(p.jacobian[i].begin(), p.jacobian[i].end(), jacobian);
    return true;
  }

  /// WeightedSse of the training trials at u.
  double Sse(const double* u) { return SumWeightedSquares(At(u, false).residuals, w_); }

 private:
  struct Point {
    std::vector<double> u;
    std::vector<TrialResidual> residuals;        ///< per trial
    std::vector<std::vector<double>> jacobian;   ///< per trial, empty until asked
    std::vector<bool> jacobian_finite;
  };

  std::vector<double> Weighted(const TrialResidual& res) const {
    std::vector<double> r(2 * res.e_z.size());
    for (std::size_t k = 0; k < res.e_z.size(); ++k) {
      r[2 * k] = w_.z * res.e_z[k];
      r[2 * k + 1] = w_.pitch * res.e_pitch[k];
    }
    return r;
  }

  Point& At(const double* u, bool with_jacobian) {
    const std::size_t size = static_cast<std::size_t>(map_.Size());
    auto found = std::find_if(points_.begin(), points_.end(), [&](const Point& p) {
      return std::equal(p.u.begin(), p.u.end(), u);
    });
    if (found == points_.end()) {
      if (points_.size() == kKept) points_.erase(points_.begin());
      Point p;
      p.u.assign(u, u + size);
      p.residuals = ComputeResiduals(trials_, map_.Params(u));
      points_.push_back(std::move(p));
      found = points_.end() - 1;
    }
    if (with_jacobian && found->jacobian.empty()) AddJacobian(*found);
    return *found;
  }

  void AddJacobian(Point& p) const {
    const std::size_t size = p.u.size(), trials = trials_.size();
    std::vector<double> delta(size);
    for (std::size_t j = 0; j < size; ++j)
      delta[j] = std::max(std::sqrt(std::numeric_limits<double>::epsilon()), std::abs(p.u[j]) * 1e-6);
    // Every trial at every perturbed point, concurrently: slot (i, j), its weighted residuals.
    std::vector<std::vector<double>> moved(trials * size);
    std::vector<char> moved_finite(trials * size, 0);
    ParallelFor(trials * size, [&](std::size_t slot) {
      const std::size_t i = slot / size, j = slot % size;
      if (!p.residuals[i].finite) return;
      std::vector<double> u = p.u;
      u[j] = p.u[j] + delta[j];
      const TrialResidual res = ComputeResidual(trials_[i], map_.Params(u.data()));
      moved_finite[slot] = res.finite;
      if (res.finite) moved[slot] = Weighted(res);
    });
    p.jacobian.assign(trials, {});
    p.jacobian_finite.assign(trials, false);
    for (std::size_t i = 0; i < trials; ++i) {
      if (!p.residuals[i].finite) continue;
      const std::vector<double> r0 = Weighted(p.residuals[i]);
      std::vector<double>& jac = p.jacobian[i];
      jac.assign(r0.size() * size, 0.0);
      bool finite = true;
      for (std::size_t j = 0; j < size && finite; ++j) {
        finite = moved_finite[i * size + j] != 0;
        if (!finite) break;
        const std::vector<double>& r1 = moved[i * size + j];
        const double one_over_delta = 1.0 / delta[j];
        for (std::size_t row = 0; row < r0.size(); ++row) jac[row * size + j] = (r1[row] - r0[row]) * one_over_delta;
      }
      p.jacobian_finite[i] = finite;
    }
  }

  static constexpr std::size_t kKept = 3;
  const std::vector<FitTrial>& trials_;
  const Mapper& map_;
  ChannelWeights w_;
  std::vector<Point> points_;
};

/// Trial i's residual block, read from the batch.
class TrialCost : public ceres::CostFunction {
 public:
  TrialCost(TrialBatch* batch, std::size_t trial, int parameters, int residuals)
      : batch_(batch), trial_(trial) {
    mutable_parameter_block_sizes()->push_back(parameters);
    set_num_residuals(residuals);
  }
  bool Evaluate(double const* const* u, double* residuals, double** jacobians) const override {
    return batch_->Evaluate(trial_, u[0], residuals, jacobians ? jacobians[0] : nullptr);
  }

 private:
  TrialBatch* batch_;
  std::size_t trial_;
};

/// LM log multipliers (u[0..3]) for a tyre start. The start's LM is the base model's, which
/// saw tyres and suspension in series: the suspension is started stiffer so that with the
/// start's tyres in series it keeps the stiffness the data showed. Tyre j under wheel share
/// a_j (heave) and pitch share p_j (the GM's plane) adds compliance c_j a_j² to heave and
/// c_j p_j² to pitch: 1/K_s = 1/K - Σ c_j a_j², 1/K_θs = 1/K_θ - Σ c_j p_j²; the dampers are
/// raised in the same ratio. Unchanged where the tyres alone are softer than the start.
std::vector<double> SeriesStiffnessStart(const effects::PreparedTrial& trial, const Mapper& map,
                                         const std::vector<double>& u) {
  const effects::ExtendedParams p = map.Params(u.data());
  const Chair& chair = trial.chair;
  const int n = chair.wheel_count();
  effects::WheelArray alpha{}, x{};
  for (int i = 0; i < n; ++i) {
    alpha[static_cast<std::size_t>(i)] = chair.gm->alpha[static_cast<std::size_t>(i)];
    x[static_cast<std::size_t>(i)] = chair.wheels[static_cast<std::size_t>(i)].x;
  }
  const effects::WheelPlane share = effects::WeightedPlane(alpha, x, n);  // the GM's plane
  double heave = 0.0, pitch = 0.0;  // added compliances [m/N], [1/(N m)]
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double c = trial.is_caster[k] ? p.fx.caster_tyre_compliance : p.fx.drive_tyre_compliance;
    const double period = trial.is_caster[k] ? p.fx.caster_tyre_period : p.fx.drive_tyre_period;
    if (c <= 0.0 || period <= 0.0) continue;
    heave += c * share.z[k] * share.z[k];
    pitch += c * share.pitch[k] * share.pitch[k];
  }
  std::vector<double> out(u.begin(), u.begin() + 4);
  auto raise = [](double k, double added) {  // log ratio of the suspension to the seen stiffness
    if (!(added > 0.0)) return 0.0;  // rigid tyres: the start as it is
    const double inv = 1.0 / k - added;
    return inv > 0.2 / k ? std::log(1.0 / (k * inv)) : 0.0;
  };
  const double rz = raise(map.start.k_z * std::exp(u[0]), heave);
  const double rt = raise(map.start.k_theta * std::exp(u[2]), pitch);
  out[0] = std::clamp(u[0] + rz, -kLogBound, kLogBound);
  out[1] = std::clamp(u[1] + rz, -kLogBound, kLogBound);
  out[2] = std::clamp(u[2] + rt, -kLogBound, kLogBound);
  out[3] = std::clamp(u[3] + rt, -kLogBound, kLogBound);
  return out;
}

double Centre(const std::vector<double>& measured, const std::vector<double>& model,
              std::size_t count) {
  double sum = 0.0;
  for (std::size_t k = 0; k < count; ++k) sum += measured[k] - model[k];
  return sum / static_cast<double>(count);
}

}  // namespace

FitTrial MakeFitTrial(const effects::TrialRecord& record, const Chair& chair, double rest_window,
                      std::vector<double> accel) {
  FitTrial fit;
  fit.name = record.name;
  fit.prepared =
      effects::PrepareTrial(chair, record.terrain, record.load_kg, record.t, record.x, std::move(accel));
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
  const std::vector<TrialResidual> residuals = ComputeResiduals(trials, params);
  const double sse = SumWeightedSquares(residuals, w);
  const bool finite = std::all_of(residuals.begin(), residuals.end(),
                                  [](const TrialResidual& r) { return r.finite; });
  if (residual_count && finite) {
    *residual_count = 0;
    for (const FitTrial& trial : trials) *residual_count += 2 * trial.z.size();
  }
  return sse;
}

double FitStep(std::optional<effects::EffectId>) {
  // One grid for every candidate and for identification (SimulationOptions::dt), so the base
  // model is identification's and no extension gains from the discretisation alone.
  return SimulationOptions{}.dt;
}

std::vector<FitTrial> WithFitStep(const std::vector<FitTrial>& trials,
                                  std::optional<effects::EffectId> effect) {
  std::vector<FitTrial> out = trials;
  const double step = FitStep(effect);
  ParallelFor(out.size(), [&](std::size_t i) {
    effects::PreparedTrial& t = out[i].prepared;
    if (t.step == step && t.cache_step == step) return;  // cached already (CacheInputs is pure)
    t.step = step;
    effects::CacheInputs(t);
  });
  return out;
}

FitResult FitModel(const std::vector<FitTrial>& training, std::optional<effects::EffectId> effect,
                   const LumpedParams& start, const ChannelWeights& weights,
                   const FitOptions& options) {
  effects::ExtendedParams p;
  p.lm = start;
  std::vector<effects::EffectId> list;
  if (effect) list.push_back(*effect);
  return FitModelJoint(training, list, p, weights, options);
}

FitResult FitModelJoint(const std::vector<FitTrial>& training_in,
                        const std::vector<effects::EffectId>& effect_list,
                        const effects::ExtendedParams& start, const ChannelWeights& weights,
                        const FitOptions& options) {
  PWSIM_DEMAND(!training_in.empty());
  const std::optional<effects::EffectId> last =
      effect_list.empty() ? std::nullopt : std::optional<effects::EffectId>(effect_list.back());
  const std::vector<FitTrial> training = WithFitStep(training_in, last);

  Mapper map{effect_list, start.lm, start.fx};
  const int size = map.Size();
  std::vector<double> u(static_cast<std::size_t>(size), 0.0);
  int last_col = 4;
  {
    int col = 4;
    for (std::size_t e = 0; e < effect_list.size(); ++e) {
      const auto& specs = effects::EffectParameters(effect_list[e]);
      const std::vector<double> values = effects::GetEffectValues(effect_list[e], start.fx);
      if (e + 1 == effect_list.size()) last_col = col;
      for (std::size_t j = 0; j < specs.size(); ++j, ++col)
        u[static_cast<std::size_t>(col)] = std::clamp(values[j], specs[j].lower, specs[j].upper) / specs[j].scale;
    }
  }

  // Multi-start of the last effect over the catalogue's starting points (Cartesian product)
  // and over its family's discrete members; the starts with the lowest error are solved and
  // the best fit kept. One start in general; for the tyres the best two stiff starts (c_t held
  // at 0: their periods lie in different basins more often than not) and the best compliant
  // start of each caster-compliance rung (a start's error favours the stiff rungs, whose fits
  // stay near the base model, over a soft tyre's basin); for the stops the best start of each
  // member. (Solving the best three tyre starts regardless of kind was tried: on the
  // independent truth it found no better basin and added a spurious cause, at twice the time.)
  std::vector<std::vector<double>> starts;  // solved, each; the lowest training error is kept
  std::vector<effects::EffectParams> bases;  // their discrete settings (cushion basis, rebound stops)
  std::vector<bool> stiff;                  // stiff-tyre starts: compliances held at zero
  if (last && options.multi_start) {
    const auto& specs = effects::EffectParameters(*last);
    const bool cushion = *last == effects::EffectId::kCushionCompliance;
    const bool stops = *last == effects::EffectId::kNonlinearStiffness;
    const std::vector<double> lm_start(u.begin(), u.begin() + 4);
    const bool tyre = *last == effects::EffectId::kTyreCompliance;
    struct Scored {
      double score;
      std::vector<double> u;
      effects::EffectParams base;
    };
    std::array<std::vector<Scored>, 2> scored;  // by kind: stiff, compliant
    // The family's discrete members are multi-started: the cushion's load basis (per wheel or
    // whole chair; the better start solved), the stops in compression only or in rebound as
    // well (the best start of each solved: a start's error hardly tells them apart).
    for (int basis = 0; basis < (cushion || stops ? 2 : 1); ++basis) {
      if (cushion) map.base_fx.cushion_whole_chair = basis == 1;
      if (stops) map.base_fx.bump_rebound = basis == 1;
      std::vector<std::size_t> index(specs.size(), 0);
      while (true) {
        for (std::size_t j = 0; j < specs.size(); ++j)
          u[static_cast<std::size_t>(last_col) + j] = specs[j].starts[index[j]] / specs[j].scale;
        // Compliant tyres in series soften the chair: each tyre start is tried both with the
        // base LM and with the suspension raised so that the series pair keeps the stiffness
        // the data showed (SeriesStiffnessStart).
        std::copy(lm_start.begin(), lm_start.end(), u.begin());
        const bool series = tyre && effect_list.size() == 1;
        const std::vector<double> raised =
            series ? SeriesStiffnessStart(training.front().prepared, map, u) : lm_start;
        for (int lm = 0; lm < (raised != lm_start ? 2 : 1); ++lm) {
          std::copy(lm == 0 ? lm_start.begin() : raised.begin(), lm == 0 ? lm_start.end() : raised.end(),
                    u.begin());
          const double sse = WeightedSse(training, map.Params(u.data()), weights);
          const double score = std::isfinite(sse) ? sse : std::numeric_limits<double>::infinity();
          const effects::EffectParams fx = map.Params(u.data()).fx;
          // Kinds solved apart: stiff and compliant tyres; stops in compression only and in
          // rebound as well (a rebound start without stops is the compression one again).
          if (stops && fx.bump_rebound && fx.bump_gain <= 0.0) continue;
          const bool compliant = tyre && (fx.caster_tyre_compliance > 0.0 || fx.drive_tyre_compliance > 0.0);
          const std::size_t kind = compliant || (stops && fx.bump_rebound) ? 1 : 0;
          scored[kind].push_back({score, u, map.base_fx});
        }
        std::size_t j = 0;
        while (j < specs.size() && ++index[j] == specs[j].starts.size()) index[j++] = 0;
        if (j == specs.size()) break;
      }
    }
    for (std::size_t kind = 0; kind < 2; ++kind) {
      // The lowest errors first; of equal errors (a non-finite one too) the first tried.
      std::stable_sort(scored[kind].begin(), scored[kind].end(),
                       [](const Scored& a, const Scored& b) { return a.score < b.score; });
      const std::size_t keep = tyre && kind == 0 ? 2 : 1;
      std::vector<double> rungs;  // compliant tyres: caster compliances already taken
      for (std::size_t k = 0, taken = 0; k < scored[kind].size(); ++k) {
        if (tyre && kind == 1) {
          // The best start of each caster-compliance rung: the start's error favours the
          // stiffer rungs, whose fits stay near the base model, over a soft tyre's basin.
          const double c = map.Params(scored[kind][k].u.data()).fx.caster_tyre_compliance;
          if (std::find(rungs.begin(), rungs.end(), c) != rungs.end()) continue;
          rungs.push_back(c);
        } else if (taken == keep) {
          break;
        }
        ++taken;
        starts.push_back(scored[kind][k].u);
        bases.push_back(scored[kind][k].base);
        stiff.push_back(tyre && kind == 0);
      }
    }
  }

  if (starts.empty()) {
    starts.push_back(u);
    bases.push_back(map.base_fx);
    stiff.push_back(false);
  }
  // Columns of the last effect's tyre compliances (held at zero when a stiff start is solved:
  // the stiff tyre is its own member of the family, a filter of the ground with no reaction).
  std::vector<int> compliance_cols;
  if (last && *last == effects::EffectId::kTyreCompliance) {
    const auto& specs = effects::EffectParameters(*last);
    for (std::size_t j = 0; j < specs.size(); ++j)
      if (specs[j].name.find("compliance") != std::string::npos)
        compliance_cols.push_back(last_col + static_cast<int>(j));
  }
  // One solve from x: its iterations and the training error where it ends.
  struct Solved {
    int iterations;
    double sse;
  };
  auto solve = [&](std::vector<double>& x, bool hold_compliance, int max_iterations) {
    TrialBatch batch(training, map, weights);
    ceres::Problem problem;
    for (std::size_t i = 0; i < training.size(); ++i)
      problem.AddResidualBlock(new TrialCost(&batch, i, size, static_cast<int>(2 * training[i].z.size())),
                               nullptr, x.data());
    if (hold_compliance && !compliance_cols.empty())
      problem.SetManifold(x.data(), new ceres::SubsetManifold(size, compliance_cols));
    for (int j = 0; j < 4; ++j) {
      problem.SetParameterLowerBound(x.data(), j, -kLogBound);
      problem.SetParameterUpperBound(x.data(), j, kLogBound);
    }
    int col = 4;
    for (effects::EffectId id : effect_list) {
      for (const effects::ParamSpec& spec : effects::EffectParameters(id)) {
        problem.SetParameterLowerBound(x.data(), col, spec.lower / spec.scale);
        problem.SetParameterUpperBound(x.data(), col, spec.upper / spec.scale);
        ++col;
      }
    }
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_QR;
    solver.max_num_iterations = max_iterations;
    solver.num_threads = 1;  // the batch runs the simulations concurrently
    solver.function_tolerance = options.function_tolerance;
    solver.parameter_tolerance = 1e-7;
    solver.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    return Solved{static_cast<int>(summary.iterations.size()), batch.Sse(x.data())};
  };
  double best_sse = std::numeric_limits<double>::infinity();
  int iterations = 0;
  effects::EffectParams basis = map.base_fx;
  // More than three starts (the tyres' stiff starts and compliance rungs): each is solved a
  // few iterations, the best then solved on; the solves are the cost of a fit.
  const bool screened = starts.size() > 3;
  const int first_pass = screened ? std::min(options.max_iterations, kScreenIterations) : options.max_iterations;
  bool held = false;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    map.base_fx = bases[k];
    std::vector<double> x = starts[k];
    const Solved solved = solve(x, stiff[k], first_pass);
    if (k == 0 || solved.sse < best_sse) {  // the first of equal errors
      best_sse = solved.sse;
      u = x;
      iterations = solved.iterations;
      basis = bases[k];
      held = stiff[k];
    }
  }
  map.base_fx = basis;
  if (screened && options.max_iterations > first_pass) {
    std::vector<double> x = u;
    const Solved solved = solve(x, held, options.max_iterations - first_pass);
    iterations += solved.iterations;
    if (solved.sse <= best_sse) u = x;
  }

  FitResult result;
  result.effects = effect_list;
  result.params = map.Params(u.data());
  for (effects::EffectId id : effect_list) {
    const std::vector<double> v = effects::GetEffectValues(id, result.params.fx);
    result.effect_values.insert(result.effect_values.end(), v.begin(), v.end());
  }
  result.parameter_count = size;
  result.iterations = iterations;
  result.sse = WeightedSse(training, result.params, weights, &result.residual_count);
  const double n = static_cast<double>(result.residual_count);
  result.bic = n * std::log(std::max(1e-300, result.sse / n)) + size * std::log(n);
  return result;
}

}  // namespace pwsim::diagnose
