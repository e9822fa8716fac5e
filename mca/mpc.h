#pragma once
// Model-predictive motion cueing: a linear MPC whose cost is the difference between the motion
// the occupant would perceive in the vehicle and on the platform (pwsim's otolith and canal
// models, mca/vestibular.h), weighted per axis, under the platform's limits (mca/platform.h).
//
// Model (one state pair per present platform axis i, the axis list comes from the platform):
//   ṗ_i = v_i,  v̇_i = u_i                       u: the axis's acceleration, held over a block
//   head specific-force deviation, linearised about neutral (p_PH = head from pivot):
//     f = a_trans + g·(θ, φ, 0) + ω̇ × p_PH,   ω = (φ̇, −θ̇, ψ̇)
//     f_x = ẍ + g θ − θ̈ p_z − ψ̈ p_y
//     f_y = ÿ + g φ + ψ̈ p_x − φ̈ p_z
//     f_z = z̈ + φ̈ p_y + θ̈ p_x
//   (the g·θ, g·φ terms are tilt coordination: it comes out of the optimisation)
//   perceived: ŷ_oto,j = H_oto(s) f_j,  ŷ_scc,j = H_scc,j(s) ω_j, on the platform and, from
//   the vehicle's head motion, in the vehicle.
// Horizon: N blocks, the first one control period long (the move that is applied), the others
// `block_s` long (move blocking); horizon = period + (N−1)·block ≥ horizon_s.
// Cost (block k of length h_k, H the horizon; thresholds from mca.vestibular):
//   Σ_k h_k/H · [ Σ_j w_j ((ŷ_plat,j − ŷ_veh,j)/threshold_j)²
//                 + Σ_i w_n (p_i/P_i)² + w_r (v_i/V_i)² + w_e (u_i/A_i)² + w_t (s_k² + s_k) ]
//   (the linear term on the slack s_k makes the penalty exact: s = 0 whenever the band can
//   be kept at a marginal cost below w_t)
//   P_i the travel (π rad for an endless axis), V_i the speed, A_i the acceleration limit.
// Constraints at every block end, for every axis:
//   |u_i| ≤ A_i = brake acceleration (the steady one where the drive has one)
//   |v_i| ≤ V̄_i = min(speed, √(A_i T_i))      T_i travel
//   |p_i| ≤ T_i,  |p_i + c_i v_i| ≤ T_i,  c_i = V̄_i / A_i
// The last one says the platform can always brake to a stop before its end stops: with
// v ≥ 0 it implies p + v²/(2A) ≤ T, and braking at A keeps p + c v from growing, so a feasible
// plan stays feasible (recursive feasibility).
// Tilt rate (pitch and roll, the axes that carry g·θ): the platform's rate stays in the band
// between 0 and the vehicle's own rate θ̇_veh, widened by the tilt threshold:
//   min(0, θ̇_veh) − threshold − s_k ≤ θ̇ ≤ max(0, θ̇_veh) + threshold + s_k,  s_k ≥ 0
// (a soft constraint): any rotation beyond the vehicle's, or against it, is kept below the
// threshold, so tilt coordination is not perceived as rotation.
// Vehicle prediction: without a preview the current input is held over the horizon; with one
// (SetPreview: a recorded or simulated trial), each block gets that trial's mean input.
// Each control period one QP is solved (mca/qp_active_set.h by default, ALGLIB minqp as the
// alternatives, mca/qp_alglib.h), warm-started from the last active set;
// every engine tick the planned pose passes the platform limiter (StepLimiter), which never
// lets a command leave the limits. A failed solve falls back to the classical washout for that
// period (counted); a non-finite input holds the last finite one for fault.hold_s, then
// assumes rest (the neutral pull brings the platform home).
//
//   MpcCueing mpc(config.mpc, config.washout, config.vestibular, config.platform, 1e-3);
//   const McaCommand& cmd = mpc.Step(head_motion);

#include <Eigen/Dense>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/yaml_reader.h"
#include "mca/dof.h"
#include "mca/head_motion.h"
#include "mca/platform.h"
#include "mca/qp_active_set.h"
#include "mca/qp_alglib.h"
#include "mca/vestibular.h"
#include "mca/washout.h"

namespace pwsim::mca {

/// Most blocks the solver meets in real time (2 ms per control step on the 2-core machine,
/// bench/mpc_bench.cc; docs/mca.md).
inline constexpr int kMpcMaxBlocks = 24;

struct MpcParams {
  double horizon{1.0};          ///< [s] at least this far ahead
  double control_period{0.01};  ///< [s] one QP per period (100 Hz)
  double block{0.1};            ///< [s] length of the blocks after the first
  bool preview{false};          ///< use the trial ahead when one is given (SetPreview)
  QpAlgorithm solver{QpAlgorithm::kActiveSet};
  std::array<double, 3> weight_otolith{1.0, 1.0, 1.0};  ///< perceived f_x, f_y, f_z [-]
  std::array<double, 3> weight_canal{1.0, 1.0, 1.0};    ///< perceived ω_x, ω_y, ω_z [-]
  double weight_neutral{0.1};       ///< pull back to neutral, on (p/P)² [-]
  double weight_neutral_rate{0.01}; ///< on (v/V)² [-]
  double weight_effort{1e-3};       ///< on (u/A)² [-]
  double weight_tilt_rate{1.0e4};   ///< on the tilt-rate excess s² [1/(rad/s)²]
  /// The offline ceiling (mca/offline_optimum.h): one solve at tick 0 over the whole horizon,
  /// the plan then followed open loop; not a scene key, and not bound by kMpcMaxBlocks.
  bool whole_trial{false};
  bool operator==(const MpcParams&) const = default;

