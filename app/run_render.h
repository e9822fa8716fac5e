#pragma once
// The render stage of `pwsim run`: renders the trial headlessly from the TrialTable's visual
// channel (vis_* columns when the MCA wrote them, else the chair's x_m, z_m, pitch_rad with no
// tilt) and writes DIR/video.mp4, DIR/frames.csv, optional DIR/video_lossless.mkv and
// DIR/frames/*.png, the pixel check DIR/visual_check.{csv,png}, and summary["render"] and
// summary["visual_check"]. Frame k is tick k·N, N = clock rate / fps.

#include <filesystem>
#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "engine/scene.h"
#include "engine/trial_table.h"

namespace pwsim::app {

/// @throws std::invalid_argument for bad options, InputError for a bad render: section,
/// render::RenderError when no real GL context can be made.
void RenderTrial(const Scene& scene, const TrialTable& table, const ParsedArgs& args,
                 nlohmann::ordered_json& summary, const std::filesystem::path& out_dir);

}  // namespace pwsim::app
