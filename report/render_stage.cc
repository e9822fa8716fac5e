#include "report/render_stage.h"

#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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

/// A vestibular rate cue to compare with: `sign` × column is the axis' rate in the camera's
/// sense (nose-up pitch, left yaw, right-side-down roll) [rad/s].
struct VestibularCue {
  std::string key;     ///< summary key suffix
  std::string column;  ///< trial.csv column
  double sign{1.0};
  std::string label;   ///< summary.json's "reference": the column it came from
  std::string legend;  ///< the figure's, in words
};

/// An axis of the pixel check (visual_check.csv columns est_<name>_rate_<unit>,
/// pose_<name>_rate_<unit> and <cue key>_<name>_rate_<unit>).
struct CheckAxis {
  std::string name;   ///< "pitch", "yaw", "roll" or "vertical"
  std::string unit;   ///< "radps" or "mps"
  std::string title;  ///< the figure panel's
  std::string pixels_label;
  std::string reference;          ///< what the pose log's series is
  std::vector<double> est, pose;  ///< per frame: from the pixels, from the pose log
  std::vector<VestibularCue> cues;
};

/// The MCA's semicircular-canal outputs about the axis (trial.csv's x ahead, y left, z up, so a
/// nose-up pitch rate is −w_y, a left yaw rate w_z, a right-side-down roll rate w_x): felt on the
/// platform and felt in the real chair. Without them, the chair's own rate.
std::vector<VestibularCue> VestibularCues(const TrialTable& table, const std::string& axis) {
  const char scc = axis == "pitch" ? 'y' : axis == "yaw" ? 'z' : 'x';
  const double sign = axis == "pitch" ? -1.0 : 1.0;
  const std::string prefix = sign < 0 ? "-" : "";
  std::vector<VestibularCue> cues;
  for (const auto& [key, who, what] : {std::array<std::string, 3>{"vestibular_platform", "plat", "felt on the platform"},
                                       std::array<std::string, 3>{"vestibular_true", "true", "felt in the real chair"}}) {
    const std::string column = "vest_" + who + "_scc_" + scc + "_radps";
    if (table.Has(column))
      cues.push_back({key, column, sign, prefix + column + " (" + what + ")",
                      what + " (canal model)"});
  }
  if (cues.empty() && table.Has(axis + "_rate_radps")) {
    cues.push_back({"chair", axis + "_rate_radps", 1.0, axis + "_rate_radps (chair; no vest_ columns)",
                    "the chair's own rotation"});
  }
  return cues;
}

nlohmann::ordered_json ComparisonJson(const render::SeriesComparison& c, const std::string& ref) {
  return {{"reference", ref},         {"gain", c.gain},
          {"lag_s", c.lag},           {"correlation", c.correlation},
          {"rms_error", c.rms_error}, {"samples", c.samples}};
}

/// visual_check.csv/.png and summary["visual_check"]: per axis, the pixels' rate against the
/// pose log's and the cues' (gain, lag within ±max_lag frames, correlation), and the pose log
/// against the cues. `time` the frames' times; frame k's cue is taken at the tick midway
/// between frames k−1 and k.
void WriteVisualCheck(const TrialTable& table, const std::vector<double>& time,
                      const std::vector<CheckAxis>& axes, double frame_dt, int ticks_per_frame,
                      int max_lag, const std::filesystem::path& out_dir,
                      nlohmann::ordered_json& summary) {
  const std::size_t frame_count = time.size();
  std::vector<double> frame_index(frame_count), t_mid(frame_count);
  for (std::size_t k = 0; k < frame_count; ++k) {
    frame_index[k] = static_cast<double>(k);
    t_mid[k] = k == 0 ? time[0] : (time[k] + time[k - 1]) / 2.0;
  }
  const auto cue_rate = [&](const VestibularCue& cue) {
    std::vector<double> rate(frame_count, kNaN);
    const std::vector<double>& column = table.Column(cue.column);
    for (std::size_t k = 1; k < frame_count; ++k) {
      rate[k] = cue.sign * column[k * static_cast<std::size_t>(ticks_per_frame) -
                                  static_cast<std::size_t>(ticks_per_frame) / 2];
    }
    return rate;
  };
  TrialTable check(frame_count);
  check.Add("frame", frame_index);
  check.Add("t_mid_s", t_mid);
  std::vector<plot::SharedXPanel> panels;
  nlohmann::ordered_json check_json{{"csv", "visual_check.csv"}, {"plot", "visual_check.png"}};
  int estimated = 0;
  for (double v : axes.front().est) estimated += std::isfinite(v) ? 1 : 0;
  check_json["frames_estimated"] = estimated;
  const unsigned cue_colors[] = {plot::color::kGreen, plot::color::kPurple, plot::color::kOrange};
  for (const CheckAxis& axis : axes) {
    const std::string suffix = axis.name + "_rate_" + axis.unit;
    check.Add("est_" + suffix, axis.est);
    check.Add("pose_" + suffix, axis.pose);
    // Rotation rates drawn in deg/s, as in mca.png (visual_check.csv keeps rad/s).
    const double shown = axis.unit == "mps" ? 1.0 : 180.0 / std::numbers::pi;
    const auto scaled = [shown](std::vector<double> v) {
      for (double& x : v) x *= shown;
      return v;
    };
    std::vector<plot::SharedXSeries> series{{"video " + axis.pixels_label, scaled(axis.est), plot::color::kVermillion},
                                            {"camera pose (what the video should show)", scaled(axis.pose), plot::color::kBlue}};
    check_json[axis.name + "_rate_vs_pose"] =
        ComparisonJson(render::CompareSeries(axis.est, axis.pose, frame_dt, max_lag), axis.reference);
    for (std::size_t c = 0; c < axis.cues.size(); ++c) {
      const VestibularCue& cue = axis.cues[c];
      std::vector<double> rate = cue_rate(cue);
      check_json[axis.name + "_rate_vs_" + cue.key] =
          ComparisonJson(render::CompareSeries(axis.est, rate, frame_dt, max_lag), cue.label);
      check_json["pose_" + axis.name + "_rate_vs_" + cue.key] =
          ComparisonJson(render::CompareSeries(axis.pose, rate, frame_dt, max_lag), cue.label);
      series.push_back({cue.legend, scaled(rate), cue_colors[c % 3]});
      check.Add(cue.key + "_" + suffix, std::move(rate));
    }
    panels.push_back({axis.title, axis.name + (axis.unit == "mps" ? " velocity [m/s]" : " rate [deg/s]"),
                      std::move(series)});
  }
  check.WriteCsv(out_dir / "visual_check.csv");
  plot::WriteSharedXFigure(out_dir / "visual_check.png", t_mid, panels, "time [s]", 1100, 300,
                           "Does the video move as it should? Motion measured from its pixels against the "
                           "camera's pose and the rotation felt (vestibular canal model)");
  summary["visual_check"] = check_json;
}

}  // namespace