  int BlockCount() const;
  /// Empty when valid, else which field is wrong and why (the real-time block limit applies
  /// unless whole_trial).
  std::string Validate() const;
};

/// Reads `mca.mpc` over `base`. @throws InputError (file, line, field, expected).
MpcParams ParseMpcParams(YamlMap& map, const MpcParams& base);

/// The condensed prediction, built once from params, platform and vestibular models.
struct MpcModel {
  std::vector<Dof> axes;                ///< present platform axes, in Dof order
  std::vector<int> tilt_axes;           ///< indices into axes of pitch and roll (tilt rate)
  int blocks{0};
  std::vector<double> block_length;     ///< [s]
  int nx{0};                            ///< platform model states: (p, v) per axis + perceived
  int nz{0};                            ///< QP variables: u per axis per block, then slacks
  // platform model over one control period (exact ZOH)
  Eigen::MatrixXd phi_period, gamma_period;
  // vehicle perceived model (inputs f_x, f_y, f_z, ω_x, ω_y, ω_z): per control period, per block
  Eigen::MatrixXd vphi_period, vgamma_period;
  std::vector<Eigen::MatrixXd> vphi, vgamma;
  Eigen::MatrixXd vc;                   ///< 6 × nv: perceived outputs of the vehicle model
  // cost ½‖E z + e‖², e = Fx x0 − (row_scale ∘ ŷ_veh)
  Eigen::MatrixXd cost_e, cost_et, cost_fx, hessian;
  std::vector<int> ref_row;             ///< perceived rows: cost row
  std::vector<int> ref_block, ref_channel;
  std::vector<double> ref_scale;
  // constraints  c_lo − Dx x0 (+ r) ≤ C z ≤ c_hi − Dx x0 (+ r)
  Eigen::MatrixXd con_c, con_dx;
  Eigen::VectorXd con_lo, con_hi;
  std::vector<int> con_tilt_block;      ///< −1, or the block whose vehicle rate shifts the bounds
  std::vector<int> con_tilt_channel;    ///< which ω channel (0 roll, 1 pitch) and its sign below
  std::vector<double> con_tilt_sign;    ///< +1: upper row (+ max(0, rate)); −1: lower row (+ min(0, rate))
  Eigen::VectorXd z_lo, z_hi;
  Eigen::VectorXd z_linear;             ///< constant linear cost: the exact (L1) penalty on slacks
  std::vector<std::pair<int, double>> z_linear_entries;
};

MpcModel BuildMpcModel(const MpcParams& params, const VestibularParams& vestibular,
                       const PlatformSpec& platform);

/// Counters of the real-time path.
struct MpcStats {
  std::int64_t solves{0};
  std::int64_t fallbacks{0};        ///< control steps that used the washout (solver failed)
  std::int64_t fault_ticks{0};      ///< ticks with non-finite input
  std::int64_t iterations{0};       ///< summed solver iterations
};

class MpcCueing {
 public:
  /// @pre every Validate() empty; control_period a whole number of dt ticks.
  MpcCueing(const MpcParams& params, const WashoutParams& washout, const VestibularParams& vestibular,
            const PlatformSpec& platform, double dt);
  ~MpcCueing();

  /// The trial ahead (tick k of the trial is the k-th Step); used when params.preview.
  /// The vector must outlive the controller; nullptr removes it.
  void SetPreview(const std::vector<HeadMotion>* trial);
  bool using_preview() const { return params_.preview && preview_ != nullptr; }

  void Reset();
  const McaCommand& Step(const HeadMotion& input);

  const McaCommand& command() const { return command_; }
  const MpcStats& stats() const { return stats_; }
  const MpcModel& model() const { return model_; }
  const MpcParams& params() const { return params_; }
  /// The first solve from rest with the vehicle at rest: feasible for a valid platform.
  bool StartIsFeasible();

 private:
  void Solve();
  void PredictVehicle();

  MpcParams params_;
  VestibularParams vestibular_;
  PlatformSpec platform_;
  double dt_;
  int period_ticks_;
  MpcModel model_;
  std::unique_ptr<ActiveSetQp> active_set_;  ///< solver kActiveSet
  std::unique_ptr<AlglibQp> alglib_;         ///< the others
  ClassicalWashout washout_;          ///< the fallback, stepped every tick
  // state
  std::int64_t tick_{0};
  Eigen::VectorXd x_;                 ///< platform model state at the last solve
  Eigen::VectorXd xv_;                ///< vehicle perceived state at the last solve
  Eigen::VectorXd z_;                 ///< last plan (warm start)
  Eigen::VectorXd u_;                 ///< applied accelerations this period
  std::array<double, 6> input_sum_{}; ///< vehicle input summed over this period
  std::array<double, 6> last_input_{};
  std::array<LimiterState, kDofCount> limiter_{};
  DofArray nominal_pose_{}, nominal_rate_{};
  bool fallback_{false};
  std::int64_t fault_run_{0};
  HeadMotion held_;
  double vehicle_pitch_{0.0}, vehicle_roll_{0.0};
  // scratch
  Eigen::MatrixXd ref_;               ///< 6 × blocks: predicted vehicle perceived outputs
  Eigen::MatrixXd rate_ref_;          ///< 2 × blocks: vehicle roll and pitch (nose-up) rates
  Eigen::VectorXd e_, b_, c_lo_, c_hi_, dx_, xv_scratch_, xv_next_, x_next_;
  const std::vector<HeadMotion>* preview_{nullptr};
  MpcStats stats_;
  McaCommand command_;
};

}  // namespace pwsim::mca
