#include "sysid/diagnose/greybox_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "engine/check.h"
#include "sysid/diagnose/noise_model.h"
#include "sysid/diagnose/parallel_for.h"

namespace pwsim::diagnose {
namespace {

constexpr double kLogBound = 2.5;  ///< LM multipliers within e^±2.5 of the start
constexpr int kScreenIterations = 10;  ///< first-pass iterations when many starts are solved

/// u (optimiser vector) <-> ExtendedParams: 4 LM log multipliers, then each effect's values/scale.
struct Mapper {
  std::vector<effects::EffectId> effects;
  LumpedParams start;
  effects::EffectParams base_fx;  ///< settings not optimised (each family's member)

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

}  // namespace

std::vector<TrialResidual> ComputeResiduals(const std::vector<FitTrial>& trials,
                                            const effects::ExtendedParams& params) {
  std::vector<TrialResidual> out(trials.size());
  ParallelFor(trials.size(), [&](std::size_t i) { out[i] = ComputeResidual(trials[i], params); });
  return out;
}

namespace {

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
  /// `held`: columns held at their start (a SubsetManifold ignores their Jacobian columns,
  /// which are left 0 and not simulated).
  TrialBatch(const std::vector<FitTrial>& trials, const Mapper& map, const ChannelWeights& w,
             const std::vector<int>& held = {})
      : trials_(trials), map_(map), w_(w), held_(held) {}

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
      if (!p.residuals[i].finite || Held(j)) return;
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
        if (Held(j)) continue;  // its column stays 0
        finite = moved_finite[i * size + j] != 0;
        if (!finite) break;
        const std::vector<double>& r1 = moved[i * size + j];
        const double one_over_delta = 1.0 / delta[j];
        for (std::size_t row = 0; row < r0.size(); ++row) jac[row * size + j] = (r1[row] - r0[row]) * one_over_delta;
      }
      p.jacobian_finite[i] = finite;
    }
  }

  bool Held(std::size_t column) const {
    return std::find(held_.begin(), held_.end(), static_cast<int>(column)) != held_.end();
  }

  static constexpr std::size_t kKept = 3;
  const std::vector<FitTrial>& trials_;
  const Mapper& map_;
  ChannelWeights w_;
  std::vector<int> held_;
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

/// LM log multipliers (u[0..3]) for a tyre start. The start's LM is the base model's, or that
/// of the causes found before (a joint fit), which saw tyres and suspension in series alike:
/// the suspension is started stiffer so that with the start's tyres in series it keeps the
/// stiffness the data showed. Tyre j under wheel share a_j (heave) and pitch share p_j (the
/// GM's plane) adds compliance c_j a_j² to heave and c_j p_j² to pitch: 1/K_s = 1/K - Σ c_j a_j²,
/// 1/K_θs = 1/K_θ - Σ c_j p_j²; the dampers are raised in the same ratio. Unchanged where the
/// tyres alone are softer than the start.
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
  const effects::WheelArray compliance = effects::TyreCompliances(p.fx, trial);
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double c = compliance[k];
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

/// e − Q Qᵀ e over the first `modes` columns of `basis` (samples × columns, column-major).
void RemoveDriftTerms(const std::vector<double>& basis, std::size_t modes, std::vector<double>& e) {
  const std::size_t n = e.size();
  for (std::size_t k = 0; k < modes; ++k) {
    const double* q = basis.data() + k * n;
    double c = 0.0;
    for (std::size_t i = 0; i < n; ++i) c += q[i] * e[i];
    for (std::size_t i = 0; i < n; ++i) e[i] -= c * q[i];
  }
}

/// The level of measured − model over the first `count` samples (the initial rest): Huber's
/// location (noise_model.h), so that outliers the replacement left there (a burst of several
/// samples) do not shift the whole trial, as they would shift a mean.
double Centre(const std::vector<double>& measured, const std::vector<double>& model,
              std::size_t count) {
  std::vector<double> difference(count);
  for (std::size_t k = 0; k < count; ++k) difference[k] = measured[k] - model[k];
  return HuberLocation(difference);
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
  fit.t = record.t;
  return fit;
}

