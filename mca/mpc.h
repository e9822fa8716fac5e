#pragma once
// Model-predictive motion cueing: a linear MPC whose cost is the difference between the motion
// the occupant would perceive in the vehicle and on the platform (pwsim's otolith and canal
// models, mca/vestibular.h), weighted per axis, under the platform's actuator limits
// (mca/mechanism.h).
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
//                 + Σ_i w_n (p_i/P_i)² + w_r (v_i/V_i)² + w_e (u_i/A_i)² ]
//   Neutral on roll and pitch is the bank: the vehicle's attitude (HeadMotion::attitude) at the
//   solve, clamped to washout bank.max_angle_deg — a slope, a ramp or a banked road is a real,
//   sustained tilt, presented as such (and its g·θ matches the vehicle's then).
//   P_i the axis box's travel (π rad for an endless axis: a scale only), V_i and A_i the
//   speed and acceleration of the axis's stage, or V̂, Â of the coupled group
//   (mca/actuator_limiter.h).
// Constraints at every block end. The platform's actuators limit it (mca/mechanism.h,
// mca/actuator_limiter.h), not the axis boxes of its file; an axis driven by an independent
// stage (a rail or rotary stage no leg depends on: pw4dof's yaw, the car's rail and
// turntable) keeps the 1-D rows of its actuator (stroke [lo, hi] about its centre m, speed,
// peak acceleration; the drive's sustained budget, where the box gives one, for braking):
//   (a) |u_i| ≤ A^peak_i,   braking with A_i = the sustained acceleration where there is one
//   (b) |v_i| ≤ V̄_i = min(speed, √(A_i T_i))      T_i half the stroke
//   (c) lo ≤ p_i ≤ hi,  (d) lo ≤ p_i + c_i v_i ≤ hi,  c_i = V̄_i / A_i
// (d) says the platform can always brake to a stop before its end stops: with v ≥ 0 it
// implies p + v²/(2A) ≤ hi. On the axes G of the coupled group (the legs), every leg i has
// rows in its own coordinate, linearised about the pose p₀ of each solve (q₀ = IK(p₀), J = ∂q/∂p
// at p₀, from the mechanism; SetConstraintMatrix gives the QP the new normals):
//   (e) q_i ≈ q₀ + J_i (p − p₀) ∈ [min_i + m_i, max_i − m_i]        stroke
//   (f) q₀ + J_i (p + c_g v − p₀) ∈ the same                          envelope
//   (g) |J_i v| ≤ (1 − μ_a) v_i,  (h) |J_i u| ≤ (1 − μ_a) a_i            speed, acceleration
// with m_i = μ_a·half-stroke and μ_a = 5 % kept free for the linearisation's error (the
// per-tick limiter holds the exact limits whatever the plan), and
//   c_g = max(max_i v_i / ((1 − μ_a) a_i), h_max/2).
// A row the present state already stands beyond (the limiter or a fault put it there) keeps
// its present value: braking never makes (e)–(g) grow, so that is feasible.
// Recursive feasibility of (e)–(h) (J fixed within a solve): brake to rest by scaling,
// u = −α v with α = min(1/h, min_i (1 − μ_a) a_i / |J_i v|). Every leg's rate w_i = J_i v then
// falls, (g) and (h) hold; if α = 1/h every leg stops in the block and
// q' = q + w h/2 ≤ q + c_g w (h ≤ 2 c_g); else α ≥ 1/c_g (|w_i| ≤ v_i) and
//   q' + c_g w' = q + c_g w + h w (1 − c_g α) − α w h²/2 ≤ q + c_g w.
//
// Tilt rate: a guarantee, not a penalty. On pitch and roll (the axes that carry g·θ) let
// ω_veh be the vehicle's own rate (roll w_x, nose-up pitch −w_y) and ω_f the same rate as the
// platform could follow it, its change per tick limited to the axis's brake acceleration A
// (its box's: how fast ω_f moves is part of the band's definition, StepFollowRate):
//   ω_f,k = clamp(ω_veh,k, ω_f,k−1 − A dt, ω_f,k−1 + A dt)
// The platform's rate r_k (pose difference per tick) stays in the tilt band
//   B_k = [min(0, ω_f,k) − τ, max(0, ω_f,k) + τ],   τ = thresholds.tilt_rate (3 deg/s)
// so the tilt-coordination rate, the rotation beyond the vehicle's or against it,
//   r − clamp(r, min(0, ω_f), max(0, ω_f))      (McaCommand::tilt_rate_pitch, tilt_rate_roll)
// is never above the threshold: tilt coordination, and the return to neutral, are not
// perceived as rotation. (ω_f rather than ω_veh: a vehicle's rate can fall faster than any
// platform brakes, and a band about ω_veh itself is then infeasible.)
//   Every tick — the QP's plan, the washout fallback and the fault path alike — the limiter in
// actuator space (mca/actuator_limiter.h) holds every actuator limit and keeps the rate in B_k:
// its proof takes windows that always contain [−τ, τ] and whose edges move at most A dt per
// tick (min(0, ·) and max(0, ·) are 1-Lipschitz, so B's do); from rest it holds on every tick.
//   In the QP the band is a hard row at every block end: v_k ∈ B̂_k widened by μ = 1.5 A dt,
// with ω̂_f predicted at the block's vehicle rate (predicted or previewed), moving at most A h_k.
// Recursive feasibility on a stage axis: from a state inside (b)–(d) with v within μ of the
// band, "brake to rest", u_k = −sgn(v_k)·min(A, |v_k|/h_k), meets every row (v > 0 shown; v < 0
// is the mirror image): |v| only falls, so (a), (b) hold; if v ≥ A h then v' = v − A h ≥ 0 and
//   p' + c v' = p + c v + h (v − c A) − A h²/2 ≤ p + c v ≤ hi   (v ≤ V̄ = c A),  p' ≥ p ≥ lo;
// if v < A h then v' = 0 and p' = p + v h/2 ≤ p + c v ≤ hi as h ≤ 2c (block_s ≤ 2 V̄/A, checked
// at load, CheckMpcStart); the band's edges move at most A h per block, so v_k ≤ U_k + μ gives
//   v_k+1 = max(0, v_k − A h) ≤ max(0, U_k+1 + μ) = U_k+1 + μ,   v_k+1 ≥ 0 ≥ L_k+1 − μ.
// On the coupled group's roll and pitch the brake by scaling (above) lowers the rate by α v
// per second, not necessarily by A: there the band rows' feasibility is not proven. A solve that
// fails falls back to the washout for that period (counted: `fallbacks_to_washout`), still under
// the per-tick limiter and band; measured: none on the shipped scenes (MpcCliSceneTest) nor on the
// fuzzed input of MpcTest.FuzzedInputNeverTiltsFasterThanTheThreshold (pw4dof, 1 kHz and 100 Hz).
// The premise holds at each solve after a period in which the plan was followed: the plan kept
// (b)–(d); the model's end-of-tick rate lies within ½ A dt of the tick's mean rate r_k ∈ B_k,
// and B moves at most A dt more by the solve: μ = 1.5 A dt.
// Vehicle prediction: with a preview (SetPreview: a recorded or simulated trial), each block
// gets that trial's mean input. Without one, as live: a VehiclePredictor, when the loop has one,
// runs the vehicle model ahead with the driver's present input held (mca/vehicle_prediction.h:
// the straight run's chair); otherwise the present input's departure from the gravity its
// attitude sustains dies away at prediction_decay_s (default 0.3 s; 0 holds the input, as
// before — an impulsive pitch rate held for a second asks for a rotation the platform cannot
// give, and the plan chases it).
// Each control period one QP is solved (mca/qp_active_set.h by default, ALGLIB minqp as the
// alternatives, mca/qp_alglib.h), warm-started from the last active set;
// every engine tick the planned pose passes the limiter in actuator space, which never lets a
// command leave an actuator's limits nor, on pitch and roll, the tilt band. A failed solve falls
// back to the classical washout for that period (counted); a non-finite input holds the last
// finite one for fault.hold_s, then assumes rest (the neutral pull brings the platform home).
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
  /// [s] without preview or predictor: the time constant at which the present input's
  /// departure from the sustained gravity of its attitude is predicted to die away (0: held)
  double prediction_decay{0.3};
  QpAlgorithm solver{QpAlgorithm::kActiveSet};
  std::array<double, 3> weight_otolith{1.0, 1.0, 1.0};  ///< perceived f_x, f_y, f_z [-]
  std::array<double, 3> weight_canal{1.0, 1.0, 1.0};    ///< perceived ω_x, ω_y, ω_z [-]
  double weight_neutral{0.1};       ///< pull back to neutral, on (p/P)² [-]
  double weight_neutral_rate{0.01}; ///< on (v/V)² [-]
  double weight_effort{1e-3};       ///< on (u/A)² [-]
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

