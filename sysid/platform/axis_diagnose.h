#pragma once
// Diagnosis of one identified axis (shared/spec/platform-data.md, `pwsim platform diagnose`):
// what the base inverse model τ = M q̈ + Fv q̇ + Fc sign(q̇) + offset gets wrong, which axis
// effect explains it, the extended model re-identified, and the gain on held-out recordings.
//
//  1. Split, three ways, in blocks of contiguous samples (`block_s`, 1 s by default):
//       training rows   fit every model's coefficients and grid parameters;
//       selection rows  take every decision: the noise model, whether the base is adequate,
//                       which effect earns (its gain), the order of the ranking, forward
//                       selection and its stop;
//       report rows     are read once, at the end, to report: errors, gains, confirmation,
//                       the verdict, the closed-loop comparison.
//     Without validation recordings, each recording is cut into blocks dealt to the three roles
//     in turn so that every role keeps its share (`holdout_fraction` report,
//     `selection_fraction` of the rest selection) and draws blocks from the whole recording
//     (every part of the stroke and of the excitation); with validation recordings, those are
//     the report rows and the recordings given are dealt into training and selection blocks.
//     Each block is cut out BEFORE filtering and loses the filter border at both ends, so no
//     filter, derivative or decimation sees two roles. Blocks rather than interleaved rows:
//     the zero-phase filter, the centred derivatives and the decimation filter spread every
//     sample over ≈ 100 samples, so interleaved rows would share noise between roles and the
//     held-out errors would be optimistic; what is left between blocks (slow disturbances,
//     ≈ 1 s) is what a second recording would also share. Validation recordings, never cut,
//     are grouped into blocks of `block_s` for the uncertainty of step 6 only.
//  2. Base: IDIM-LS (idim.h) on the training rows.
//  3. Each effect of the spec's table becomes extra regressor columns, linear in their
//     coefficients; a nonlinear parameter (Stribeck speed, cogging period, backlash gap, load
//     frequency and damping, delay) is fitted by the training error: the best grid point, then
//     Brent's minimisation (Boost.Math) between its neighbours:
//       asymmetric_friction          base with Fv, Fc split by direction (axis-asymmetric:
//                                    [q̈, q̇⁺, [q̇>0], q̇⁻, −[q̇<0]]; the offset is their mean)
//       stribeck_friction            + sign(q̇)·exp(−(q̇/v_s)²)
//       position_dependent_friction  + sign(q̇)·P1(x), sign(q̇)·P2(x), x = stroke mapped to [−1, 1]
//       cogging                      + sin(2πq/p), cos(2πq/p)
//       transmission_compliance      + q̈_l − q̈_m, q̇_l − q̇_m, sign q̇_l − sign q̇_m with the load
//                                    position q_l = H(s) q_m, H = (2ζω s + ω²)/(s² + 2ζω s + ω²)
//                                    (load on a spring-damper; ω, ζ on a grid): τ = J_m q̈_m +
//                                    J_l q̈_l + f(q̇_l)
//       backlash                     the same three columns with q_l the play operator of q_m
//                                    (gap b on a grid, rigid contact)
//       command_delay (added id)     the base columns taken d later: the effort recorded at t
//                                    acts at t + d, τ_rec(t) = τ(t + d) (d on a grid of 0.25 .. 3
//                                    samples, no extra coefficient); the EMPS loop has a
//                                    one-sample computation delay
//  3b. Rows at rest (|q̇| < rest_speed_fraction · the training rows' peak) are left out of
//     every fit and error.
//  4. Noise model, on the selection rows: the white part of the residual,
//     σ² = mean((e_k − (e_k−1 + e_k+1)/2)²)/c (a local smoother's residual; c makes it unbiased
//     for noise that is white up to the decimation filter's cut-off β = 0.8 of the decimated
//     Nyquist, c = (1/βπ)∫₀^βπ(1 − cos ω)²dω = 0.9375; 1.5 without decimation), taken on the
//     base residual or on the residual of every candidate at once when lower. Noise floor of a
//     set of rows: F = 100·σ·√N/‖τ‖ (the relative error of the noise alone on those rows).
//  5. Forward selection on the selection rows. An effect earns when ΔBIC (training) <
//     bic_threshold and it removes at least min_gain_pct of the base model's selection error
//     above the floor, excess(E) = √max(E² − F², 0),
//     gain = 100·(excess(E_current) − excess(E_with)) / excess(E_base)  [%].
//     Effects are added greedily (each on top of the ones found) while one earns and the
//     selection excess is still above adequate_ratio·F; among those that earn, the one with the
//     lowest training BIC (grid-chosen parameters counted) is taken. Nothing is searched when
//     the base is already noise-like on the selection rows.
//  6. Report rows, read once: the errors of the base and of every step of the extended model
//     (coefficients from step 2 and 5, unchanged), each cause's gain as in 5, and its
//     uncertainty by the delete-one-block jackknife over the report blocks (block_jackknife.h).
//     A cause is CONFIRMED when the one-sided `confirm_level` lower bound of its report gain is
//     positive. Verdict (sysid/diagnosis_verdict.h) on the report rows: adequate when
//     excess(E_base) ≤ adequate_ratio·F; else explained when a cause is confirmed and the
//     extended model's excess ≤ adequate_ratio·F; partly_explained when a cause is confirmed
//     and more is left; unexplained when none is confirmed (unconfirmed causes are still listed,
//     with their figures, never as the cause).
//  7. When the recording carries its loop (reference, gains), the base and extended models are
//     simulated in that closed loop (axis_closed_loop.h) over the whole recording (the model
//     reads only the reference and gains) and compared with the measurement on the report
//     samples.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sysid/diagnosis_verdict.h"
#include "sysid/platform/axis_closed_loop.h"
#include "sysid/platform/axis_recording.h"
#include "sysid/platform/idim.h"

