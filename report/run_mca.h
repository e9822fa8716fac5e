#pragma once
// The motion-cueing stage of `pwsim run`: head motion from the chair samples, the classical
// washout on the scene's platform, the visual channel and both vestibular responses.
// Adds to trial.csv (see docs/mca.md for units and signs):
//   head_fs_{x,y,z}_mps2, head_w_{x,y,z}_radps         vehicle motion at the head (MCA input)
//   plat_<dof>_<m|rad>                                  platform pose setpoint per present axis
//   head_plat_fs_{x,y,z}_mps2, head_plat_w_{x,y,z}_radps  what the platform delivers at the head
//   vis_x_m, vis_z_m, vis_pitch_rad                     vehicle pose the visuals show: the chair
//                                                       pose X_WV (O_V and θ); the eyes sit at
//                                                       occupant.head_offset_m on it
//   vis_tilt_pitch_rad, vis_tilt_roll_rad               tilt-coordination angle NOT to show
//   plat_bank_pitch_rad, plat_bank_roll_rad             the vehicle's sustained attitude the
//                                                       platform presents (a slope: shown)
//   vest_{true,plat}_oto_{x,y,z}_mps2, vest_{true,plat}_scc_{x,y,z}_radps
//   mca_fault                                           1 on ticks with non-finite input
// summary["mca"] gets the platform, its use of the limits (per actuator, against the axis
// boxes; within_limits from the actuator positions), tilt and bank, the consistency metrics,
// the six-channel perceived error and the comparison of the algorithms on the trial;
// DIR/mca.png (with .svg, .csv and .gp beside it, plot/plot.h) plots vehicle against platform
// specific force and pitch rate.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <vector>

#include "engine/chair_simulator.h"
#include "engine/scene.h"
#include "engine/trial_table.h"
#include "mca/config.h"
#include "mca/cue_analysis.h"
#include "mca/cueing.h"

namespace pwsim::report {

/// The MCA's trial.csv columns, shared by the chair and the car runs: the vehicle motion at the
/// head (head_fs_*, head_w_*), the platform setpoint per present axis (plat_*), what the
/// platform delivers at the head (head_plat_fs_*, head_plat_w_*).
void AddCueMotionColumns(const mca::McaConfig& config, const mca::CueingTrace& trace,
                         TrialTable& table);
/// Both vestibular responses (vest_{true,plat}_{oto,scc}_*) and mca_fault.
void AddVestibularColumns(const mca::CueingTrace& trace, TrialTable& table);

/// summary.json parts shared by the chair and the car runs: per platform axis its peaks
/// (deg or m) and their fractions of the limits; whether every fraction stays <= 1; the
/// consistency of true and platform vestibular responses per otolith and canal axis; and the
/// wrong-sign cues summed over all axes.
nlohmann::ordered_json PlatformUsageJson(const mca::ConsistencyReport& report);
/// Every actuator within its stroke, speed and acceleration (mca::kLimitTolerance) and every
/// position checked back by forward kinematics (ConsistencyReport::limits).
bool WithinLimits(const mca::ConsistencyReport& report);
/// summary["mca"]["actuators"]: per actuator its stroke use against what the axis boxes ask
/// (box_stroke_use), position range, speed and acceleration fractions.
nlohmann::ordered_json ActuatorsJson(const mca::PlatformSpec& platform, const mca::ConsistencyReport& report);
/// summary["mca"]["limits"]: within_limits, how it is computed, the tolerance, the FK residual.
nlohmann::ordered_json LimitsJson(const mca::PlatformSpec& platform, const mca::ConsistencyReport& report);
/// The six-channel perceived error: RMS, correlation, cross-correlation peak and its lag.
nlohmann::ordered_json PerceivedJson(const mca::PerceivedError& perceived);
/// summary["mca"]["comparison"]: the same head motion through the washout, the MPC without
/// preview (`predictor`, as a live session has it) and the offline ceiling: each one's
/// PerceivedJson and QP fallbacks. `rail_yaw`: the car's delivered kinematics.
nlohmann::ordered_json ComparisonJson(const mca::McaConfig& config, const std::vector<mca::HeadMotion>& head, double dt,
                                      mca::VehiclePredictor* predictor, bool rail_yaw);
nlohmann::ordered_json AxisJson(const mca::AxisConsistency& c, const char* unit);
nlohmann::ordered_json ConsistencyJson(const mca::ConsistencyReport& report);
struct WrongSignCues {
  int count{0};
  double duration_s{0.0};
};
WrongSignCues CountWrongSignCues(const mca::ConsistencyReport& report);

/// What `pwsim run --mca ... [--mca-preview]` asks of the MCA stage.
struct McaChoice {
  std::optional<mca::McaAlgorithm> algorithm;  ///< overrides the scene's mca.algorithm
  bool preview{false};   ///< the MPC previews the trial (mca.mpc.preview)
  bool offline{false};   ///< the offline ceiling instead (mca/offline_optimum.h)
  bool compare{true};    ///< summary["mca"]["comparison"]: washout, MPC and ceiling on this trial
  /// A pwsim-platform/1 file instead of the scene's platform (its axis boxes and mechanism;
  /// the scene's mca: settings stay). @throws InputError from Apply for a bad file.
  std::optional<std::filesystem::path> platform;
  /// Applies the choice to a loaded configuration.
  void Apply(mca::McaConfig& config) const;
};

/// summary["mca"]["algorithm"]: washout or mpc; for the MPC whether it previewed the trial
/// (or held the current input), its horizon and solver, solves and fallbacks to the washout.
nlohmann::ordered_json AlgorithmJson(const mca::McaConfig& config, const mca::CueingTrace& trace);

/// The axes whose peak pose reaches `min_fraction` of their travel (["heave", "roll", ...]).
nlohmann::ordered_json AxesInUse(const mca::ConsistencyReport& report, double min_fraction = 0.01);

/// The chair pose X_WV the visuals must show, per tick [m, rad]. y, roll and yaw stay empty on a
/// straight run (its trial.csv keeps vis_x_m, vis_z_m, vis_pitch_rad only).
struct VisualPose {
  std::vector<double> x, y, z, roll, pitch, yaw;
};

/// The stage for any chair: the head motion per tick in, columns, summary["mca"] and DIR/mca.png
/// out. With a planar visual pose (yaw given) it also writes vis_y_m, vis_roll_rad, vis_yaw_rad,
/// summary["mca"]["platform"]["axes_in_use"], the roll tilt, and DIR/mca_lateral.png (sway
/// force, roll and yaw rate, platform roll with its tilt part, platform yaw).
/// @throws InputError for a bad mca: or platform: section.
void AddMotionCueingStage(const Scene& scene, const std::vector<double>& t,
                          const std::vector<mca::HeadMotion>& head, const VisualPose& visual,
                          TrialTable& table, nlohmann::ordered_json& summary,
                          const std::filesystem::path& out_dir, const McaChoice& choice = {},
                          mca::VehiclePredictor* predictor = nullptr);

/// The straight run's stage: head motion from the sagittal samples (HeadMotionFromChair).
/// `choice`: what `pwsim run --mca` overrides.
/// @throws InputError for a bad mca: or platform: section.
void AddMotionCueing(const Scene& scene, const std::vector<ChairSample>& samples, TrialTable& table,
                     nlohmann::ordered_json& summary, const std::filesystem::path& out_dir,
                     const McaChoice& choice = {});

}  // namespace pwsim::report
