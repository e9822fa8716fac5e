#pragma once
// The chair part of `pwsim run`'s outputs: the per-tick trial.csv columns of the foundation
// (t_s, x_m, v_mps, a_mps2, z_oI_m per wheel, z_gm_m, pitch_gm_rad, z_m, pitch_rad, rates,
// accelerations, pitch_torque_nm) and the peaks in summary.json. The MCA stage
// (report/run_mca.h) and the render stage (report/render_stage.h) add their own.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "engine/chair_simulator.h"
#include "engine/scene.h"
#include "engine/trial_table.h"

namespace pwsim::report {

/// The engine's per-tick samples as trial.csv columns.
TrialTable ChairColumns(const Scene& scene, const std::vector<ChairSample>& samples);

/// Largest |value - value at t = 0| of column `name` over the trial, with its time:
/// {"value_<unit>", "excursion_<unit>", "t_s"}.
nlohmann::ordered_json Peak(const TrialTable& table, const std::string& name, const char* unit);

/// summary.json's chair part: format, scene, clock, duration, load, speed, peak heave/pitch.
nlohmann::ordered_json RunSummary(const Scene& scene, const std::string& scene_path,
                                  const TrialTable& table);

}  // namespace pwsim::report
