#include "report/render_stage.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "engine/input_error.h"
#include "render/camera_rig.h"
#include "render/image_io.h"
#include "render/motion_check.h"
#include "render/offscreen_renderer.h"
#include "render/render_config.h"
#include "render/render_scene.h"
#include "render/video_writer.h"
#include "plot/plot.h"

namespace pwsim::report {
namespace {

using render::RenderConfig;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The scene's render: section with the command line's overrides applied.
RenderConfig ConfigWithOverrides(const Scene& scene, const RenderStageOptions& options) {
  RenderConfig config = render::ParseRenderConfig(scene);
  if (options.width_px > 0 && options.height_px > 0) {
    if (config.stereo || options.stereo) {
      config.hmd.eye_width = options.width_px / 2;  // both eyes side by side make the image
      config.hmd.eye_height = options.height_px;
    }
    config.width = options.width_px;
    config.height = options.height_px;
  }
  if (options.fps > 0) config.fps = options.fps;
  if (options.stereo) config.stereo = true;
  if (options.no_tilt_removal) config.remove_tilt = false;
  if (const std::string error = config.Validate(scene.clock); !error.empty()) {
    const SceneSection* section = scene.section("render");
    throw InputError(scene.file.empty() ? std::string("scene") : scene.file.string(),
                     section ? section->line : 0, "render", "a render setup the clock can drive",
                     error);
  }
  return config;
}

/// The visual channel at one tick: the MCA's vis_* columns when present, else the chair.
class VisualChannel {
 public:
  explicit VisualChannel(const TrialTable& table) {
    const bool mca = table.Has("vis_x_m");
    source_ = mca ? "mca visual channel (vis_*)" : "chair (x_m, z_m, pitch_rad; no tilt)";
    x_ = &table.Column(mca ? "vis_x_m" : "x_m");
    z_ = &table.Column(mca && table.Has("vis_z_m") ? "vis_z_m" : "z_m");
    pitch_ = &table.Column(mca && table.Has("vis_pitch_rad") ? "vis_pitch_rad" : "pitch_rad");
    if (table.Has("vis_yaw_rad")) {  // a chair free in the plane (circuit scenes)
      y_ = &table.Column("vis_y_m");
      roll_ = &table.Column("vis_roll_rad");
      yaw_ = &table.Column("vis_yaw_rad");
      source_ += ", in the plane (vis_y_m, vis_roll_rad, vis_yaw_rad)";
    }
    if (table.Has("vis_tilt_pitch_rad")) tilt_pitch_ = &table.Column("vis_tilt_pitch_rad");
    if (table.Has("vis_tilt_roll_rad")) tilt_roll_ = &table.Column("vis_tilt_roll_rad");
  }
  render::VisualSample At(std::size_t row) const {
    render::VisualSample s;
    s.x = (*x_)[row];
    s.z = (*z_)[row];
    s.pitch = (*pitch_)[row];
    s.tilt_pitch = tilt_pitch_ != nullptr ? (*tilt_pitch_)[row] : 0.0;
    s.tilt_roll = tilt_roll_ != nullptr ? (*tilt_roll_)[row] : 0.0;
    if (yaw_ != nullptr) {
      s.y = (*y_)[row];
      s.roll = (*roll_)[row];
      s.yaw = (*yaw_)[row];
    }
    return s;
  }
  /// X_WV: in the plane when the channel has a yaw, else the straight run's sagittal pose.
  Eigen::Isometry3d ChairPose(const render::VisualSample& s) const {
    return yaw_ != nullptr ? render::ChairPose3d(s) : render::ChairPose(s);
  }
  bool planar() const { return yaw_ != nullptr; }
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  const std::vector<double>* x_{nullptr};
  const std::vector<double>* z_{nullptr};
  const std::vector<double>* pitch_{nullptr};
  const std::vector<double>* tilt_pitch_{nullptr};
  const std::vector<double>* tilt_roll_{nullptr};
  const std::vector<double>* y_{nullptr};
  const std::vector<double>* roll_{nullptr};
  const std::vector<double>* yaw_{nullptr};
};

/// A vestibular pitch-rate cue to compare with: `sign` × column is a nose-up rate [rad/s].
struct VestibularCue {
  std::string key;     ///< summary key suffix
  std::string column;  ///< trial.csv column
  double sign{1.0};
  std::string label;
};

/// The MCA's semicircular-canal outputs about y (y points left, so a nose-up pitch rate is
/// −w_y): felt on the platform and felt in the real chair. Without them, the chair's pitch rate.
std::vector<VestibularCue> VestibularCues(const TrialTable& table) {
  std::vector<VestibularCue> cues;
  if (table.Has("vest_plat_scc_y_radps")) {
    cues.push_back({"vestibular_platform", "vest_plat_scc_y_radps", -1.0,
                    "-vest_plat_scc_y_radps (felt on the platform)"});
  }
  if (table.Has("vest_true_scc_y_radps")) {
    cues.push_back({"vestibular_true", "vest_true_scc_y_radps", -1.0,
                    "-vest_true_scc_y_radps (felt in the real chair)"});
  }
  if (cues.empty()) {
    cues.push_back(
        {"chair", "pitch_rate_radps", 1.0, "pitch_rate_radps (chair; no vest_ columns)"});
  }
  return cues;
}

/// A terminal progress bar on stderr (redrawn in place on a terminal, sparse lines otherwise).
class ProgressBar {
 public:
  explicit ProgressBar(std::int64_t total) : total_(total), tty_(::isatty(2) != 0) {}
  void Update(std::int64_t done, double fps) {
    const int percent = static_cast<int>(100 * done / std::max<std::int64_t>(total_, 1));
    if (!tty_ && percent < last_percent_ + 25 && done != total_) return;
    last_percent_ = percent;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * done / std::max<std::int64_t>(total_, 1));
    char line[160];
    std::snprintf(line, sizeof(line), "render [%s%s] %3d%% %lld/%lld frames %6.1f fps",
                  std::string(static_cast<std::size_t>(filled), '#').c_str(),
                  std::string(static_cast<std::size_t>(kWidth - filled), '.').c_str(), percent,
                  static_cast<long long>(done), static_cast<long long>(total_), fps);
    std::cerr << (tty_ ? "\r" : "") << line << (tty_ && done != total_ ? "" : "\n") << std::flush;
  }

