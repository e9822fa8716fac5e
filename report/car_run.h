#pragma once
// `pwsim run` for a car scene (kind: car): the car of engine/vehicle through the scene's
// controls, the head motion at the driver's head through the classical MCA to seed 001's rail +
// yaw platform (with the false cues the turntable puts on the rail, mca/rail_yaw.h), both
// vestibular responses, and the road video with the dashboard.
//
// Writes into DIR:
//   trial.csv     one row per tick (every --decimate-th), a unit in every column name:
//                 t_s, x_m, y_m, yaw_rad, v_mps, vx_mps, vy_mps, yaw_rate_radps, ax_mps2, ay_mps2,
//                 roll_rad, pitch_rad, engine_rpm, engine_running, clutch_locked, gear, throttle,
//                 throttle_effective, brake, clutch, steer_rad, road_wheel_angle_rad,
//                 engine_torque_nm, clutch_torque_nm, head_fs_{x,y,z}_mps2, head_w_{x,y,z}_radps,
//                 plat_surge_m, plat_yaw_rad, head_plat_fs_{x,y,z}_mps2, head_plat_w_{x,y,z}_radps,
//                 false_cue_surge_mps2, false_cue_sway_mps2, vest_{true,plat}_{oto,scc}_*, mca_fault
//   summary.json  the drive (distance, speeds, gears, stall), the MCA (platform use of its limits,
//                 within_limits, consistency, false cues, the rail-yaw false cue)
//   mca.png       vehicle against platform at the head (+ .svg, .csv, .gp from plot/plot.h)
//   video.mp4, frames.csv   the driver's view of the road with the instruments (unless no_video)

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string_view>
#include <optional>
#include <string>
#include <vector>

#include "engine/trial_table.h"
#include "engine/vehicle/car_scene.h"
#include "mca/config.h"
#include "report/run_mca.h"

namespace pwsim::report {

struct CarRunOptions {
  int decimate{1};
  bool video{true};
  int width{0}, height{0};  ///< 0: the scene's render.size
  int fps{0};               ///< 0: the scene's render.fps
  McaChoice mca;  ///< what --mca overrides
  /// Called with ("render", frames done, frames) before the first frame and after each; none: silent.
  std::function<void(std::string_view stage, int done, int total)> progress;
};

/// The trial.csv columns of the drive itself (no MCA).
TrialTable CarColumns(const vehicle::CarScene& scene, const std::vector<vehicle::CarSample>& samples);

/// Head motion -> MCA -> rail + yaw platform -> vestibular; adds columns, summary["mca"] and
/// DIR/mca.png.
void AddCarCueing(const vehicle::CarScene& scene, const std::vector<vehicle::CarSample>& samples,
                  TrialTable& table, nlohmann::ordered_json& summary, const std::filesystem::path& out_dir,
                  const McaChoice& choice = {});

/// The driver's view with the dashboard: DIR/video.mp4 and DIR/frames.csv; summary["render"].
void RenderCarTrial(const vehicle::CarScene& scene, const std::vector<vehicle::CarSample>& samples,
                    const CarRunOptions& options, nlohmann::ordered_json& summary,
                    const std::filesystem::path& out_dir);

/// The whole run; returns the files written (paths under out_dir).
std::vector<std::filesystem::path> RunCarScene(const vehicle::CarScene& scene, const std::filesystem::path& scene_file,
                                               const CarRunOptions& options, const std::filesystem::path& out_dir);

}  // namespace pwsim::report