std::size_t DriftModes(double duration_s, double slow_scale_s, std::size_t samples) {
  if (!(slow_scale_s > 0.0) || !(duration_s > 0.0)) return 0;
  const double below_knee = 1.0 + std::floor(duration_s / (std::numbers::pi * slow_scale_s));
  const std::size_t cap = std::max<std::size_t>(1, std::min(kMaxDriftModes, samples / 10));
  return std::min(cap, static_cast<std::size_t>(below_knee));
}

void SetDriftTerms(FitTrial& trial, double slow_scale_z_s, double slow_scale_pitch_s) {
  const std::size_t n = trial.t.size();
  PWSIM_DEMAND(n == trial.z.size() && n >= 2);
  const double t0 = trial.t.front(), duration = trial.t.back() - t0;
  DriftTerms& d = trial.drift;
  d.modes_z = DriftModes(duration, slow_scale_z_s, n);
  d.modes_pitch = DriftModes(duration, slow_scale_pitch_s, n);
  const std::size_t modes = std::max(d.modes_z, d.modes_pitch);
  d.basis.assign(n * modes, 0.0);
  for (std::size_t k = 0; k < modes; ++k) {
    double* q = d.basis.data() + k * n;
    for (std::size_t i = 0; i < n; ++i) q[i] = std::cos(std::numbers::pi * static_cast<double>(k) * (trial.t[i] - t0) / duration);
    for (int pass = 0; pass < 2; ++pass) {  // modified Gram–Schmidt, twice
      for (std::size_t j = 0; j < k; ++j) {
        const double* p = d.basis.data() + j * n;
        double c = 0.0;
        for (std::size_t i = 0; i < n; ++i) c += p[i] * q[i];
        for (std::size_t i = 0; i < n; ++i) q[i] -= c * p[i];
      }
    }
    double norm = 0.0;
    for (std::size_t i = 0; i < n; ++i) norm += q[i] * q[i];
    norm = std::sqrt(norm);
    PWSIM_DEMAND(norm > 0.0);
    for (std::size_t i = 0; i < n; ++i) q[i] /= norm;
  }
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
  const DriftTerms& drift = trial.drift;
  const double oz = drift.modes_z > 0 ? 0.0 : Centre(trial.z, res.model.z, trial.rest_samples);
  const double op = drift.modes_pitch > 0 ? 0.0 : Centre(trial.pitch, res.model.pitch, trial.rest_samples);
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
  // The drift terms' least-squares share leaves the residual and joins the model's output.
  if (drift.modes_z > 0) {
    RemoveDriftTerms(drift.basis, drift.modes_z, res.e_z);
    for (std::size_t k = 0; k < n; ++k) res.z_model[k] = trial.z[k] - res.e_z[k];
  }
  if (drift.modes_pitch > 0) {
    RemoveDriftTerms(drift.basis, drift.modes_pitch, res.e_pitch);
    for (std::size_t k = 0; k < n; ++k) res.pitch_model[k] = trial.pitch[k] - res.e_pitch[k];
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

namespace {

/// One start of a multi-start: the optimiser vector, the member it belongs to, the settings
/// not optimised (its member's), the parameters held, its training error before solving.
struct Start {
  std::vector<double> u;
  const effects::FamilyMember* member{nullptr};  ///< null: the given start, no multi-start
  effects::EffectParams base_fx;
  std::vector<int> held;  ///< columns of u held at their start
  double score{0.0};
};

/// The largest swing of the measured pitch from its rest value over `trials` [rad].
double LargestPitchSwing(const std::vector<FitTrial>& trials) {
  double largest = 0.0;
  for (const FitTrial& t : trials) {
    double rest = 0.0;
    for (std::size_t k = 0; k < t.rest_samples; ++k) rest += t.pitch[k];
    rest /= static_cast<double>(t.rest_samples);
    for (double p : t.pitch) largest = std::max(largest, std::abs(p - rest));
  }
  return largest;
}

/// Every start of every member of `family` (the last effect of `map`, its values at column
/// `col` of `u`), scored by its training error; the best of each member chosen by the member's
/// rule (FamilyMember: `solved`, `rung`, `ranked_with_previous`), in member order.
std::vector<Start> ChooseStarts(const std::vector<FitTrial>& training, Mapper map,
                                const effects::EffectFamily& family, std::vector<double> u, int col,
                                const ChannelWeights& weights, const FitOptions& options) {
  const std::vector<double> lm_start(u.begin(), u.begin() + 4);
  std::vector<std::vector<Start>> rankings;  // one per member, or per members ranked together
  std::vector<const effects::FamilyMember*> rule;
  for (const effects::FamilyMember& member : family.members) {
    if (!member.ranked_with_previous || rankings.empty()) {
      rankings.emplace_back();
      rule.push_back(&member);
    }
    effects::CopyMember(family.id, member.setting, map.base_fx.member);
    std::vector<int> held;
    for (std::size_t j : member.held) held.push_back(col + static_cast<int>(j));
    for (const std::vector<double>& values : member.starts) {
      for (std::size_t j = 0; j < values.size(); ++j)
        u[static_cast<std::size_t>(col) + j] = StartWithin(values[j], family.params[j], options) / family.params[j].scale;
      std::copy(lm_start.begin(), lm_start.end(), u.begin());
      const std::vector<double> raised =
          member.series_start ? SeriesStiffnessStart(training.front().prepared, map, u) : lm_start;
      for (int lm = 0; lm < (raised != lm_start ? 2 : 1); ++lm) {
        std::copy(lm == 0 ? lm_start.begin() : raised.begin(), lm == 0 ? lm_start.end() : raised.end(), u.begin());
        const double sse = WeightedSse(training, map.Params(u.data()), weights);
        const double score = std::isfinite(sse) ? sse : std::numeric_limits<double>::infinity();
        rankings.back().push_back({u, &member, map.base_fx, held, score});
      }
    }
  }
  std::vector<Start> chosen;
  for (std::size_t r = 0; r < rankings.size(); ++r) {
    // The lowest errors first; of equal errors (a non-finite one too) the first tried.
    std::stable_sort(rankings[r].begin(), rankings[r].end(),
                     [](const Start& a, const Start& b) { return a.score < b.score; });
    std::vector<double> rungs;  // start values of the rung parameter already taken
    int taken = 0;
    for (Start& s : rankings[r]) {
      if (rule[r]->rung >= 0) {
        const double value = s.u[static_cast<std::size_t>(col + rule[r]->rung)];
        if (std::find(rungs.begin(), rungs.end(), value) != rungs.end()) continue;
        rungs.push_back(value);
      } else if (taken == rule[r]->solved) {
        break;
      }
      ++taken;
      chosen.push_back(std::move(s));
    }
  }
  return chosen;
}

/// One solve: its iterations and the training error where it ends.
struct Solved {
  int iterations;
  double sse;
};

/// Solves `x` (Ceres, within the LM's and the effects' bounds, the `held` columns fixed) for at
/// most `max_iterations`; the trials' simulations run concurrently in a TrialBatch.
Solved Solve(const std::vector<FitTrial>& training, const Mapper& map, const ChannelWeights& weights,
             const FitOptions& options, const std::vector<int>& held, std::vector<double>& x,
             int max_iterations) {
  const int size = map.Size();
  TrialBatch batch(training, map, weights, held);
  ceres::Problem problem;
  for (std::size_t i = 0; i < training.size(); ++i)
    problem.AddResidualBlock(new TrialCost(&batch, i, size, static_cast<int>(2 * training[i].z.size())),
                             nullptr, x.data());
  if (!held.empty()) problem.SetManifold(x.data(), new ceres::SubsetManifold(size, held));
  for (int j = 0; j < 4; ++j) {
    problem.SetParameterLowerBound(x.data(), j, -kLogBound);
    problem.SetParameterUpperBound(x.data(), j, kLogBound);
  }
  int col = 4;
  for (effects::EffectId id : map.effects) {
    for (const effects::ParamSpec& spec : effects::EffectParameters(id)) {
      const auto [lower, upper] = FitBounds(spec, options);
      problem.SetParameterLowerBound(x.data(), col, lower / spec.scale);
      problem.SetParameterUpperBound(x.data(), col, upper / spec.scale);
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
  // No projected line search along the trust-region step, and non-monotonic steps instead.
  // Ceres runs the search by default on a problem with bounds: an Armijo search with cubic
  // interpolation, which asks for the gradient at every trial step, i.e. a whole Jacobian (one
  // simulation per trial and free parameter): 81 % of the simulations of the README's diagnose
  // example. Without it the step is the trust region's, clamped to the bounds by Ceres' Plus;
  // a step that raises the cost shrinks the region. The search had made each iteration go
  // further: the iteration budgets are twice what they were with it (FitOptions, the screens),
  // and a step may raise the cost above the best so far within Ceres' non-monotonic window
  // (use_nonmonotonic_steps), which takes the fit along the narrow valleys that the line
  // search used to follow (two causes jointly, a suspension in series with tyres). The README
  // example: 115 479 simulations and 102 CPU-s before, 24 CPU-s now (docs/diagnosis.md).
  solver.max_num_line_search_step_size_iterations = 0;
  solver.use_nonmonotonic_steps = true;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  return Solved{static_cast<int>(summary.iterations.size()), batch.Sse(x.data())};
}

/// The best of a multi-start: its optimiser vector, its start, the iterations, the training
/// error.
struct Best {
  LumpedParams origin;  ///< the LM that u's first four columns are relative to
  std::vector<double> u;
  std::optional<Start> start;  ///< empty: nothing solved yet
  int iterations{0};
  double sse{std::numeric_limits<double>::infinity()};
};

/// Solves each of `starts` (more than three: each a few iterations, then the best of each member
/// solved on, so that the laws are compared where their fits end rather than by their first
/// steps) and returns the lowest training error's (the first of equal errors); each solve is
/// appended to `solved`.
Best SolveStarts(const std::vector<FitTrial>& training, Mapper map, const ChannelWeights& weights,
                 const FitOptions& options, const std::vector<Start>& starts,
                 std::vector<FitResult::SolvedStart>& solved) {
  const bool screened = starts.size() > 3;
  const int first_pass = screened ? std::min(options.max_iterations, kScreenIterations) : options.max_iterations;
  std::vector<Best> members;  // the best first pass of each member, in the order they first come
  for (const Start& s : starts) {
    map.base_fx = s.base_fx;
    std::vector<double> x = s.u;
    const Solved it = Solve(training, map, weights, options, s.held, x, first_pass);
    solved.push_back({s.member ? s.member->name : "", s.base_fx.member.kinematics, it.sse});
    auto same = std::find_if(members.begin(), members.end(), [&](const Best& b) { return b.start->member == s.member; });
    if (same == members.end()) {
      members.push_back(Best{map.start, x, s, it.iterations, it.sse});
    } else if (it.sse < same->sse) {  // the first of equal errors
      *same = Best{map.start, x, s, it.iterations, it.sse};
    }
  }
  Best best;
  for (Best& m : members) {
    if (screened && options.max_iterations > first_pass) {
      map.base_fx = m.start->base_fx;
      std::vector<double> x = m.u;
      const Solved more = Solve(training, map, weights, options, m.start->held, x, options.max_iterations - first_pass);
      m.iterations += more.iterations;
      if (more.sse <= m.sse) {
        m.u = x;
        m.sse = more.sse;
      }
    }
    if (!best.start || m.sse < best.sse) best = m;
  }
  return best;
}

}  // namespace

std::pair<double, double> FitBounds(const effects::ParamSpec& spec, const FitOptions& options) {
  double lower = spec.lower, upper = spec.upper;
  for (const FitOptions::NarrowedRange& r : options.narrowed) {
    if (r.name != spec.name) continue;
    lower = std::max(lower, r.lower);
    upper = std::min(upper, r.upper);
  }
  if (!(lower <= upper)) return {spec.lower, spec.upper};  // disjoint: the measurement is ignored
  return {lower, upper};
}

double StartWithin(double value, const effects::ParamSpec& spec, const FitOptions& options) {
  const auto [lower, upper] = FitBounds(spec, options);
  if (value >= lower && value <= upper) return value;
  if (lower == spec.lower && upper == spec.upper) return std::clamp(value, lower, upper);
  return 0.5 * (lower + upper);
}

LumpedParams PlausibleLm(const Chair& chair, const LumpedParams& lm, double load_kg) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  auto plausible = [&](const Mode& mode) { return std::isfinite(mode.omega_n) && mode.omega_n >= kTwoPi * 0.3; };
  const Chair paper = MakeTableOneChair();
  const Mode paper_heave = HeaveMode(paper, 50.0), paper_pitch = PitchMode(paper, 50.0);
  Chair given = chair;
  given.lm = lm;
  LumpedParams out = lm;
  if (!plausible(HeaveMode(given, load_kg))) {
    const double mass = MovingMass(chair, load_kg);
    out.k_z = mass * paper_heave.omega_n * paper_heave.omega_n;
    out.c_z = 2.0 * paper_heave.zeta * std::sqrt(out.k_z * mass);
  }
  if (!plausible(PitchMode(given, load_kg))) {
    const double inertia = PitchInertia(chair, load_kg);
    out.k_theta = inertia * paper_pitch.omega_n * paper_pitch.omega_n;
    out.c_theta = 2.0 * paper_pitch.zeta * std::sqrt(out.k_theta * inertia);
  }
  return out;
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
  // The given start: LM at start.lm, every effect at its values in start.fx (within bounds).
  std::vector<double> u(4, 0.0);
  int last_col = 4;
  for (effects::EffectId id : effect_list) {
    last_col = static_cast<int>(u.size());
    const auto& specs = effects::EffectParameters(id);
    const std::vector<double> values = effects::GetEffectValues(id, start.fx);
    for (std::size_t j = 0; j < specs.size(); ++j)
      u.push_back(StartWithin(values[j], specs[j], options) / specs[j].scale);
  }
  // Multi-start of the last effect over its family's members x starts (only its own member
  // changes: the earlier effects keep theirs), or the given start alone. Past the small-angle
  // limit the whole multi-start is run under exact kinematics as well, and the lower final
  // training error kept (the small-angle one of equal errors).
  std::vector<effects::Kinematics> kinematics{start.fx.member.kinematics};
  if (last && options.multi_start && kinematics.front() == effects::Kinematics::kSmallAngle &&
      LargestPitchSwing(training) > options.small_angle_limit)
    kinematics.push_back(effects::Kinematics::kExact);
  // The LMs the multi-start runs from: start.lm, and the plausible LM where start.lm is not.
  std::vector<LumpedParams> origins{start.lm};
  if (last && options.multi_start) {
    double load_kg = 0.0;
    for (const FitTrial& t : training) load_kg += t.prepared.load_kg / static_cast<double>(training.size());
    const LumpedParams plausible = PlausibleLm(training.front().prepared.chair, start.lm, load_kg);
    if (plausible.k_z != start.lm.k_z || plausible.k_theta != start.lm.k_theta) origins.push_back(plausible);
  }
  FitResult result;
  Best best;
  for (const LumpedParams& origin : origins) {
    map.start = origin;
    for (effects::Kinematics geometry : kinematics) {
      map.base_fx.member.kinematics = geometry;
      const std::vector<Start> starts =
          last && options.multi_start ? ChooseStarts(training, map, effects::Family(*last), u, last_col, weights, options)
                                      : std::vector<Start>{Start{u, nullptr, start.fx, {}, 0.0}};
      Best fit = SolveStarts(training, map, weights, options, starts, result.starts);
      if (!best.start || fit.sse < best.sse) best = std::move(fit);
    }
  }
  map.start = best.origin;
  map.base_fx = best.start->base_fx;
  u = best.u;
  result.iterations = best.iterations;
  result.effects = effect_list;
  result.member = best.start->member ? best.start->member->name : "";
  result.params = map.Params(u.data());
  for (effects::EffectId id : effect_list) {
    const std::vector<double> v = effects::GetEffectValues(id, result.params.fx);
    result.effect_values.insert(result.effect_values.end(), v.begin(), v.end());
  }
  result.parameter_count = map.Size();
  result.sse = WeightedSse(training, result.params, weights, &result.residual_count);
  const double n = static_cast<double>(result.residual_count);
  result.bic = n * std::log(std::max(1e-300, result.sse / n)) + result.parameter_count * std::log(n);
  return result;
}

}  // namespace pwsim::diagnose
