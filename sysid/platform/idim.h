#pragma once
// Inverse dynamic identification by least squares (IDIM-LS), the reference method of the EMPS
// benchmark (Janot, Gautier, Brunot 2019) applied to one axis or to the rail + yaw platform of
// seed 001:
//   1. q filtered by a zero-phase Butterworth low-pass (order 4, 100 Hz at 1 kHz: butter(4, 0.2));
//   2. q̇, q̈ by centred differences of the filtered q (DiffCentral, twice);
//   3. the first `border_samples` samples dropped (filter start-up; MATLAB's 50:N); at the end
//      `end_border_samples` (0 in the reference method);
//   4. the regressor X(q, q̇, q̈) and the effort y = gain·command built at full rate;
//   5. every column of X and y decimated by `decimation` (parallel filtering: MATLAB decimate);
//   6. θ̂ = argmin ‖y − Xθ‖ (SVD), σ_i = std(e)·√((XᵀX)⁻¹)_ii (std with mean removed, N − 1),
//      relative error 100·‖y − Xθ̂‖/‖y‖, condition number σ_max(X)/σ_min(X).
// With two joints the rows of both joints are stacked (joint 1 then joint 2) and weighted by
// 1/σ_j of each joint's OLS error (Gautier's weighted LS), so N·m and N rows count alike; the
// reported relative error is on the unweighted efforts.
//
// Models (linear in their parameters; sign(0) = 0):
//   axis-base        τ = M q̈ + Fv q̇ + Fc sign(q̇) + offset                     (EMPS)
//   axis-asymmetric  τ = M q̈ + Fv+ q̇⁺ + Fc+ [q̇>0] + Fv− q̇⁻ − Fc− [q̇<0]         (EMPS, no offset)
//                    with q̇⁺ = max(q̇, 0), q̇⁻ = min(q̇, 0)
//   friction         τ = Fv q̇ + Fc sign(q̇) + offset on constant-velocity rows only
//                    (|q̈| < accel_threshold, |q̇| > speed_threshold): the seed's ramp/step tests
//   rail-yaw         seed 001, q1 yaw (the revolute joint), q2 rail (the prismatic joint):
//     τ1 = θ1 q̈1 + θ2 (q2 q̈1 + q̇1 q̇2) + θ3 (q2² q̈1 + 2 q2 q̇1 q̇2) + θ4 q̈2
//          + Fv1 q̇1 + Fc1 sign(q̇1) + off1
//     τ2 = θ4 q̈1 − θ2 q̇1²/2 + θ3 (q̈2 − q2 q̇1²) + Fv2 q̇2 + Fc2 sign(q̇2) + off2
//     θ1 = m1(xG1² + yG1²) + I1zz + I2zz + m2(xG2² + yG2²), θ2 = 2 m2 xG2, θ3 = m2, θ4 = −m2 yG2
//   (derived again from eq. 8-12; docs/platform.md lists where eq. 18-20 differ).

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

#include "sysid/platform/axis_recording.h"

