#pragma once
// Diagnosis (measured-trials.md, `pwsim diagnose`): what the identified base model (GM + LM,
// seed 000) gets wrong on measured trials, which effect of the spec's table explains it, the
// extended model re-identified, and the gain measured on trials held out of every fit.
//
//  1. Split, three ways: `report` trials (one speed level, the middle one, as the paper
//     validates at 1.2 m/s; with one speed level, one load level; else every third trial)
//     are held out of every fit AND of every choice: they are read once, at the end, to
//     report. Of the rest, a `selection` share (every third by speed and load, rotating the
//     load) decides; the remaining `training` trials are fitted.
//  2. Base: GM from the chair (or identified on training + selection trials when the chair has
//     none, sysid/identify/, with the α summing to 1: rigid heave), LM re-identified by output
//     error on the training trials, under the paper's small-angle kinematics and under exact
//     rigid-body kinematics (effect_model.h Kinematics; concurrently), the lower training
//     error kept: the model's geometry, not a cause, chosen on training data like a member.
//  3. Noise model from the training + selection trials (noise_model.h): a level per channel
//     and the noise's colour, from the rest before each trial's start.
//  4. The base model's residual on the selection trials tested against it (verdict.h (a)-(e)):
//     noise-like → no cause is looked for.
//  5. Residual analysis of the base model (residual_analysis.h): evidence lines per effect.
//  6. Every extension fitted alone on the training trials (the ranking; concurrently); then
//     forward selection. An extension earns when ΔBIC < bic_threshold (training) AND its gain
//     (below) on the SELECTION trials is ≥ min_selection_gain. Of the earning ones the largest selection gain is added,
//     unless the selection trials cannot tell it from a rival (a Diebold-Mariano test,
//     paired_test.h): then the lowest training BIC among those tied. Every further candidate
//     (those with ΔBIC < bic_threshold alone) is fitted JOINTLY with the ones found
//     (concurrently; from where its fit alone ended, only its own discrete member copied, and
//     from its family's multi-start, the lower training error kept; compared after
//     screen_iterations, the chosen one solved on), and so on while one earns, at most
//     max_causes, stopping when the residual on the selection trials is noise-like. A marker
//     lever, once found in a set whose GM came from the trials, has the GM identified again on
//     the tracks corrected for it (GeometryUnderMarkerLever), alternating with the fit, and a_x
//     taken from O_V's x; a cushion, likewise, has GM and LM identified again under its yield
//     (BaseUnderCushion).
//  7. Report (ReportOnHeldOut in diagnose.cc): fitness of base and extended model on the
//     report trials, each cause's gain on them (below) with its interval, and whether the
//     report trials confirm it (Cause::confirmed: the gain's lower bound > 0); the residual
//     tests on the selection + report trials: base noise-like → `adequate`; a confirmed cause
//     and the extended model noise-like → `explained`, else `partly_explained`; no confirmed
//     cause → `unexplained`. A cause is FOUND when it earned on the selection trials and the
//     report trials confirm it; one that did not is reported apart, never as found.
//  8. Every catalogue effect's probability of being present (EffectProbabilities), from the
//     selection trials' errors of every model the ranking and forward selection fitted.
// Nothing tells the diagnosis which effect (if any) is hidden.
//
// The gain, one quantity wherever it appears (the choice, the confirmation, diagnosis.json,
// diagnosis.md, the console), on the selection trials or on the report trials: of a model
// change from `before` to `after` (base → one extension in the ranking; the model before a cause
// → the model with it in forward selection),
//   ρ² = max(0, MS − N),   gain = 1 − ρ_after / ρ_before,
// MS the weighted mean square per residual of both channels on those trials and N the noise's
// (its lower bound, Diagnosis::selection_noise_ms): the share of the structured error above the
// noise that the change removes. Nothing above the noise before (ρ_before = 0): gain 0, there
// is nothing left to remove. On the report trials its uncertainty comes from the reduction of
// the squared error D = Σ (e_before² − e_after²) and its Newey-West standard deviation s
// (diagnose.cc GainOnTrials): the gain at D ∓ 1.645 s gives its one-sided 95 % lower and upper
// bounds, and since the gain grows with D, lower ≤ gain ≤ upper.

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sysid/diagnose/greybox_fit.h"
#include "sysid/diagnose/lever_from_track.h"
#include "sysid/diagnose/noise_model.h"
#include "sysid/diagnose/residual_analysis.h"
#include "sysid/diagnose/verdict.h"
#include "sysid/effects/effect_catalog.h"
#include "sysid/effects/effect_model.h"
#include "sysid/measured/measured_trial.h"

