#pragma once
// Grey-box output-error fit of the extended model (sysid/effects/) on measured trials with
// Ceres Solver: the lumped model's K_Z, C_Z, K_θ, C_θ (log multipliers) are re-identified
// together with one effect's parameters (none: the base model). The criterion is the
// simulation error of both channels, each centred on the trial's initial rest window (as
// the paper's Fig. 5; the level is Huber's location, noise_model.h, robust to a burst of
// outliers left there) and weighted by 1/std of the measured channel over the training set.
// Where the measurement drifts (noise_model.h), each trial carries slow drift terms instead
// of the centring (DriftTerms below), nuisance parameters eliminated in closed form.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/chair.h"
#include "sysid/effects/effect_catalog.h"
#include "sysid/effects/effect_model.h"

namespace pwsim::diagnose {

/// Slow drift terms of a trial (separable least squares: nuisance parameters eliminated in
/// closed form). A channel with K > 0 terms is compared with the model plus its least-squares
/// combination of the first K cosines over the trial,
///   φ_k(t) = cos(π k (t − t₀) / T),  k = 0 … K − 1,  T = t_last − t₀,
/// i.e. its residual is e ← e − Q Qᵀ e, Q their orthonormal basis over the trial's samples
/// (modified Gram–Schmidt, twice). φ₀ is the trial's offset, which then replaces the centring
/// on the rest window. Cosine k has the frequency k / (2T): the terms span what lies below
/// k_max / (2T), and a drift there (a wandering marker, a slow calibration change) can neither
/// hide an effect nor be taken for one. K = 0: the rest-window centring, as without drift.
struct DriftTerms {
  std::size_t modes_z{0}, modes_pitch{0};  ///< K of each channel
  std::vector<double> basis;               ///< Q, column-major: samples × max(K)
};

/// K for a slow part of scale `slow_scale_s` (noise_model.h: the Gaussian smooth whose transfer
/// has its knee at 1/(2π s_d)) over a trial lasting `duration_s`: the cosines below the knee,
/// K = 1 + ⌊T / (π s_d)⌋, at most kMaxDriftModes and a tenth of the samples; 0 for s_d ≤ 0.
std::size_t DriftModes(double duration_s, double slow_scale_s, std::size_t samples);
inline constexpr std::size_t kMaxDriftModes = 48;

/// One trial ready for fitting.
struct FitTrial {
  std::string name;
  effects::PreparedTrial prepared;
  std::vector<double> z;      ///< [m] measured
  std::vector<double> pitch;  ///< [rad] measured
  double speed{0.0};          ///< [m/s] nominal
  std::size_t rest_samples{1};  ///< samples of the initial centring window (≥ 1)
  std::vector<double> t;        ///< [s] sample times (for the drift terms)
  DriftTerms drift;             ///< none: centred on the rest window
};

/// Sets the trial's drift terms for the slow parts of scale `slow_scale_z_s` (Z) and
/// `slow_scale_pitch_s` (θ) [s]; 0: none for that channel.
void SetDriftTerms(FitTrial& trial, double slow_scale_z_s, double slow_scale_pitch_s);

/// Builds a FitTrial from a record; `chair` must have gm (its lm is not used here). The
/// longitudinal acceleration is estimated from the record's x unless `accel` is given.
FitTrial MakeFitTrial(const effects::TrialRecord& record, const Chair& chair,
                      double rest_window = 0.25, std::vector<double> accel = {});

struct ChannelWeights {
  double z{1.0};      ///< [1/m]
  double pitch{1.0};  ///< [1/rad]
};
/// 1/std of each measured channel pooled over `trials` (each trial centred on its mean).
ChannelWeights MakeChannelWeights(const std::vector<FitTrial>& trials);

/// Centred model output and residual of one trial for `params`.
struct TrialResidual {
  effects::ModelOutput model;   ///< raw model output
  std::vector<double> z_model;  ///< model + initial offset (comparable with measured)
  std::vector<double> pitch_model;
  std::vector<double> e_z;      ///< measured - z_model [m]
  std::vector<double> e_pitch;  ///< [rad]
  bool finite{true};
};
TrialResidual ComputeResidual(const FitTrial& trial, const effects::ExtendedParams& params);
/// Every trial's residual for `params`, the simulations run concurrently (parallel_for.h).
std::vector<TrialResidual> ComputeResiduals(const std::vector<FitTrial>& trials,
                                            const effects::ExtendedParams& params);

struct FitOptions {
  int max_iterations{30};  ///< Ceres iterations, rejected steps included (greybox_fit.cc Solve)
  double function_tolerance{1e-6};
  /// FitModelJoint multi-starts its last effect; false: every effect starts from `start.fx`
  /// (a refinement of a previous fit).
  bool multi_start{true};
  /// [rad] Where the measured pitch swings further than this from its rest value in a training
  /// trial, the multi-start is run under exact rigid-body kinematics as well
  /// (effect_model.h, Kinematics::kExact); the small-angle pitch stiffness is 3.9 % off at 0.2.
  double small_angle_limit{0.2};
  /// Parameters whose range another measurement narrows (the marker lever's height by the
  /// measured x, lever_from_track.h): each fitted within [lower, upper] ∩ its family's bounds,
  /// a start outside the range moved to the range's middle.
  struct NarrowedRange {
    std::string name;  ///< EffectParameters' name, e.g. "marker_lever_z_m"
    double lower{0.0}, upper{0.0};
  };
  std::vector<NarrowedRange> narrowed;
};

/// The bounds `spec` is fitted within under `options` (its own, narrowed by options.narrowed).
std::pair<double, double> FitBounds(const effects::ParamSpec& spec, const FitOptions& options);
/// `value` as a start under FitBounds: clamped to the family's bounds; outside a narrowed
/// range, the range's middle.
double StartWithin(double value, const effects::ParamSpec& spec, const FitOptions& options);

/// `lm`, but an axis whose stiffness fled towards 0 (natural frequency below 0.3 Hz at
/// `load_kg`: no suspension, and a fit whose LM moves at most e^±2.5 cannot come back) set to
/// the mode of the paper's Table I LM on the Table I chair at 50 kg (heave 3.2 Hz, ζ 0.54;
/// pitch 3.0 Hz, ζ 0.51) on `chair`'s mass and pitch inertia. (An overdamped or stiff axis, as
/// a base fitted to obstacles that yield, is kept: identified again under the cushion, it
/// comes back; diagnose.h.)
LumpedParams PlausibleLm(const Chair& chair, const LumpedParams& lm, double load_kg);

struct FitResult {
  std::vector<effects::EffectId> effects;  ///< empty: base model; fitted jointly, in this order
  effects::ExtendedParams params;
  std::vector<double> effect_values;  ///< EffectParameters of each effect, concatenated
  int parameter_count{4};             ///< LM 4 + effect parameters
  double sse{0.0};                    ///< weighted sum of squared training residuals
  std::size_t residual_count{0};
  double bic{0.0};                    ///< N ln(sse/N) + p ln N on the training residuals
  int iterations{0};
  /// The member of the last effect's family whose start won the multi-start ("" without one).
  std::string member;
  /// Each start solved, in order: its member and its training error after the first pass.
  struct SolvedStart {
    std::string member;
    effects::Kinematics kinematics{effects::Kinematics::kSmallAngle};
    double sse{0.0};
  };
  std::vector<SolvedStart> starts;
};

/// Fits LM (+ the effect's parameters) on `training` from `start` (LM) with multi-start over
/// the effect's catalogue starting points. The simulations of every trial (and of every
/// parameter step of the Jacobian) run concurrently on the current pool (parallel_for.h); the
/// result is the same to the bit whatever the number of threads.
FitResult FitModel(const std::vector<FitTrial>& training, std::optional<effects::EffectId> effect,
                   const LumpedParams& start, const ChannelWeights& weights,
                   const FitOptions& options = {});

/// Fits LM and every effect of `effects` jointly. The effects but the last start from their
/// values and members in `start.fx` (a previous fit); the last is multi-started over its
/// family's members x starts (effect_catalog.h, EffectFamily): every start scored by its
/// training error, the best of each member solved (more than three: each a few iterations,
/// then the best of each member solved on), the lowest training error kept. Where the training trials pitch
/// beyond options.small_angle_limit, the multi-start is run under exact kinematics as well
/// and the lower final training error kept. Where start.lm has an axis without stiffness
/// (PlausibleLm: a base whose identification fled to K ≈ 0), the multi-start is
/// run from the plausible LM as well (the LM stays within e^±2.5 of where it starts, so it
/// could not come back from there). options.multi_start false: one start, `start` itself.
FitResult FitModelJoint(const std::vector<FitTrial>& training,
                        const std::vector<effects::EffectId>& effects,
                        const effects::ExtendedParams& start, const ChannelWeights& weights,
                        const FitOptions& options = {});

/// Weighted sum of squares of `params` on `trials` (same weights as the fit).
double WeightedSse(const std::vector<FitTrial>& trials, const effects::ExtendedParams& params,
                   const ChannelWeights& weights, std::size_t* residual_count = nullptr);

/// Grid step the fit uses for an effect: identification's (the same for every effect).
double FitStep(std::optional<effects::EffectId> effect);
/// Copies of `trials` set to FitStep(effect) with their input caches filled (kept where they
/// were filled for that step already).
std::vector<FitTrial> WithFitStep(const std::vector<FitTrial>& trials,
                                  std::optional<effects::EffectId> effect);

}  // namespace pwsim::diagnose