namespace pwsim::sysid::platform {

struct IdimOptions {
  int lowpass_order{4};
  double lowpass_cutoff_hz{100.0};  ///< [Hz] zero-phase Butterworth on q
  int border_samples{49};           ///< samples dropped at the start after filtering
  /// Samples dropped at the end: 0 as the reference method (EMPS ends in slow motion and keeps
  /// its last samples); a recording cut out of a longer one or ending in fast motion needs
  /// border_samples here (the diagnosis does that for its split recordings).
  int end_border_samples{0};
  int decimation{10};               ///< parallel decimation factor (1 = none)
  double speed_threshold{0.0};      ///< [m/s or rad/s] friction model: min |q̇| (0 = 2 % of max)
  double accel_threshold{0.0};      ///< [m/s² or rad/s²] friction model: max |q̈| (0 = 2 % of max)
};

/// Filtered joint states at the recording's rate, after the border.
struct JointStates {
  std::string name;
  JointKind kind{JointKind::kPrismatic};
  std::vector<double> q, qd, qdd, tau;  ///< [m, m/s, m/s², N] or rad, N·m
};
struct ProcessedRecording {
  std::string name;
  double dt{0.0};
  std::vector<double> t;
  std::vector<JointStates> joints;
};
/// Steps 1-3. @throws std::invalid_argument when the recording is too short for the filters.
ProcessedRecording Preprocess(const AxisRecording& recording, const IdimOptions& options);

struct ParameterInfo {
  std::string joint;  ///< joint name; "" for parameters shared by the joints (θ of rail-yaw)
  std::string name;   ///< e.g. inertia, viscous, coulomb, offset, theta1, viscous_pos
  std::string unit;
};

/// A model linear in its parameters. `columns` fills, for joint block `joint`, the full-rate
/// regressor rows (one row per sample of that joint's equation).
struct LinearModel {
  std::string name;
  std::vector<ParameterInfo> params;
  std::function<void(const ProcessedRecording&, std::size_t joint, Eigen::MatrixXd& x)> columns;
  /// Optional row filter applied after decimation (friction model); empty = all rows.
  std::function<std::vector<bool>(const Eigen::MatrixXd& x_joint, const JointStates&)> keep_rows;
};

LinearModel AxisBaseModel(const std::string& joint, JointKind kind = JointKind::kPrismatic);
LinearModel AxisAsymmetricModel(const std::string& joint, JointKind kind = JointKind::kPrismatic);
LinearModel FrictionModel(const std::string& joint, const IdimOptions& options,
                          JointKind kind = JointKind::kPrismatic);
/// @throws std::invalid_argument unless `recording` has one revolute and one prismatic joint.
LinearModel RailYawModel(const ProcessedRecording& recording);
/// The names ModelByName knows: "axis-base", "axis-asymmetric", "friction", "rail-yaw".
const std::vector<std::string>& ModelNames();
/// "axis-base", "axis-asymmetric", "friction", "rail-yaw"; "" = default for the recording
/// (one joint: axis-base, or friction for step/ramp experiments; two joints: rail-yaw).
/// @throws std::invalid_argument for an unknown name or one that does not fit the joints.
LinearModel ModelByName(const std::string& name, const ProcessedRecording& recording,
                        const std::string& experiment, const IdimOptions& options);

/// Decimated regression of one or more recordings (steps 4-5), rows stacked joint by joint.
struct Regression {
  Eigen::MatrixXd x;
  Eigen::VectorXd y;
  std::vector<int> joint_of_row;  ///< joint index of each row
  std::vector<double> t;          ///< [s] time of each row
};
Regression BuildRegression(const ProcessedRecording& recording, const LinearModel& model,
                           const IdimOptions& options);
void Append(Regression& to, const Regression& from);

struct LsFit {
  Eigen::VectorXd theta, sigma;
  double relative_error_pct{0.0};  ///< 100 ‖y − Xθ‖/‖y‖ (unweighted)
  double condition_number{0.0};    ///< of the (weighted) X
  double error_norm{0.0};          ///< ‖y − Xθ‖
  double error_std{0.0};           ///< std(e), N − 1
  int rows{0};
  Eigen::VectorXd residual;        ///< y − Xθ
};
/// OLS; with `joints` > 1 and row weights per joint (1/σ_j), Gautier's WLS.
LsFit SolveLeastSquares(const Regression& regression, int joints);
/// 100 ‖y − Xθ‖/‖y‖.
double RelativeErrorPct(const Regression& regression, const Eigen::VectorXd& theta);

struct ValidationResult {
  std::string recording;
  double relative_error_pct{0.0};
  double condition_number{0.0};
  int rows{0};
};

struct PlatformFit {
  LinearModel model;
  LsFit ls;
  Regression regression;  ///< identification rows (for plots)
  std::vector<std::string> joints;
  std::vector<JointKind> joint_kinds;  ///< of each joint: its effort is a force [N] or a torque [N m]
  std::vector<ValidationResult> validation;
  std::vector<Regression> validation_regressions;
};

/// Identifies `model_name` on the stacked recordings (all must have the same joints) and
/// cross-tests on `validate` with θ̂ held fixed.
PlatformFit IdentifyPlatform(const std::vector<AxisRecording>& recordings,
                             const std::vector<AxisRecording>& validate,
                             const std::string& model_name, const IdimOptions& options = {});

/// sign with sign(0) = 0.
inline double Sign(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

}  // namespace pwsim::sysid::platform