void CheckRenderSetup(const Scene& scene, const RenderStageOptions& options) {
  ConfigWithOverrides(scene, options);
}

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
  // the camera's rotation from frame k−1 to k, ω = log(R_WC(k−1)ᵀ R_WC(k)) in C's axes, and
  // the same from the pixels (rows k ≥ 1; NaN where the estimate failed)
  std::vector<Eigen::Vector3d> pose_step(frame_count, Eigen::Vector3d::Constant(kNaN));
  std::vector<render::FrameMotion> pixel_step(frame_count);
  Eigen::Matrix3d previous_R_WC = Eigen::Matrix3d::Identity();

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
  // mono views: the floor/ceiling plane fit along a straight run's room, any rigid scene on a
  // circuit (rotation only)
  std::unique_ptr<render::FrameMotionEstimator> estimator;
  if (!config.stereo) {
    estimator = std::make_unique<render::FrameMotionEstimator>(
        width, height, config.fov_y_deg, 640,
        channel.planar() ? render::SceneModel::kRigid : render::SceneModel::kFloorPlane);
  }

  const int frames_total = static_cast<int>(frame_count);
  if (options.progress) options.progress("render", 0, frames_total);
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
    if (estimator) pixel_step[k] = estimator->Push(frame, cam_z[k], scene.room.height - cam_z[k]);
    if (k > 0) {
      const Eigen::AngleAxisd step(previous_R_WC.transpose() * X_WC.linear());
      pose_step[k] = step.angle() * step.axis();
    }
    previous_R_WC = X_WC.linear();
    if (options.progress) options.progress("render", static_cast<int>(k + 1), frames_total);
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
                                     {"texture_anisotropy", renderer.texture_anisotropy()},
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
    summary["visual_check"] = {{"skipped", "stereo view"}};
    return;
  }

  // Pixel check: motion between frames k−1 and k belongs to the mid time (k − ½)/fps; the
  // references are the camera's own rotation between the frames (pose log) and the vestibular
  // cues at that time. Straight runs: pitch and vertical motion (plane fit); circuits: yaw, pitch
  // and roll (rigid scene).
  const auto rate = [&](auto of) {
    std::vector<double> pose(frame_count, kNaN), est(frame_count, kNaN);
    for (std::size_t k = 1; k < frame_count; ++k) {
      const auto [from_pose, from_pixels] = of(k);
      pose[k] = from_pose / frame_dt;
      if (pixel_step[k].valid) est[k] = from_pixels / frame_dt;
    }
    return std::pair{pose, est};
  };
  std::vector<CheckAxis> axes;
  const std::string pixels = channel.planar() ? "pixels (optical flow, essential matrix)"
                                              : "pixels (optical flow, plane fit)";
  const auto add_rotation = [&](const std::string& name, const std::string& title, auto of) {
    auto [pose, est] = rate(of);
    axes.push_back({name, "radps", title, pixels,
                    "the camera's rotation between frames, log(R_WC(k-1)^T R_WC(k)), from the pose log",
                    std::move(est), std::move(pose), VestibularCues(table, name)});
  };
  if (channel.planar()) {
    add_rotation("yaw", "yaw rate (turning left +): seen in the video, in the camera pose, and felt",
                 [&](std::size_t k) { return std::pair{pose_step[k].z(), pixel_step[k].yaw_delta}; });
  }
  add_rotation("pitch", "pitch rate (nose-up +): seen in the video, in the camera pose, and felt",
               [&](std::size_t k) { return std::pair{-pose_step[k].y(), pixel_step[k].pitch_delta}; });
  if (channel.planar()) {
    add_rotation("roll", "roll rate (right side down +): seen in the video, in the camera pose, and felt",
                 [&](std::size_t k) { return std::pair{pose_step[k].x(), pixel_step[k].roll_delta}; });
  } else {
    auto [pose, est] = rate([&](std::size_t k) {
      return std::pair{cam_z[k] - cam_z[k - 1], pixel_step[k].vertical_delta};
    });
    axes.push_back({"vertical", "mps", "vertical velocity of the eye (up +): seen in the video and in the camera pose",
                    "pixels (floor and ceiling plane fit)", "cam_z_m (frames.csv), differenced", std::move(est),
                    std::move(pose), {}});
  }
  WriteVisualCheck(table, time, axes, frame_dt, ticks_per_frame, std::max(2, config.fps / 2), out_dir,
                   summary);
}

}  // namespace pwsim::report