/// What the vehicle will do over the horizon as far as the loop knows it: the vehicle model run
/// forward from its present state with the driver's input held (mca/vehicle_prediction.h).
class VehiclePredictor {
 public:
  virtual ~VehiclePredictor() = default;
  /// At the control step of engine tick `tick` (whose input is the present one): the mean over
  /// each block of the MCA input's channels (fs_x, fs_y, fs_z − g, w_x, w_y, w_z), blocks of
  /// `block_ticks` ticks, the first starting at `tick`, into `means` (6 × blocks, sized).
  virtual void Predict(std::int64_t tick, const std::vector<int>& block_ticks, Eigen::MatrixXd& means) = 0;
};

/// The condensed prediction, built once from params, platform and vestibular models.
struct MpcModel {
  std::vector<Dof> axes;                ///< present platform axes, in Dof order
  std::vector<int> tilt_axes;           ///< indices into axes of pitch and roll (tilt rate)
  std::array<double, 2> tilt_brake{};   ///< A of roll, pitch [rad/s²]: ω_f's rate of change
  int blocks{0};
  std::vector<double> block_length;     ///< [s]
  int nx{0};                            ///< platform model states: (p, v) per axis + perceived
  int nz{0};                            ///< QP variables: u per axis per block
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
  std::vector<int> bank_row, bank_channel;  ///< neutral-pull rows of roll (0) and pitch (1)
  std::vector<double> bank_scale;
  // constraints  c_lo − Dx x0 ≤ C z ≤ c_hi − Dx x0; a tilt-band row's bounds (±τ) also
  // move by min(0, ω̂_f) below and max(0, ω̂_f) above and widen by μ (MpcCueing)
  Eigen::MatrixXd con_c, con_dx;
  Eigen::VectorXd con_lo, con_hi;
  std::vector<int> con_tilt_block;      ///< −1, or the block whose ω̂_f shifts the bounds
  std::vector<int> con_tilt_channel;    ///< which ω channel (0 roll, 1 pitch)
  Eigen::VectorXd z_lo, z_hi;
  // the coupled group (legs): its actuator rows, linearised about the pose of each solve
  enum class ActuatorRowKind { kStroke, kEnvelope, kSpeed, kAccel };
  struct ActuatorRow {
    int row{0};             ///< index into the constraint rows
    int actuator{0};        ///< Mechanism actuator index
    int block{0};
    ActuatorRowKind kind{ActuatorRowKind::kStroke};
  };
  std::vector<int> coupled_actuators;
  std::vector<ActuatorRow> actuator_rows;
  /// per block kb and axis a (row kb·m + a): the pose and rate at the block's end, C z + Dx x0
  Eigen::MatrixXd axis_pos_c, axis_vel_c, axis_pos_dx, axis_vel_dx;
  /// the same, row-major (the per-solve rows combine rows)
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> axis_pos_c_rows, axis_vel_c_rows,
      axis_pos_dx_rows, axis_vel_dx_rows;
  double envelope_c{0.0};               ///< c_g of the envelope rows [s]
  double actuator_margin{0.0};          ///< share kept for the linearisation
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
  /// The vehicle model's prediction, used without a preview; nullptr (default): the present
  /// input's transients decay (MpcParams::prediction_decay). Must outlive the controller.
  void SetPredictor(VehiclePredictor* predictor);
  bool using_predictor() const { return !using_preview() && predictor_ != nullptr; }