namespace pwsim::diagnose {

struct DiagnoseOptions {
  double min_selection_gain{0.10};  ///< the gain (above) on the selection trials an extension must reach
  double bic_threshold{-10.0};    ///< ΔBIC (extended - base) an extension must beat
  FitOptions fit;
  std::vector<effects::EffectId> candidates{effects::AllEffects().begin(),
                                            effects::AllEffects().end()};
  double rest_window{0.25};  ///< [s] initial window that centres each channel
  int max_causes{3};         ///< forward selection stops after this many
  int screen_iterations{12};  ///< solver iterations of the joint fits compared in rounds ≥ 2
  /// Threads of the pool (parallel_for.h) on which the candidate fits, and inside each fit the
  /// simulations of every trial and parameter step, run concurrently; the results are the
  /// same to the bit whatever the count.
  int threads{2};
  VerdictOptions verdict;
  /// Told each stage as it starts and each candidate fitted in the ranking and the joint rounds
  /// (stage, items done, items; may be called from the pool's threads); no effect on the results.
  std::function<void(std::string_view stage, int done, int total)> progress;
};

struct FitPct {
  double z{0.0};      ///< [%] MATLAB compare fitness, pooled over trials
  double pitch{0.0};  ///< [%]
};

/// The gain (above) on the report trials, with its bounds.
struct HeldOutGain {
  double pct{0.0};        ///< [%] the gain
  double lower_pct{0.0};  ///< [%] its one-sided 95 % lower bound (≤ pct)
  double upper_pct{0.0};  ///< [%] its one-sided 95 % upper bound (≥ pct)
};

struct RankEntry {
  effects::EffectId effect{};
  std::string evidence;   ///< one line from the residual analysis
  double delta_bic{0.0};  ///< BIC(extended) - BIC(base) on training trials (< 0 favours it)
  FitPct heldout;         ///< held-out fitness of the extended model
  HeldOutGain heldout_gain;  ///< the gain, base → this extension, on the report trials
  double selection_gain{0.0};  ///< [-] the gain, base → this extension, on the selection trials (decides `earns`)
  double selection_error{0.0};  ///< E_ext on the selection trials (RMS weighted residual)
  bool earns{false};
  FitResult fit;
  std::vector<std::pair<std::string, double>> parameters;  ///< effect and LM, named
};

/// Base-model residuals of one trial, with what the located/phase analysis needs.
struct TrialAnalysis {
  std::string name;
  bool heldout{false};
  double speed{0.0}, load_kg{0.0};
  std::vector<double> t, x, accel;
  std::vector<double> z, pitch;                 ///< measured
  std::vector<double> z_base, pitch_base;       ///< base model, centred like measured
  std::vector<double> z_ext, pitch_ext;         ///< extended (cause) model; base if none
  std::vector<double> z_gm, pitch_gm;           ///< base GM output
};

/// Residual averaged against the distance of a wheel to the nearest terrain breakpoint, signed
/// by the breakpoint's slope change and by the wheel's effect on the channel (pitch: front
/// wheels +, rear wheels -; heave: the wheels with a large α), so that the signatures of ramp
/// feet and crests, front and rear wheels add up instead of cancelling.
struct LocatedResidual {
  std::vector<double> distance;  ///< [m] bin centres (wheel x - breakpoint x)
  std::vector<double> slow_pitch, fast_pitch;  ///< [rad] mean pitch residual, slow/fast trials
  std::vector<double> slow_z, fast_z;          ///< [m]
  double space_lock{0.0};  ///< correlation of slow and fast profiles binned in space
  double time_lock{0.0};   ///< same, binned in time since the breakpoint
};

struct PhaseRms {
  std::string phase;  ///< still, accelerate, cruise, decelerate
  double z{0.0};      ///< [m] RMS base residual
  double pitch{0.0};  ///< [rad]
  std::size_t samples{0};
};

struct ResidualReport {
  FitPct fit;                       ///< base model, all trials
  CorrelationTest whiteness_z, whiteness_pitch;      ///< first trial with the most excitation
  CorrelationTest input_z, input_pitch;              ///< residual vs own-channel GM input
  CorrelationTest cross_z, cross_pitch;              ///< e_z vs θ_GM, e_θ vs Z_GM
  Spectrum spectrum_z, spectrum_pitch;               ///< averaged over trials
  double high_band_z{0.0}, high_band_pitch{0.0};     ///< share of residual power above 6 Hz
  double peak_hz_pitch{0.0};
  ScaleLag scale_z, scale_pitch;                     ///< pooled over trials
  LocatedResidual located;
  std::vector<PhaseRms> phases;
  std::vector<std::string> evidence;  ///< per effect, catalogue order
};

/// One cause forward selection added (it earned on the selection trials); found when confirmed.
struct Cause {
  effects::EffectId effect{};
  double heldout_gain_pct{0.0};   ///< [%] the gain, the model before it → with it, report trials
  double heldout_gain_lower_pct{0.0};  ///< [%] its one-sided 95 % lower bound (≤ heldout_gain_pct)
  double heldout_gain_upper_pct{0.0};  ///< [%] its one-sided 95 % upper bound (≥ heldout_gain_pct)
  double selection_gain{0.0};     ///< [-] the gain, the model before it → with it, selection trials
  double delta_bic{0.0};          ///< vs the model before it
  /// The report trials confirm it: heldout_gain_lower_pct > 0 (the reduction of their squared
  /// error beyond its Newey-West uncertainty, with something above the noise to remove). Only
  /// a confirmed cause is found.
  bool confirmed{false};
  std::size_t report_trials{0};      ///< report trials judged
  std::size_t report_trials_improved{0};  ///< of them, those whose error it reduced
};

/// One catalogue effect's probability of being present (EffectProbabilities).
struct EffectProbability {
  effects::EffectId effect{};
  double probability{0.0};
};

/// A model the ranking or forward selection fitted, as the probabilities need it: its effects
/// and, per selection trial and channel (Z then pitch), the mean square of its residual.
struct VisitedModel {
  std::vector<effects::EffectId> effects;
  std::vector<double> selection_ms;  ///< [m², rad²] per selection trial: Z, pitch, Z, pitch, ...
};

/// The constants of EffectProbabilities (docs/diagnosis.md, "How likely each effect is"), fitted
/// on development seeds only (scripts/evaluate-diagnosis.py --fit-probability: the lowest Brier
/// score on the first 25 development and calibration sets, 0.0234 against 0.0305 at π = 1/9,
/// ν = 1; on all 38, 0.0288, the grid's lowest 0.0284).
struct ProbabilityOptions {
  double prior{0.02};           ///< π: an effect's prior probability of being present
  double samples_per_unit{3.0};  ///< ν: independent samples a trial's channel counts for
};

/// Each candidate effect's posterior inclusion probability over the visited models: model m
/// weighs  w_m ∝ (π/(1−π))^{|m|} Π_u MS_{m,u}^{−ν/2}  (u the selection trials' channels; the
/// Gaussian predictive likelihood of held-out trials, ν samples each, under the model's own
/// error level), normalised over the models; P(e) = Σ_{m ∋ e} w_m. Models with a non-finite or
/// missing error are left out. Candidates in `candidates` order.
std::vector<EffectProbability> EffectProbabilities(const std::vector<VisitedModel>& models,
                                                   const std::vector<effects::EffectId>& candidates,
                                                   const ProbabilityOptions& options = {});

struct Diagnosis {
  DiagnoseOptions options;         ///< the options of the run (its limits)
  std::string cause{"none"};       ///< the first confirmed cause; none when none is confirmed
  Verdict verdict{Verdict::kUnexplained};
  std::vector<Cause> causes;       ///< in the order forward selection added them; found: confirmed
  std::vector<EffectProbability> probabilities;  ///< every candidate effect, catalogue order
  std::vector<VisitedModel> visited;  ///< the models the probabilities weigh
  FitPct noise_floor;              ///< [%] on the report trials
  NoiseModel noise;                ///< from the training + selection trials (noise_model.h)
  double sigma_z{0.0}, sigma_pitch{0.0};  ///< σ̂ [m], [rad] (noise.z.sigma, noise.pitch.sigma)
  /// N: the weighted noise mean square per residual the selection gains are taken above (the
  /// noise's lower bound, diagnose.cc SelectionNoise)
  double selection_noise_ms{0.0};
  NoiseCheck base_check, extended_check;  ///< selection + report trials, read at the end
  FitResult selected;              ///< the joint fit forward selection ended with (base: none)
  FitResult extended;              ///< `selected`, or the base model when the verdict is adequate
  std::vector<std::pair<std::string, double>> extended_parameters;  ///< its parameters, named
  std::vector<std::string> selection_trials;
  std::vector<RankEntry> ranking;  ///< best first
  FitPct base_heldout, extended_heldout;
  std::vector<std::string> heldout_trials, training_trials;
  std::string split;  ///< how the held-out trials were chosen
  FitResult base;
  Chair chair;        ///< the chair whose GM was used (by the extended model)
  bool gm_under_marker{false};  ///< the GM was identified again under the marker lever found
  bool base_under_cushion{false};  ///< GM and LM identified again under the cushion found
  /// The marker lever's height the training + selection trials' x bears out
  /// (lever_from_track.h), the range the lever's fit is held within; none where the pitch does
  /// not swing the x.
  std::optional<LeverHeight> lever_from_x;
  ResidualReport residuals;
  std::vector<TrialAnalysis> trials;
  std::vector<bool> selection;      ///< per trial: used to choose the causes
};

/// Runs the whole diagnosis. @pre ≥ 2 trials, all with the same chair wheels; chair.gm set
/// on every record (use IdentifyBaseChair first when it is not). The trials are taken in the
/// order of their names whatever order they come in (the fits sum over trials in floating
/// point, and a multi-start can tip either way on the last bit), so one set of trials gives
/// one diagnosis.
Diagnosis Diagnose(const std::vector<effects::TrialRecord>& trials,
                   const DiagnoseOptions& options = {});

/// The held-out indices for `trials` and a description of the split.
std::vector<bool> ChooseHeldOut(const std::vector<effects::TrialRecord>& trials,
                                std::string* description = nullptr);

/// Of the trials not in `report`, the selection share (every third in (speed, load) order,
/// rotating the load), never leaving fewer than 2 training trials.
std::vector<bool> ChooseSelection(const std::vector<effects::TrialRecord>& trials,
                                  const std::vector<bool>& report);

/// One measured trial as the diagnosis reads it (its name, terrain, load, nominal speed and
/// track), on `chair`.
effects::TrialRecord RecordOf(const MeasuredTrial& trial, const Chair& chair);

/// Measured trials as diagnosis records. When the chair has no identified gm (or lm), the base
/// model is identified (sysid/identify/, the paper's §IV) on the trials ChooseHeldOut keeps
/// for training, so held-out trials stay out of every fit. `base_source` says which.
/// @throws InputError when the trials do not share one chair's wheels.
std::vector<effects::TrialRecord> RecordsFromMeasured(const std::vector<MeasuredTrial>& trials,
                                                      std::string* base_source = nullptr);

/// A record's track with the marker at lever (r_x, r_z) in the chair frame taken out (the
/// motion of O_V): x = x_m − r_x cos θ + r_z sin θ, Z = Z_m − r_x sin θ − r_z (cos θ − 1), θ the
/// measured pitch less its mean over the first `rest_window` s (the chair at rest, level).
struct TrackUnderLever {
  std::vector<double> x, z;  ///< [m]
};
TrackUnderLever TrackUnderMarkerLever(const effects::TrialRecord& record, double lever_x_m,
                                      double lever_z_m, double rest_window = 0.25);

/// The GM identified again (sysid/identify's step 1, regressors filtered by `lm`) on the same
/// trials RecordsFromMeasured identified it on, their tracks first corrected for a marker at
/// lever (r_x, r_z) in the chair frame (effect_model.h, marker_offset): the GM the base model
/// would have had with the marker at O_V. Used once marker_offset is found in a set whose GM
/// came from the trials (TrialRecord::gm_from_trials).
GeometricParams GeometryUnderMarkerLever(const std::vector<effects::TrialRecord>& records,
                                         const Chair& chair, const LumpedParams& lm,
                                         double lever_x_m, double lever_z_m,
                                         double rest_window = 0.25);

/// The base model (GM and LM, sysid/identify's method with the α summing to 1) identified again
/// on the trials RecordsFromMeasured identified it on, each wheel's contact height scaled by the
/// cushion's yield in `fx` (effects::CushionHeightFactors; `chair`'s α give the wheel loads) and
/// each track corrected for fx's marker lever: the base the trials would have given had the
/// terrain file held the heights the wheels met. Used once cushion_compliance is found in a set
/// whose GM came from the trials; without it the base's GM and LM, fitted to obstacles taller
/// than the wheels met, stay distorted (its LM can flee to K_Z -> 0) under the extension.
Chair BaseUnderCushion(const std::vector<effects::TrialRecord>& records, const Chair& chair,
                       const effects::EffectParams& fx, double rest_window = 0.25);

/// MATLAB fit of model vs measured pooled over trials.
FitPct PooledFitPct(const std::vector<FitTrial>& trials, const effects::ExtendedParams& params);

}  // namespace pwsim::diagnose
