#pragma once
// Identification of the chair model from measured trials (seed 000 §IV):
//  1. GM: α and β by linear least squares on the slowest trials (dynamics negligible), one
//     free offset per trial and channel.
//  2. LM: K and C by output-error (simulation-error) minimisation over the faster trials with
//     Ceres Solver, started from a linear (state-variable-filter equation-error) estimate. Optionally one
//     natural frequency and damping ratio for both axes (the paper's choice, `shared_mode`).
//  3. (passes ≥ 2) GM again with the LM-filtered regressors (the LM is linear, so the
//     measured output of a slow trial is Σ α_i LM[Z_Oi]: this removes the small dynamic bias
//     of step 1), then LM again.
// Fitness per trial and channel is MATLAB compare's (fitness.h) with the model driven by the
// trial's measured x(t) and both channels centred at the start of the trial (Fig. 5).

#include <optional>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "sysid/measured/measured_trial.h"

namespace pwsim {

enum class TrialRole { kGeometric, kLumped, kValidation };
/// "gm", "lm" or "validation" (fit.json).
const char* RoleName(TrialRole role);

struct RoleOptions {
  /// Trials whose nominal speed is within this of the slowest go to the GM [m/s].
  double speed_tolerance{0.05};
  /// When more than two speed levels exist: the fastest level is "lm", middle levels are
  /// "validation" (the paper: GM at 0.6, LM at 2.4, validation at 1.2 m/s). With two levels,
  /// every `holdout_every`-th non-GM trial (in the given order) is held out for validation.
  int holdout_every{3};
};

/// Assigns a role to each trial, in order.
std::vector<TrialRole> AssignRoles(const std::vector<MeasuredTrial>& trials,
                                   const RoleOptions& options = {});

struct IdentifyOptions {
  bool shared_mode{false};  ///< one (ω_n, ζ) for heave and pitch at the reference load
  /// Reference load of the shared mode [kg]; default: the heaviest LM trial's load.
  std::optional<double> reference_load_kg;
  int passes{2};                 ///< GM/LM alternations; 1 = the paper's single pass
  bool all_beta_pairs{false};    ///< fit every β_ij (nearly collinear); default adjacent pairs
  /// Rigid heave: the α_i sum to 1 (a ground raised by h under every wheel raises O_GM by h,
  /// whatever the suspension: its deflections do not change). Fitted as
  ///   Z - Z_On = Σ_{i<n} α_i (Z_Oi - Z_On) + offset,  α_n = 1 - Σ_{i<n} α_i,
  /// so that an obstacle lower under the chair than in the terrain file (a cushion that
  /// yields) is left in the residual instead of scaling the α down (without the constraint
  /// a cushion yielding a share y is fitted exactly by Σ α = 1 - y). Table I's α sum to 1.00.
  bool rigid_heave{false};
  SimulationOptions simulation;  ///< internal step of the exact LM
  double offset_window{0.25};    ///< [s] initial window that centres each channel
  int max_iterations{100};       ///< Ceres iterations per LM solve
};

/// How one trial is reproduced by a chair (centred channels, at the mocap times).
struct TrialComparison {
  std::vector<double> t;              ///< [s]
  std::vector<double> z_measured;     ///< [m] measured minus its initial offset
  std::vector<double> z_model;        ///< [m]
  std::vector<double> pitch_measured; ///< [rad]
  std::vector<double> pitch_model;    ///< [rad]
  double fit_z{0.0};                  ///< [%]
  double fit_pitch{0.0};              ///< [%]
};

/// Drives `chair` (with gm and lm) by the trial's measured x(t) and compares.
TrialComparison CompareTrial(const MeasuredTrial& trial, const Chair& chair,
                             const SimulationOptions& simulation = {},
                             double offset_window = 0.25);

struct TrialFit {
  std::string trial;
  TrialRole role{TrialRole::kValidation};
  double fit_z{0.0};      ///< [%]
  double fit_pitch{0.0};  ///< [%]
};

/// The linear (equation-error) estimate the output-error search starts from.
struct LinearEstimate {
  LumpedParams lm;
  bool fallback_z{false};      ///< heave estimate was not usable; a default was used
  bool fallback_pitch{false};
};

struct IdentifyResult {
  Chair chair;                       ///< the input chair with gm and lm filled in
  LinearEstimate start;              ///< first-pass starting point of the LM search
  std::vector<TrialFit> trials;      ///< in input order
  double validation_fit_z{0.0};      ///< pooled over validation trials [%]; NaN if none
  double validation_fit_pitch{0.0};
  double reference_load_kg{0.0};     ///< shared mode only
  int solver_iterations{0};          ///< Ceres iterations, all passes
  std::string solver_summary;        ///< Ceres' brief report of the last LM solve
};

/// Identifies gm and lm of the trials' chair. @throws InputError when the trials disagree on
/// the chair's wheels or a role has no trial.
IdentifyResult IdentifyChair(const std::vector<MeasuredTrial>& trials,
                             const std::vector<TrialRole>& roles,
                             const IdentifyOptions& options = {});

/// Step 1 alone: α, β by linear least squares on `trials` for `chair`'s wheels. With `lm`,
/// the regressors are first filtered by the lumped model (per trial load).
GeometricParams IdentifyGeometric(const std::vector<const MeasuredTrial*>& trials,
                                  const Chair& chair, const IdentifyOptions& options = {},
                                  const std::optional<LumpedParams>& lm = std::nullopt);

/// Step 2 alone: the linear estimate of K, C for `chair` (which must have gm).
LinearEstimate EstimateLumpedLinear(const std::vector<const MeasuredTrial*>& trials,
                                    const Chair& chair, const IdentifyOptions& options = {});

struct LumpedFitResult {
  LumpedParams lm;
  int iterations{0};
  std::string summary;
};
/// Step 2: output-error fit of K, C for `chair` (with gm) from `start`.
LumpedFitResult IdentifyLumped(const std::vector<const MeasuredTrial*>& trials,
                               const Chair& chair, const LumpedParams& start,
                               const IdentifyOptions& options = {},
                               double reference_load_kg = 100.0);

}  // namespace pwsim
