#pragma once
// Diagnosis of one identified axis (shared/spec/platform-data.md, `pwsim platform diagnose`):
// what the base inverse model τ = M q̈ + Fv q̇ + Fc sign(q̇) + offset gets wrong, which axis
// effect explains it, the extended model re-identified, and the gain on held-out recordings.
//
//  1. Split: the validation recordings are held out; without any, the last `holdout_fraction`
//     of every recording is cut off before filtering (so no filter sees both sides).
//  2. Base: IDIM-LS (idim.h) on the training rows; the filter border is dropped at both ends
//     (split recordings start and end in motion).
//  3. Each effect of the spec's table becomes extra regressor columns, linear in their
//     coefficients; a nonlinear parameter (Stribeck speed, cogging period, backlash gap) is
//     chosen on a grid by the training error:
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
//  3b. Rows at rest (|q̇| < rest_speed_fraction · peak) are left out of every fit and error.
//  4. Noise floor: the white part of the base residual, σ² = mean((e_k − (e_k−1 + e_k+1)/2)²)/c
//     (a local smoother's residual; c makes it unbiased for noise that is white up to the
//     decimation filter's cut-off β = 0.8 of the decimated Nyquist, c = (1/βπ)∫₀^βπ(1 − cos ω)²dω
//     = 0.9375; 1.5 without decimation), as a relative error 100·σ·√N/‖τ‖ on the held-out rows.
//  5. An effect earns when ΔBIC (training) < bic_threshold and it removes at least
//     min_heldout_gain of the base model's held-out error above the floor,
//     excess(E) = √max(E² − F², 0), gain = (excess(E_current) − excess(E_with)) / excess(E_base).
//     Effects are added greedily (each on top of the ones found) while one earns and the
//     held-out excess is still above adequate_ratio·F; among those that earn, the one with the
//     lowest training BIC (grid-chosen parameters counted) is taken.
//     Verdict: adequate when excess(E_base) ≤ adequate_ratio·F; explained when the causes bring
//     excess(E_ext) ≤ adequate_ratio·F; partly_explained when a cause earns but more is left;
//     unexplained when the base is wrong and nothing earns.
//  6. When the recording carries its loop (reference, gains), the base and extended models are
//     simulated in that closed loop (axis_closed_loop.h) and compared with the measurement.

#include <optional>
#include <string>
#include <utility>
#include <vector>

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
  double holdout_fraction{0.3};  ///< used when no validation recording is given
  double bic_threshold{-10.0};
  double min_heldout_gain{0.10};
  double adequate_ratio{0.5};    ///< excess error at most this share of the floor = noise
  std::vector<AxisEffect> candidates{AllAxisEffects()};
  bool simulate{true};           ///< closed-loop check when the loop is known
  /// Rows slower than this share of the peak speed are left out (static friction at rest is
  /// indeterminate: any force up to breakaway holds the axis).
  double rest_speed_fraction{0.02};
};

struct NamedValue {
  std::string name;
  double value{0.0};
};

struct EffectResult {
  AxisEffect effect{};
  std::string evidence;          ///< one line
  double delta_bic{0.0};         ///< training BIC(extended) − BIC(current)
  double train_relative_error_pct{0.0};
  double heldout_relative_error_pct{0.0};
  double heldout_gain{0.0};      ///< share of the base's held-out excess error it removed
  bool earns{false};
  std::vector<NamedValue> parameters;  ///< the extended model's parameters
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
  std::string verdict;  ///< adequate | explained | partly_explained | unexplained
  std::string cause{"none"};
  std::vector<std::pair<AxisEffect, double>> causes;  ///< effect, held-out gain (0..1)
  std::vector<EffectResult> ranking;                  ///< first round, best first
  std::vector<NamedValue> base_parameters, extended_parameters;
  double base_train_relative_error_pct{0.0};
  double heldout_base_pct{0.0}, heldout_extended_pct{0.0};
  double noise_floor_pct{0.0};   ///< held-out relative error of the noise alone
  std::string unexplained_evidence;
  std::vector<std::string> training_recordings, heldout_recordings;
  std::vector<ClosedLoopComparison> closed_loop;
  /// Held-out series for plots: time (s, rows of all held-out recordings), τ measured, base, ext.
  std::vector<double> heldout_t, heldout_tau, heldout_base, heldout_ext, heldout_qd;
};

/// @throws std::invalid_argument for recordings without exactly one joint.
AxisDiagnosis DiagnoseAxis(const std::vector<AxisRecording>& recordings,
                           const std::vector<AxisRecording>& validation,
                           const AxisDiagnoseOptions& options = {});

}  // namespace pwsim::sysid::platform
