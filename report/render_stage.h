#pragma once
// The render stage of `pwsim run`: renders the trial headlessly from the TrialTable's visual
// channel (vis_* columns when the MCA wrote them, else the chair's x_m, z_m, pitch_rad with no
// tilt) and writes DIR/video.mp4, DIR/frames.csv, optional DIR/video_lossless.mkv and
// DIR/frames/*.png, the pixel check DIR/visual_check.{csv,png}, and summary["render"] and
// summary["visual_check"] (visual_check.png via plot/, with .svg and .csv beside it). Frame k is tick k·N, N = clock rate / fps.

#include <filesystem>
#include <functional>
#include <string_view>
#include <nlohmann/json.hpp>

#include "engine/scene.h"
#include "engine/trial_table.h"

namespace pwsim::report {

/// The command line's choices over the scene's render: section (0 = keep the scene's value).
struct RenderStageOptions {
  int width_px{0};   ///< image width (both eyes side by side in stereo)
  int height_px{0};
  int fps{0};
  bool stereo{false};
  bool no_tilt_removal{false};  ///< show the tilt-coordination angle (for checks)
  bool no_video{false};         ///< skip the stage
  bool lossless{false};         ///< also video_lossless.mkv
  bool png_frames{false};       ///< also frames/frame_NNNNN.png
  /// Called with ("render", frames done, frames) before the first frame and after each (the
  /// command shows it: app/progress.h); none: silent.
  std::function<void(std::string_view stage, int done, int total)> progress;
};

/// Checks the scene's render: section with the command line's overrides, as RenderTrial will,
/// before anything is simulated or written. @throws InputError as RenderTrial.
void CheckRenderSetup(const Scene& scene, const RenderStageOptions& options);

/// @throws InputError for a bad render: section (or overrides that break it),
/// render::RenderError when no real GL context can be made.
void RenderTrial(const Scene& scene, const TrialTable& table, const RenderStageOptions& options,
                 nlohmann::ordered_json& summary, const std::filesystem::path& out_dir);

}  // namespace pwsim::report