namespace pwsim::sysid::platform {

enum class AxisEffect {
  kAsymmetricFriction,
  kStribeckFriction,
  kPositionDependentFriction,
  kCogging,
  kTransmissionCompliance,
  kBacklash,
  kCommandDelay,  ///< added id: the recorded effort leads the applied one (computation delay)
};
const char* AxisEffectId(AxisEffect effect);
const std::vector<AxisEffect>& AllAxisEffects();

struct AxisDiagnoseOptions {
  IdimOptions idim;
  double holdout_fraction{0.3};    ///< report share of each recording without validation
  double selection_fraction{0.3};  ///< selection share of what is not reported
  double block_s{1.0};             ///< [s] length of the contiguous blocks of the split
  double bic_threshold{-10.0};
  double min_gain_pct{10.0};       ///< [%] selection gain an effect must bring to earn
  double adequate_ratio{0.5};      ///< excess error at most this share of the floor = noise
  double confirm_level{0.95};      ///< one-sided level of a cause's confirmation
  std::vector<AxisEffect> candidates{AllAxisEffects()};
  bool simulate{true};             ///< closed-loop check when the loop is known
  /// Rows slower than this share of the peak speed are left out (static friction at rest is
  /// indeterminate: any force up to breakaway holds the axis).
  double rest_speed_fraction{0.02};
};

struct NamedValue {
  std::string name;
  double value{0.0};
};

enum class AxisRole { kTraining, kSelection, kReport };
/// "training", "selection", "report".
const char* AxisRoleName(AxisRole role);

/// One block of the split: samples [begin, end) of a recording.
struct AxisBlock {
  std::string recording;
  std::size_t begin{0}, end{0};
  AxisRole role{};
};

/// One effect on top of the base model (the ranking's first round).
struct EffectResult {
  AxisEffect effect{};
  std::string evidence;                    ///< one line
  double delta_bic{0.0};                   ///< training BIC(extended) − BIC(base)
  double train_relative_error_pct{0.0};
  double selection_relative_error_pct{0.0};
  double selection_gain_pct{0.0};          ///< [%] of the base's selection excess removed
  bool earns{false};                       ///< decided on training + selection rows
  double heldout_relative_error_pct{0.0};  ///< report rows (reported, never decides)
  double heldout_gain_pct{0.0};            ///< [%] report rows
  std::vector<NamedValue> parameters;      ///< the extended model's parameters
};

/// One cause of the forward selection, in the order found.
struct AxisCause {
  AxisEffect effect{};
  double selection_gain_pct{0.0};  ///< [%] what earned it (selection rows)
  double heldout_gain_pct{0.0};    ///< [%] the same measure on the report rows
  double heldout_gain_se_pct{0.0}; ///< [%] its jackknife standard error over report blocks
  double heldout_gain_lower_pct{0.0};  ///< [%] one-sided lower bound at confirm_level
  bool confirmed{false};           ///< lower bound > 0
};

struct ClosedLoopComparison {
  std::string recording;
  ClosedLoopErrors base;
  ClosedLoopErrors extended;
  bool available{false};
  std::string why_not;  ///< when not available
};

struct AxisDiagnosis {
  std::string joint;
  diagnose::Verdict verdict{diagnose::Verdict::kUnexplained};
  std::string cause{"none"};        ///< the first confirmed cause, or none
  std::vector<AxisCause> causes;    ///< every cause chosen, confirmed or not, in order
  std::vector<EffectResult> ranking;  ///< first round, earning first, by selection gain
  std::vector<NamedValue> base_parameters, extended_parameters;
  double base_train_relative_error_pct{0.0};
  double noise_sigma{0.0};          ///< [N or N m] white noise of the effort (selection rows)
  double selection_base_pct{0.0}, selection_extended_pct{0.0}, selection_floor_pct{0.0};
  /// Report rows ("held-out" in the contract's names).
  double heldout_base_pct{0.0}, heldout_extended_pct{0.0};
  double noise_floor_pct{0.0};      ///< relative error of the noise alone on the report rows
  int report_blocks{0};             ///< blocks of the jackknife
  std::string unexplained_evidence;
  std::vector<std::string> training_recordings, selection_recordings, heldout_recordings;
  std::vector<AxisBlock> blocks;    ///< the split, in sample indices of each recording
  std::vector<ClosedLoopComparison> closed_loop;
  /// Report series for plots: time (s, rows of all report blocks), τ measured, base, ext.
  std::vector<double> heldout_t, heldout_tau, heldout_base, heldout_ext, heldout_qd;
};

/// @throws std::invalid_argument for recordings without exactly one joint.
AxisDiagnosis DiagnoseAxis(const std::vector<AxisRecording>& recordings,
                           const std::vector<AxisRecording>& validation,
                           const AxisDiagnoseOptions& options = {});

}  // namespace pwsim::sysid::platform
