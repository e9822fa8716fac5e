#pragma once
// Diagnosis (measured-trials.md, `pwsim diagnose`): what the identified base model (GM + LM,
// seed 000) gets wrong on measured trials, which effect of the spec's table explains it, the
// extended model re-identified, and the gain measured on trials held out of every fit.
//
//  1. Split: the trials of one speed level (the middle one, as the paper validates at
//     1.2 m/s) are held out; with one speed level, one load level; else every third trial.
//  2. Base: GM from the chair (or identified on the training trials when the chair has none,
//     sysid/identify/), LM re-identified by output error on the training trials.
//  3. Residual analysis of the base model (residual_analysis.h): per channel, whiteness,
//     residual-input correlation, spectra, residuals located in space around the terrain's
//     breakpoints and by drive phase, scale/lag regression; one evidence line per effect.
//  4. Every effect's extension fitted as a grey box (greybox_fit.h) on the training trials.
//     An extension earns its parameters when ΔBIC < bic_threshold on the training trials AND
//     it removes at least min_heldout_gain of the held-out error; the cause is the earning
//     extension with the largest held-out gain, `none` when none earns.
// Nothing tells the diagnosis which effect (if any) is hidden.

#include <optional>
#include <string>
#include <vector>

#include "sysid/diagnose/greybox_fit.h"
#include "sysid/diagnose/residual_analysis.h"
#include "sysid/effects/effect_catalog.h"
#include "sysid/effects/effect_model.h"
#include "sysid/measured/measured_trial.h"

namespace pwsim::diagnose {

struct DiagnoseOptions {
  double min_heldout_gain{0.10};  ///< share of the held-out error an extension must remove
  double bic_threshold{-10.0};    ///< ΔBIC (extended - base) an extension must beat
  FitOptions fit;
  std::vector<effects::EffectId> candidates{effects::AllEffects().begin(),
                                            effects::AllEffects().end()};
  double rest_window{0.25};  ///< [s] initial window that centres each channel
};

struct FitPct {
  double z{0.0};      ///< [%] MATLAB compare fitness, pooled over trials
  double pitch{0.0};  ///< [%]
};

struct RankEntry {
  effects::EffectId effect{};
  std::string evidence;   ///< one line from the residual analysis
  double delta_bic{0.0};  ///< BIC(extended) - BIC(base) on training trials (< 0 favours it)
  FitPct heldout;         ///< held-out fitness of the extended model
  double heldout_gain{0.0};  ///< 1 - E_ext / E_base, E = RMS weighted held-out residual
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

struct Diagnosis {
  std::string cause{"none"};
  std::vector<RankEntry> ranking;  ///< best first
  FitPct base_heldout, extended_heldout;
  std::vector<std::string> heldout_trials, training_trials;
  std::string split;  ///< how the held-out trials were chosen
  FitResult base;
  Chair chair;        ///< the chair whose GM was used
  ResidualReport residuals;
  std::vector<TrialAnalysis> trials;
};

/// Runs the whole diagnosis. @pre ≥ 2 trials, all with the same chair wheels; chair.gm set
/// on every record (use IdentifyBaseChair first when it is not).
Diagnosis Diagnose(const std::vector<effects::TrialRecord>& trials,
                   const DiagnoseOptions& options = {});

/// The held-out indices for `trials` and a description of the split.
std::vector<bool> ChooseHeldOut(const std::vector<effects::TrialRecord>& trials,
                                std::string* description = nullptr);

/// Measured trials as diagnosis records. When the chair has no identified gm (or lm), the base
/// model is identified (sysid/identify/, the paper's §IV) on the trials ChooseHeldOut keeps
/// for training, so held-out trials stay out of every fit. `base_source` says which.
/// @throws InputError when the trials do not share one chair's wheels.
std::vector<effects::TrialRecord> RecordsFromMeasured(const std::vector<MeasuredTrial>& trials,
                                                      std::string* base_source = nullptr);

/// MATLAB fit of model vs measured pooled over trials.
FitPct PooledFitPct(const std::vector<FitTrial>& trials, const effects::ExtendedParams& params);

}  // namespace pwsim::diagnose
