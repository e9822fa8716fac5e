#pragma once
// `pwsim run` for a circuit scene (a scene with a `circuit:` section, engine/circuit.h): the
// full-DoF chair driven by its joystick through walls, obstacles and gates over the floor's
// relief; the head motion in all six axes through the classical MCA to every axis of the
// platform (pw4dof: heave, roll, pitch, yaw); the occupant's view of the circuit.
//
// Writes into DIR:
//   trial.csv     one row per tick (every --decimate-th), a unit in every column name:
//                 t_s, x_m, y_m, yaw_rad, v_mps, yaw_rate_radps, lateral_speed_mps, ax_mps2,
//                 ay_mps2, yaw_acc_radps2, distance_m, joystick_forward, joystick_turn,
//                 z_o<i>_m per row, z_gm_m, pitch_gm_rad, roll_gm_rad, z_m, pitch_rad, roll_rad,
//                 z_rate_mps, pitch_rate_radps, roll_rate_radps, then per ground contact
//                 (<i> the row from the front, l|r the side; at_l, at_r the anti-tip wheels)
//                 load_<c>_n and, for casters, caster_<c>_rad (swivel angle δ from V's x);
//                 lift_off_count, tip_over, on_anti_tip, cop_x_m, cop_y_m, in_contact,
//                 contact_events, gates_passed; then the MCA's columns (report/run_mca.h) with the
//                 visual channel in the plane (vis_x_m, vis_y_m, vis_z_m, vis_roll_rad,
//                 vis_pitch_rad, vis_yaw_rad, vis_tilt_*)
//   summary.json  the chair part (run_report.h) plus "circuit": distance, gates passed of all,
//                 wall/obstacle contacts with their count and peak approach speed, lift-offs
//                 (ticks, episodes, per contact), tip-over, peak roll and yaw rate, peak lateral
//                 acceleration; "mca" with the platform's use of every axis and "axes_in_use";
//                 "training": the training metrics (report/training_report.h)
//   training.md   the training metrics as a page
//   score.json    a skill item's score (report/skill_score.h), when the scene has `skill:`
//   top_view.png  the path from above: walls, obstacles, gates, the chair's footprint and its
//                 casters' rolling directions once a second, contacts and lift-offs
//   wheels.png    caster swivel angles and wheel loads over time (lift-off where a load ≤ 0)
//   mca.png, mca_lateral.png, video.mp4, frames.csv   as for every run (render_stage.h)
// Every figure comes with .svg, .plot.csv and .gp beside it (plot/plot.h).

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "engine/circuit.h"
#include "engine/full_chair.h"
#include "engine/scene.h"
#include "engine/trial_table.h"
#include "report/render_stage.h"
#include "mca/head_motion.h"
#include "report/run_mca.h"

namespace pwsim::report {

/// The column suffix of contact c ("1l", "1r", ..., "at_l", "at_r").
std::string ContactName(int contact, int rows);

/// The chair's trial.csv columns (the list above, before the MCA's).
TrialTable CircuitColumns(const Scene& scene, const std::vector<FullChairSample>& samples);

/// summary["circuit"]: route, contacts, lift-offs, tip-over, peaks.
nlohmann::ordered_json CircuitSummary(const Scene& scene, const std::vector<FullChairSample>& samples);

/// Head motion from the chair's pose track through the MCA: columns, summary["mca"], mca*.png.
void AddCircuitMotionCueing(const Scene& scene, const std::vector<FullChairSample>& samples,
                            TrialTable& table, nlohmann::ordered_json& summary,
                            const std::filesystem::path& out_dir, const McaChoice& mca_choice = {});

/// The head's specific force against its plausibility bound (engine/circuit.h
/// ComputeHeadForceBound, from the run's peak speed and yaw rate): summary["head_force"] (bound,
/// peak away from wall contacts, within_bound, the wall contacts' peak, the bound's links) and
/// DIR/head_force.png.
void AddHeadForceBound(const Scene& scene, const std::vector<FullChairSample>& samples,
                       const std::vector<mca::HeadMotion>& head, const std::vector<double>& t,
                       nlohmann::ordered_json& summary, const std::filesystem::path& out_dir);

/// DIR/top_view.png and DIR/wheels.png (each with .svg, .plot.csv, .gp).
void WriteCircuitFigures(const Scene& scene, const std::vector<FullChairSample>& samples,
                         const std::filesystem::path& out_dir);

/// The whole run; returns the files written. A skill item (a `skill:` section,
/// report/skill_score.h) is also scored: DIR/score.json, and its line in `skill_line`.
/// @pre scene.is_circuit().
std::vector<std::filesystem::path> RunCircuitScene(const Scene& scene, const std::string& scene_path,
                                                   int decimate, const RenderStageOptions& render,
                                                   const std::filesystem::path& out_dir,
                                                   const McaChoice& mca_choice = {},
                                                   std::string* skill_line = nullptr);

}  // namespace pwsim::report