 private:
  std::int64_t total_;
  bool tty_;
  int last_percent_{-100};
};

nlohmann::ordered_json ComparisonJson(const render::SeriesComparison& c, const std::string& ref) {
  return {{"reference", ref},         {"gain", c.gain},
          {"lag_s", c.lag},           {"correlation", c.correlation},
          {"rms_error", c.rms_error}, {"samples", c.samples}};
}

}  // namespace

void RenderTrial(const Scene& scene, const TrialTable& table, const RenderStageOptions& options,
                 nlohmann::ordered_json& summary, const std::filesystem::path& out_dir) {
  const RenderConfig config = ConfigWithOverrides(scene, options);
  if (options.no_video) {
    summary["render"] = {{"skipped", "--no-video"}};
    return;
  }
  const int ticks_per_frame = config.TicksPerFrame(scene.clock);
  const std::size_t frame_count =
      (table.rows() - 1) / static_cast<std::size_t>(ticks_per_frame) + 1;
  const double frame_dt = 1.0 / config.fps;
  const VisualChannel channel(table);
  const auto& head = scene.occupant.head_offset;

  // Frame log columns (frames.csv) and pixel-check columns (visual_check.csv).
  std::vector<double> frame_index(frame_count), tick(frame_count), time(frame_count);
  std::vector<double> cam_x(frame_count), cam_y(frame_count), cam_z(frame_count);
  std::vector<double> cam_pitch(frame_count), cam_roll(frame_count), cam_yaw(frame_count, 0.0);
  std::vector<double> tilt_shown(frame_count);
  std::vector<double> est_pitch_rate(frame_count, kNaN), est_vertical_rate(frame_count, kNaN);

  render::OffscreenRenderer renderer(scene.is_circuit() ? render::BuildCircuitRenderScene(scene, config)
                                                        : render::BuildRenderScene(scene, config),
                                     config);
  const int width = renderer.width(), height = renderer.height();
  render::VideoWriter h264(
      {out_dir / "video.mp4", width, height, config.fps, render::VideoCodec::kH264, config.crf});
  std::unique_ptr<render::VideoWriter> lossless;
  if (options.lossless) {
    lossless = std::make_unique<render::VideoWriter>(
        render::VideoConfig{out_dir / "video_lossless.mkv", width, height, config.fps,
                            render::VideoCodec::kLossless, 0});
  }
  // mono views of straight runs only: the plane fit assumes a chair moving along the room
  std::unique_ptr<render::FrameMotionEstimator> estimator;
  if (!config.stereo && !channel.planar()) {
    estimator = std::make_unique<render::FrameMotionEstimator>(width, height, config.fov_y_deg);
  }

  ProgressBar progress(static_cast<std::int64_t>(frame_count));
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < frame_count; ++k) {
    const std::size_t row = k * static_cast<std::size_t>(ticks_per_frame);  // frame k = tick k·N
    const render::VisualSample sample = channel.At(row);
    const Eigen::Isometry3d X_WV = channel.ChairPose(sample);
    const Eigen::Isometry3d X_WC = render::EyePoseOn(X_WV, sample, head, config.remove_tilt);
    // camera angles: the heading taken out first (R = Rz(ψ) Ry(−θ) Rx(φ)), so a straight run
    // (ψ = 0) reads its pitch and roll exactly as before
    const double yaw = channel.planar() ? std::atan2(X_WC.linear()(1, 0), X_WC.linear()(0, 0)) : 0.0;
    const std::array<double, 2> pitch_roll = render::PitchRollOf(
        channel.planar() ? Eigen::Matrix3d(Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()) * X_WC.linear())
                         : Eigen::Matrix3d(X_WC.linear()));
    frame_index[k] = static_cast<double>(k);
    tick[k] = static_cast<double>(row);
    time[k] = scene.clock.TimeAt(static_cast<std::int64_t>(row));
    cam_x[k] = X_WC.translation().x();
    cam_y[k] = X_WC.translation().y();
    cam_z[k] = X_WC.translation().z();
    cam_pitch[k] = pitch_roll[0];
    cam_roll[k] = pitch_roll[1];
    cam_yaw[k] = yaw;
    tilt_shown[k] = config.remove_tilt ? 0.0 : sample.tilt_pitch;

    const render::ImageView frame = renderer.Render(X_WV, X_WC, time[k]);
    h264.Push(frame);
    if (lossless) lossless->Push(frame);
    if (options.png_frames) {
      char name[32];
      std::snprintf(name, sizeof(name), "frame_%05zu.png", k);
      render::WritePng(out_dir / "frames" / name, frame);
    }
    if (estimator) {
      const render::FrameMotion motion =
          estimator->Push(frame, cam_z[k], scene.room.height - cam_z[k]);
      if (motion.valid) {
        est_pitch_rate[k] = motion.pitch_delta / frame_dt;
        est_vertical_rate[k] = motion.vertical_delta / frame_dt;
      }
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress.Update(static_cast<std::int64_t>(k + 1), static_cast<double>(k + 1) / elapsed);
  }
  h264.Close();
  if (lossless) lossless->Close();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  TrialTable frames(frame_count);
  frames.Add("frame", frame_index);
  frames.Add("tick", tick);
  frames.Add("t_s", time);
  frames.Add("cam_x_m", cam_x);
  frames.Add("cam_y_m", cam_y);
  frames.Add("cam_z_m", cam_z);
  frames.Add("cam_pitch_rad", cam_pitch);
  frames.Add("cam_roll_rad", cam_roll);
  frames.Add("cam_yaw_rad", cam_yaw);
  frames.Add("tilt_pitch_shown_rad", tilt_shown);
  frames.WriteCsv(out_dir / "frames.csv");

  nlohmann::ordered_json render_json{{"frames_csv", "frames.csv"},
                                     {"frames", frame_count},
                                     {"fps", config.fps},
                                     {"ticks_per_frame", ticks_per_frame},
                                     {"duration_s", static_cast<double>(frame_count) * frame_dt},
                                     {"visual_source", channel.source()},
                                     {"tilt_removed", config.remove_tilt},
                                     {"stereo", config.stereo},
                                     {"width_px", config.image_width()},
                                     {"height_px", config.image_height()},
                                     {"fov_y_deg", config.fov_y_deg},
                                     {"video", "video.mp4"},
                                     {"encoder", h264.encoder()},
                                     {"gl_renderer", renderer.gl_renderer()},
                                     {"wall_s", wall_s},
                                     {"frames_per_s", static_cast<double>(frame_count) / wall_s}};
  if (config.stereo) {
    render_json["hmd"] = {{"eye_width_px", config.hmd.eye_width},
                          {"eye_height_px", config.hmd.eye_height},
                          {"ipd_m", config.hmd.ipd},
                          {"outer_deg", config.hmd.fov.outer_deg},
                          {"inner_deg", config.hmd.fov.inner_deg},
                          {"up_deg", config.hmd.fov.up_deg},
                          {"down_deg", config.hmd.fov.down_deg}};
  }
  if (lossless) render_json["lossless_video"] = "video_lossless.mkv";
  summary["render"] = render_json;
  if (!estimator) {
    summary["visual_check"] = {
        {"skipped", channel.planar() ? "circuit: the floor/ceiling plane fit assumes a straight run"
                                     : "stereo view"}};
    return;
  }

  // Pixel check: motion between frames k-1 and k belongs to the mid time (k - 1/2)/fps; the
  // references are the pose log differenced the same way and the vestibular cues at that time.
  const std::vector<VestibularCue> cues = VestibularCues(table);
  std::vector<double> t_mid(frame_count, kNaN), pose_pitch_rate(frame_count, kNaN);
  std::vector<double> pose_vertical_rate(frame_count, kNaN);
  std::vector<std::vector<double>> cue_rate(cues.size(), std::vector<double>(frame_count, kNaN));
  for (std::size_t k = 1; k < frame_count; ++k) {
    t_mid[k] = (time[k] + time[k - 1]) / 2.0;
    pose_pitch_rate[k] = (cam_pitch[k] - cam_pitch[k - 1]) / frame_dt;
    pose_vertical_rate[k] = (cam_z[k] - cam_z[k - 1]) / frame_dt;
    const std::size_t mid_row = k * static_cast<std::size_t>(ticks_per_frame) -
                                static_cast<std::size_t>(ticks_per_frame) / 2;
    for (std::size_t c = 0; c < cues.size(); ++c) {
      cue_rate[c][k] = cues[c].sign * table.Column(cues[c].column)[mid_row];
    }
  }
  t_mid[0] = time[0];
  TrialTable check(frame_count);
  check.Add("frame", frame_index);
  check.Add("t_mid_s", t_mid);
  check.Add("est_pitch_rate_radps", est_pitch_rate);
  check.Add("pose_pitch_rate_radps", pose_pitch_rate);
  for (std::size_t c = 0; c < cues.size(); ++c) {
    check.Add(cues[c].key + "_pitch_rate_radps", cue_rate[c]);
  }
  check.Add("est_vertical_rate_mps", est_vertical_rate);
  check.Add("pose_vertical_rate_mps", pose_vertical_rate);
  check.WriteCsv(out_dir / "visual_check.csv");

  const int max_lag = std::max(2, config.fps / 2);  // ±0.5 s
  const auto vs_pose = render::CompareSeries(est_pitch_rate, pose_pitch_rate, frame_dt, max_lag);
  const auto vertical =
      render::CompareSeries(est_vertical_rate, pose_vertical_rate, frame_dt, max_lag);
  int valid = 0;
  for (double v : est_pitch_rate) valid += std::isfinite(v) ? 1 : 0;
  std::vector<plot::SharedXSeries> pitch_series{
      {"pixels (optical flow, plane fit)", est_pitch_rate, 0xD55E00},
      {"camera pose log", pose_pitch_rate, 0x0072B2}};
  const unsigned cue_colors[] = {0x009E73, 0xCC79A7, 0xE69F00};
  for (std::size_t c = 0; c < cues.size(); ++c) {
    pitch_series.push_back({cues[c].label, cue_rate[c], cue_colors[c % 3]});
  }
  plot::WriteSharedXFigure(
      out_dir / "visual_check.png", t_mid,
      {{"Pitch rate (nose-up): pixels vs camera pose log vs vestibular cues",
        "pitch rate [rad/s]", pitch_series},
       {"Vertical velocity of the eye: pixels vs pose log",
        "vertical velocity [m/s]",
        {{"pixels (floor and ceiling plane fit)", est_vertical_rate, 0xD55E00},
         {"camera pose log", pose_vertical_rate, 0x0072B2}}}});
  nlohmann::ordered_json check_json{
      {"csv", "visual_check.csv"},
      {"plot", "visual_check.png"},
      {"frames_estimated", valid},
      {"pitch_rate_vs_pose", ComparisonJson(vs_pose, "cam_pitch_rad (frames.csv), differenced")},
      {"vertical_rate_vs_pose", ComparisonJson(vertical, "cam_z_m (frames.csv), differenced")}};
  for (std::size_t c = 0; c < cues.size(); ++c) {
    check_json["pitch_rate_vs_" + cues[c].key] = ComparisonJson(
        render::CompareSeries(est_pitch_rate, cue_rate[c], frame_dt, max_lag), cues[c].label);
    check_json["pose_pitch_rate_vs_" + cues[c].key] = ComparisonJson(
        render::CompareSeries(pose_pitch_rate, cue_rate[c], frame_dt, max_lag), cues[c].label);
  }
  summary["visual_check"] = check_json;
}

}  // namespace pwsim::report