  void Reset();
  const McaCommand& Step(const HeadMotion& input);

  const McaCommand& command() const { return command_; }
  const MpcStats& stats() const { return stats_; }
  const MpcModel& model() const { return model_; }
  const MpcParams& params() const { return params_; }
  const ActuatorLimiter& limiter() const { return limiter_; }
  /// The first solve from rest with the vehicle at rest: feasible for a valid platform.
  bool StartIsFeasible();

 private:
  void Solve();
  void PredictVehicle();
  void FillActuatorRows(const std::vector<DofArray>* about);
  QpStatus SolveQp(const std::vector<DofArray>* about);
  void SetBank(const HeadMotion& input);

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
  std::array<double, 6> sustained_{};  ///< the gravity of the last solve's attitude, as channels
  ActuatorLimiter limiter_;           ///< every tick: actuator limits and the tilt band
  DofArray nominal_pose_{}, nominal_rate_{};
  bool fallback_{false};
  std::int64_t fault_run_{0};
  HeadMotion held_;
  std::array<double, 2> bank_{};     ///< roll, pitch the neutral pull is about: the attitude [rad]
  std::array<double, 2> follow_rate_{};  ///< ω_f of roll, pitch this tick [rad/s]
  std::array<double, 2> band_margin_{};  ///< μ = 1.5 A dt of roll, pitch [rad/s]
  // the constraints of this solve (the actuator rows change with the pose)
  Eigen::MatrixXd con_c_, con_dx_;
  Eigen::Matrix<double, 1, Eigen::Dynamic> row_c_, row_dx_;  ///< one actuator row being built
  Eigen::VectorXd con_lo_, con_hi_;
  ActuatorJacobian jacobian_;
  std::vector<DofArray> block_poses_;            ///< the offline plan's pose per block
  std::vector<ActuatorJacobian> block_jacobians_;
  std::vector<ActuatorVector> block_positions_;
  // scratch
  Eigen::MatrixXd ref_;               ///< 6 × blocks: predicted vehicle perceived outputs
  Eigen::MatrixXd rate_ref_;          ///< 2 × blocks: predicted ω̂_f of roll, pitch at block ends
  Eigen::VectorXd e_, b_, c_lo_, c_hi_, dx_, xv_scratch_, xv_next_, x_next_;
  const std::vector<HeadMotion>* preview_{nullptr};
  VehiclePredictor* predictor_{nullptr};
  std::vector<int> block_ticks_;
  Eigen::MatrixXd predicted_;          ///< 6 × blocks from the predictor
  MpcStats stats_;
  McaCommand command_;
};

}  // namespace pwsim::mca
