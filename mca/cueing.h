#pragma once
// A whole trial through the MCA, offline: true head motion in, platform commands, visual
// channel, delivered head motion, both perceived motions and the consistency metrics out.
// The per-tick work is ClassicalWashout::Step or MpcCueing::Step (config.algorithm; the MPC
// previews the trial itself when config.mpc.preview), chosen once by McaStepper, which live
// loops step tick by tick too; this file only collects series.
//
//   CueingTrace trace = RunCueing(config, head_motions, dt);
//   ConsistencyReport report = EvaluateConsistency(config, trace, dt);

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "mca/config.h"
#include "mca/cue_analysis.h"
#include "mca/head_motion.h"
#include "mca/vestibular.h"
#include "mca/washout.h"

namespace pwsim::mca {

/// The configured algorithm, stepped tick by tick: the classical washout or the MPC. Live, no
/// trial lies ahead: the MPC holds the current input (SetPreview gives it one offline).
/// Construction allocates; Step does not.
class McaStepper {
 public:
  McaStepper(const McaConfig& config, double dt);
  ~McaStepper();
  /// The trial ahead, for the MPC when config.mpc.preview (MpcCueing::SetPreview).
  void SetPreview(const std::vector<HeadMotion>* trial);
  /// The vehicle model's prediction for the MPC without preview (MpcCueing::SetPredictor).
  void SetPredictor(VehiclePredictor* predictor);
  bool using_predictor() const { return mpc_ && mpc_->using_predictor(); }
  const McaCommand& Step(const HeadMotion& input);
  /// The last Step's command.
  const McaCommand& command() const { return mpc_ ? mpc_->command() : washout_->command(); }
  McaAlgorithm algorithm() const { return mpc_ ? McaAlgorithm::kMpc : McaAlgorithm::kWashout; }
  bool using_preview() const { return mpc_ && mpc_->using_preview(); }
  /// Solves, fallbacks, fault ticks of the MPC (zero for the washout).
  MpcStats mpc_stats() const { return mpc_ ? mpc_->stats() : MpcStats{}; }

 private:
  std::optional<ClassicalWashout> washout_;  ///< config.algorithm kWashout
  std::unique_ptr<MpcCueing> mpc_;           ///< kMpc
};

struct CueingTrace {
  std::vector<HeadMotion> truth;       ///< the vehicle's head motion (input)
  std::vector<McaCommand> commands;    ///< platform command stream and tilt, per tick
  std::vector<HeadMotion> delivered;   ///< what the platform delivers at the head
  std::vector<Perceived> perceived_true;
  std::vector<Perceived> perceived_platform;
  McaAlgorithm algorithm{McaAlgorithm::kWashout};
  bool preview{false};                 ///< the MPC saw the trial ahead
  bool predictor{false};               ///< the MPC predicted with the vehicle model (no preview)
  bool whole_trial{false};             ///< the offline ceiling (mca/offline_optimum.h)
  MpcStats mpc;                        ///< solves, fallbacks to the washout (MPC only)
};

/// `predictor`: the vehicle model's prediction for the MPC without preview (nullptr: the
/// present input's transients decay, MpcParams::prediction_decay).
CueingTrace RunCueing(const McaConfig& config, const std::vector<HeadMotion>& truth, double dt,
                      VehiclePredictor* predictor = nullptr);

/// Per-axis pose, rate and acceleration of the command against the platform file's axis box
/// (informative: the box limits nothing any more, the actuators do).
struct DofUsage {
  Dof dof{Dof::kSurge};
  double peak_pose{0.0}, peak_rate{0.0}, peak_accel{0.0};  ///< max |.| [SI]
  double pose_fraction{0.0}, rate_fraction{0.0}, accel_fraction{0.0};  ///< of the box
};

/// Relative tolerance of the limit checks: a figure counts as within a limit L when at most
/// L·(1 + kLimitTolerance) (a stroke end: within kLimitTolerance·stroke), floating point only.
inline constexpr double kLimitTolerance = 1e-9;
/// [m | rad] how far FK(IK(pose)) may lie from the pose for the positions to count as checked.
inline constexpr double kForwardTolerance = 1e-9;

/// One actuator over a trial. Positions q_k = IK(pose_k), what the drives are sent; rates and
/// accelerations their differences per tick (as mca/actuator_limiter.h).
struct ActuatorUsage {
  int index{0};
  double stroke_use{0.0};      ///< max of Mechanism::StrokeUse: share of the half-stroke from neutral
  /// max StrokeUse at the corners of the platform file's axis boxes (every box axis at ± its
  /// travel): what cueing inside the boxes could ask of this actuator; > 1: beyond its stroke
  double box_stroke_use{0.0};
  double min_position{0.0}, max_position{0.0};  ///< [m | rad]
  double speed_fraction{0.0};  ///< max |rate| / speed limit
  double accel_fraction{0.0};  ///< max |acceleration| / acceleration limit
};

/// Whether the command stream stayed within every actuator limit, from the actuator positions.
struct ActuatorLimitsCheck {
  bool within{true};           ///< every stroke, speed and acceleration within kLimitTolerance
  bool positions_checked{true};  ///< FK of every q_k gave back pose_k within kForwardTolerance
  double worst_fraction{0.0};  ///< the largest speed or acceleration fraction or stroke use
  int worst_actuator{-1};
  const char* worst_what{""};  ///< "stroke", "speed" or "acceleration"
  double forward_residual{0.0};  ///< max |FK(q_k) − pose_k| over the moved axes [m | rad]
  std::int64_t ik_failures{0};
};

/// The perceived-motion error, one figure over the six channels: the RMS of platform − vehicle
/// over the three otolith channels [m/s²] and the three canal channels [rad/s] × kCanalWeight,
/// with the stacked correlation of the same six channels (CompareStacked): zero-lag correlation,
/// cross-correlation peak and its lag (the delay).
inline constexpr double kCanalWeight = 10.0;
struct PerceivedError {
  double rms{0.0};
  StackedCorrelation correlation;
};
PerceivedError EvaluatePerceivedError(const CueingTrace& trace, double dt, double max_lag = 0.5);

struct ConsistencyReport {
  std::array<AxisConsistency, 3> otolith{};  ///< x, y, z
  std::array<AxisConsistency, 3> canals{};   ///< x, y, z
  PerceivedError perceived;
  RateCues tilt_pitch{};
  RateCues tilt_roll{};
  std::vector<DofUsage> usage;               ///< present axes only
  std::vector<ActuatorUsage> actuators;      ///< every actuator of the mechanism
  ActuatorLimitsCheck limits;
  int fault_ticks{0};
};

/// ActuatorUsage and the limit check of a pose stream on `platform` (one pose per tick).
void EvaluateActuators(const PlatformSpec& platform, const std::vector<McaCommand>& commands, double dt,
                       std::vector<ActuatorUsage>* usage, ActuatorLimitsCheck* check);

ConsistencyReport EvaluateConsistency(const McaConfig& config, const CueingTrace& trace, double dt,
                                      double max_lag = 0.5);

}  // namespace pwsim::mca
