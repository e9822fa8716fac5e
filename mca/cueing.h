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
  bool whole_trial{false};             ///< the offline ceiling (mca/offline_optimum.h)
  MpcStats mpc;                        ///< solves, fallbacks to the washout (MPC only)
};

CueingTrace RunCueing(const McaConfig& config, const std::vector<HeadMotion>& truth, double dt);

/// Per-axis use of the platform's limits.
struct DofUsage {
  Dof dof{Dof::kSurge};
  double peak_pose{0.0}, peak_rate{0.0}, peak_accel{0.0};  ///< max |.| [SI]
  double pose_fraction{0.0}, rate_fraction{0.0}, accel_fraction{0.0};  ///< of the limit
};

struct ConsistencyReport {
  std::array<AxisConsistency, 3> otolith{};  ///< x, y, z
  std::array<AxisConsistency, 3> canals{};   ///< x, y, z
  RateCues tilt_pitch{};
  RateCues tilt_roll{};
  std::vector<DofUsage> usage;               ///< present axes only
  int fault_ticks{0};
};

ConsistencyReport EvaluateConsistency(const McaConfig& config, const CueingTrace& trace, double dt,
                                      double max_lag = 0.5);

}  // namespace pwsim::mca
