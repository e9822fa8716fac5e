#include "report/car_run.h"
#include "report/run_mca.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/atomic_file.h"
#include "mca/config.h"
#include "mca/cueing.h"
#include "mca/offline_optimum.h"
#include "mca/rail_yaw.h"
#include "mca/vehicle_prediction.h"
#include "plot/plot.h"
#include "render/dashboard.h"
#include "render/image_io.h"
#include "render/offscreen_renderer.h"
#include "render/render_config.h"
#include "render/road_scene.h"
#include "render/video_writer.h"

namespace pwsim::report {
namespace {

using mca::Dof;
using vehicle::CarSample;

template <typename Get>
std::vector<double> Column(std::size_t rows, Get get) {
  std::vector<double> values(rows);
  for (std::size_t r = 0; r < rows; ++r) values[r] = get(r);
  return values;
}


}  // namespace

TrialTable CarColumns(const vehicle::CarScene& scene, const std::vector<CarSample>& samples) {
  const std::size_t n = samples.size();
  TrialTable table(n);
  auto add = [&](const char* name, auto get) {
    table.Add(name, Column(n, [&](std::size_t k) { return static_cast<double>(get(samples[k])); }));
  };
  add("t_s", [&](const CarSample& s) { return scene.clock.TimeAt(s.tick); });
  add("x_m", [](const CarSample& s) { return s.state.x; });
  add("y_m", [](const CarSample& s) { return s.state.y; });
  add("yaw_rad", [](const CarSample& s) { return s.state.yaw; });
  add("v_mps", [](const CarSample& s) { return vehicle::Speed(s.state); });
  add("vx_mps", [](const CarSample& s) { return s.state.u; });
  add("vy_mps", [](const CarSample& s) { return s.state.v; });
  add("yaw_rate_radps", [](const CarSample& s) { return s.state.r; });
  add("ax_mps2", [](const CarSample& s) { return s.state.ax; });
  add("ay_mps2", [](const CarSample& s) { return s.state.ay; });
  add("roll_rad", [](const CarSample& s) { return s.state.roll; });
  add("pitch_rad", [](const CarSample& s) { return s.state.pitch; });
  add("engine_rpm", [](const CarSample& s) { return vehicle::EngineRpm(s.state); });
  add("engine_running", [](const CarSample& s) { return s.state.engine_running ? 1.0 : 0.0; });
  add("clutch_locked", [](const CarSample& s) { return s.state.clutch_locked ? 1.0 : 0.0; });
  add("gear", [](const CarSample& s) { return s.input.gear; });
  add("throttle", [](const CarSample& s) { return s.input.throttle; });
  add("throttle_effective", [](const CarSample& s) { return s.throttle_effective; });
  add("brake", [](const CarSample& s) { return s.input.brake; });
  add("clutch", [](const CarSample& s) { return s.input.clutch; });
  add("steer_rad", [](const CarSample& s) { return s.input.steer; });
  add("road_wheel_angle_rad", [](const CarSample& s) { return s.road_wheel_angle; });
  add("engine_torque_nm", [](const CarSample& s) { return s.engine_torque; });
  add("clutch_torque_nm", [](const CarSample& s) { return s.clutch_torque; });
  return table;
}

void AddCarCueing(const vehicle::CarScene& scene, const std::vector<CarSample>& samples, TrialTable& table,
                  nlohmann::ordered_json& summary, const std::filesystem::path& out_dir,
                  const McaChoice& choice) {
  mca::McaConfig config = mca::LoadCarMcaConfig(scene);
  choice.Apply(config);
  const double dt = scene.clock.dt();
  const std::size_t n = samples.size();
  std::vector<mca::HeadMotion> head(n);
  for (std::size_t k = 0; k < n; ++k) {
    const vehicle::CarHeadMotion m = vehicle::HeadMotionOfCar(samples[k], scene.head_offset);
    head[k].fs = m.fs;
    head[k].w = m.w;
  }
  // the MPC's vehicle model without preview: the car run ahead with the driver's present input held
  mca::CarRolloutPredictor predictor(scene.car, samples, scene.head_offset, dt);
  // the rail + yaw chain: a platform with surge and yaw and nothing else
  bool rail_yaw = config.platform.Has(Dof::kSurge) && config.platform.Has(Dof::kYaw);
  for (Dof dof : {Dof::kSway, Dof::kHeave, Dof::kRoll, Dof::kPitch}) rail_yaw = rail_yaw && !config.platform.Has(dof);
  const mca::CueingTrace trace = choice.offline ? mca::RunOfflineOptimum(config, head, dt, rail_yaw)
                                 : rail_yaw     ? mca::RunRailYawCueing(config, head, dt, &predictor)
                                                : mca::RunCueing(config, head, dt, &predictor);
  const mca::ConsistencyReport report = mca::EvaluateConsistency(config, trace, dt);
  const mca::RailYawFalseCues false_cue = mca::RailYawFalseCue(config.vestibular, trace.commands, dt);

  AddCueMotionColumns(config, trace, table);
  table.Add("false_cue_surge_mps2", false_cue.surge);
  table.Add("false_cue_sway_mps2", false_cue.sway);
  AddVestibularColumns(trace, table);

  // summary
  nlohmann::ordered_json platform_json;
  platform_json["name"] = config.platform.name;
  platform_json["source"] = config.platform_source;
  platform_json["kinematics"] = rail_yaw ? "rail on the turntable (RP chain, mca/rail_yaw.h)" : "generic (mca/cue_analysis.h)";
  platform_json["usage"] = PlatformUsageJson(report);
  platform_json["within_limits"] = WithinLimits(report);
  nlohmann::ordered_json mca_json;
  mca_json["algorithm"] = AlgorithmJson(config, trace);
  mca_json["platform"] = platform_json;
  mca_json["actuators"] = ActuatorsJson(config.platform, report);
  mca_json["limits"] = LimitsJson(config.platform, report);
  mca_json["perceived"] = PerceivedJson(report.perceived);
  if (choice.compare) mca_json["comparison"] = ComparisonJson(config, head, dt, &predictor, rail_yaw);
  mca_json["consistency"] = ConsistencyJson(report);
  const WrongSignCues wrong = CountWrongSignCues(report);
  mca_json["false_cues"] = {{"wrong_sign_count", wrong.count}, {"wrong_sign_duration_s", wrong.duration_s}};
  mca_json["rail_yaw_false_cue"] = {
      {"what", "specific force the turntable's yaw adds on the rail: surge -r^2 x, sway r' x + 2 r x'"},
      {"peak_surge_mps2", false_cue.peak_surge},
      {"peak_sway_mps2", false_cue.peak_sway},
      {"rms_surge_mps2", false_cue.rms_surge},
      {"rms_sway_mps2", false_cue.rms_sway},
      {"surge_above_threshold_count", false_cue.surge_above_threshold_count},
      {"surge_above_threshold_s", false_cue.surge_above_threshold_s},
      {"sway_above_threshold_count", false_cue.sway_above_threshold_count},
      {"sway_above_threshold_s", false_cue.sway_above_threshold_s},
      {"threshold_surge_mps2", config.vestibular.thresholds.fs[0]},
      {"threshold_sway_mps2", config.vestibular.thresholds.fs[1]}};
  mca_json["fault_ticks"] = report.fault_ticks;
  summary["mca"] = mca_json;

  // mca.png, plotted at 100 Hz at most (the full rate is in trial.csv)
  const std::size_t stride = static_cast<std::size_t>(std::max(1, scene.clock.rate_hz / 100));
  const std::size_t m = (n + stride - 1) / stride;
  auto col = [&](auto get) { return Column(m, [&](std::size_t j) { return get(j * stride); }); };
  const std::vector<double> t = col([&](std::size_t k) { return scene.clock.TimeAt(samples[k].tick); });
  std::vector<plot::SharedXPanel> panels;
  const std::string in_car = "in the real car (vehicle)", on_platform = "on the platform";
  panels.push_back({"forward push felt at the head (surge specific force, forward +)", "surge force [m/s²]",
                    {{in_car, col([&](std::size_t k) { return trace.truth[k].fs[0]; }), plot::color::kVehicle},
                     {on_platform, col([&](std::size_t k) { return trace.delivered[k].fs[0]; }), plot::color::kPlatform}}});
  panels.push_back({"sideways push felt at the head (sway specific force, to the left +)", "sway force [m/s²]",
                    {{in_car, col([&](std::size_t k) { return trace.truth[k].fs[1]; }), plot::color::kVehicle},
                     {on_platform, col([&](std::size_t k) { return trace.delivered[k].fs[1]; }), plot::color::kPlatform}}});
  panels.push_back({"yaw rate (turning left +)", "yaw rate [deg/s]",
                    {{in_car, col([&](std::size_t k) { return trace.truth[k].w[2] / mca::kDegToRad; }), plot::color::kVehicle},
                     {on_platform, col([&](std::size_t k) { return trace.delivered[k].w[2] / mca::kDegToRad; }), plot::color::kPlatform}}});
  panels.push_back({"platform position along its rail (forward +)", "rail position [m]",
                    {{"rail position", col([&](std::size_t k) { return trace.commands[k].pose[mca::Index(Dof::kSurge)]; }),
                      plot::color::kGreen}}});
  panels.push_back({"platform turntable yaw (left +)", "turntable yaw [deg]",
                    {{"turntable yaw", col([&](std::size_t k) { return trace.commands[k].pose[mca::Index(Dof::kYaw)] / mca::kDegToRad; }),
                      plot::color::kPurple}}});
  panels.push_back({"false push of a turntable riding its rail, felt on the platform, not in the car "
                    "(r: turntable yaw rate, x: rail position)",
                    "false push [m/s²]",
                    {{"forward: -r² x", col([&](std::size_t k) { return false_cue.surge[k]; }), plot::color::kOrange},
                     {"sideways: r' x + 2 r x'", col([&](std::size_t k) { return false_cue.sway[k]; }),
                      plot::color::kSkyBlue}}});
  std::filesystem::create_directories(out_dir);
  plot::WriteSharedXFigure(out_dir / "mca", t, panels, "time [s]", 1100, 300,
                           "What the driver feels at the head: in the real car (vehicle) and on the " +
                               config.platform.name + " motion platform");
}

void RenderCarTrial(const vehicle::CarScene& scene, const std::vector<CarSample>& samples,
                    const CarRunOptions& options, nlohmann::ordered_json& summary,
                    const std::filesystem::path& out_dir) {
  // the render: section is parsed as for the wheelchair; a road needs a far clip plane
  Scene shim;
  shim.clock = scene.clock;
  if (const SceneSection* section = scene.section("render")) shim.sections["render"] = *section;
  render::RenderConfig config = render::ParseRenderConfig(shim);
  const SceneSection* section = scene.section("render");
  if (section == nullptr || !section->node["far_m"]) config.far = 1500.0;
  if (section == nullptr || !section->node["near_m"]) config.near = 0.2;
  if (options.width > 0) {
    config.width = options.width;
    config.height = options.height;
  }
  if (options.fps > 0) config.fps = options.fps;
  config.stereo = false;
  if (const std::string error = config.Validate(scene.clock); !error.empty()) {
    throw std::invalid_argument("render: " + error);
  }
  const int ticks_per_frame = config.TicksPerFrame(scene.clock);
  const std::size_t frames = (samples.size() - 1) / static_cast<std::size_t>(ticks_per_frame) + 1;

  render::RoadGeometry road;
  for (const auto& p : scene.road.centre) road.centre.push_back({p.x, p.y});
  road.lane_width = scene.road.lane_width;
  road.lanes = scene.road.lanes;
  for (const auto& c : scene.road.cones) road.cones.push_back({c.x, c.y});
  render::CabinGeometry cabin;
  cabin.cg_height = scene.car.chassis.cg_height;
  cabin.front = scene.car.chassis.cg_to_front + 0.9;
  cabin.half_width = 0.5 * scene.car.chassis.width;
  cabin.windscreen_x = scene.head_offset[0] + 0.55;

  render::OffscreenRenderer renderer(render::BuildRoadScene(road, cabin, config.texture_seed), config);
  render::VideoWriter video({out_dir / "video.mp4", renderer.width(), renderer.height(), config.fps,
                             render::VideoCodec::kH264, config.crf});
  std::vector<double> frame(frames), tick(frames), time(frames), cx(frames), cy(frames), cz(frames), cyaw(frames);
  if (options.progress) options.progress("render", 0, static_cast<int>(frames));
  for (std::size_t k = 0; k < frames; ++k) {
    const std::size_t row = k * static_cast<std::size_t>(ticks_per_frame);
    const CarSample& s = samples[row];
    const Eigen::Isometry3d X_WV =
        render::CarPose(s.state.x, s.state.y, cabin.cg_height, s.state.yaw, s.state.roll, s.state.pitch);
    const Eigen::Isometry3d X_WC = render::EyePoseInCar(X_WV, scene.head_offset);
    const double t = scene.clock.TimeAt(s.tick);
    render::Image image = render::CopyImage(renderer.Render(X_WV, X_WC, t));
    render::DashboardReading reading;
    reading.engine_rpm = vehicle::EngineRpm(s.state);
    reading.speed_kmh = vehicle::Speed(s.state) * 3.6;
    reading.gear = s.input.gear;
    reading.engine_running = s.state.engine_running;
    reading.redline_rpm = scene.car.engine.max_rpm;
    render::DrawDashboard(image, reading);
    video.Push(image.view());
    frame[k] = static_cast<double>(k);
    tick[k] = static_cast<double>(s.tick);
    time[k] = t;
    cx[k] = X_WC.translation().x();
    cy[k] = X_WC.translation().y();
    cz[k] = X_WC.translation().z();
    cyaw[k] = s.state.yaw;
    if (options.progress) options.progress("render", static_cast<int>(k + 1), static_cast<int>(frames));
  }
  video.Close();
  TrialTable table(frames);
  table.Add("frame", frame);
  table.Add("tick", tick);
  table.Add("t_s", time);
  table.Add("cam_x_m", cx);
  table.Add("cam_y_m", cy);
  table.Add("cam_z_m", cz);
  table.Add("cam_yaw_rad", cyaw);
  table.WriteCsv(out_dir / "frames.csv");
  summary["render"] = {{"video", "video.mp4"},
                       {"frames_csv", "frames.csv"},
                       {"frames", frames},
                       {"fps", config.fps},
                       {"size", {renderer.width(), renderer.height()}},
                       {"encoder", video.encoder()},
                       {"gl_renderer", renderer.gl_renderer()}};
}

std::vector<std::filesystem::path> RunCarScene(const vehicle::CarScene& scene, const std::filesystem::path& scene_file,
                                               const CarRunOptions& options, const std::filesystem::path& out_dir) {
  std::filesystem::create_directories(out_dir);
  for (const char* name : {"trial.csv", "summary.json", "mca.png", "mca.svg", "mca.plot.csv", "mca.plot.dat", "mca.gp", "video.mp4", "frames.csv"}) {
    std::filesystem::remove(out_dir / name);  // no stale outputs from an earlier run
  }
  const std::vector<CarSample> samples = vehicle::SimulateCarScene(scene);
  TrialTable table = CarColumns(scene, samples);

  nlohmann::ordered_json summary;
  summary["format"] = "pwsim-run-summary/1";
  summary["scene"] = {{"file", scene_file.string()}, {"name", scene.name}, {"kind", "car"}};
  summary["clock_rate_hz"] = scene.clock.rate_hz;
  summary["duration_s"] = table.Column("t_s").back();
  summary["ticks"] = samples.size();
  summary["vehicle"] = {{"name", scene.car.name}, {"file", scene.vehicle_file.string()}};
  const char* source = scene.source == vehicle::CarScene::Source::kTables        ? "time tables"
                       : scene.source == vehicle::CarScene::Source::kRecordedDrive ? "recorded drive"
                                                                                   : "closed-loop driver";
  summary["controls"] = source;
  double distance = 0.0, v_max = 0.0, ax_min = 0.0, ax_max = 0.0, ay_peak = 0.0, r_peak = 0.0, rpm_max = 0.0;
  double y_min = samples.front().state.y, y_max = y_min;
  int gear_max = 0;
  bool stalled = false;
  for (std::size_t k = 1; k < samples.size(); ++k) {
    const vehicle::VehicleState& s = samples[k].state;
    distance += std::hypot(s.x - samples[k - 1].state.x, s.y - samples[k - 1].state.y);
    v_max = std::max(v_max, vehicle::Speed(s));
    ax_min = std::min(ax_min, s.ax);
    ax_max = std::max(ax_max, s.ax);
    ay_peak = std::max(ay_peak, std::abs(s.ay));
    r_peak = std::max(r_peak, std::abs(s.r));
    rpm_max = std::max(rpm_max, vehicle::EngineRpm(s));
    y_min = std::min(y_min, s.y);
    y_max = std::max(y_max, s.y);
    if (s.clutch_locked) gear_max = std::max(gear_max, samples[k].input.gear);
    stalled = stalled || !s.engine_running;
  }
  summary["drive"] = {{"distance_m", distance},
                      {"max_speed_mps", v_max},
                      {"max_speed_kmh", v_max * 3.6},
                      {"highest_gear_engaged", gear_max},
                      {"max_engine_rpm", rpm_max},
                      {"min_ax_mps2", ax_min},
                      {"max_ax_mps2", ax_max},
                      {"peak_abs_ay_mps2", ay_peak},
                      {"peak_abs_yaw_rate_radps", r_peak},
                      {"y_range_m", {y_min, y_max}},
                      {"final_speed_mps", vehicle::Speed(samples.back().state)},
                      {"stalled", stalled}};
  AddCarCueing(scene, samples, table, summary, out_dir, options.mca);
  table.WriteCsv(out_dir / "trial.csv", options.decimate);
  if (options.video) {
    RenderCarTrial(scene, samples, options, summary, out_dir);
  } else {
    summary["render"] = {{"skipped", "--no-video"}};
  }
  WriteFileAtomically(out_dir / "summary.json", summary.dump(2) + "\n");
  std::vector<std::filesystem::path> written;
  for (const char* name : {"trial.csv", "summary.json", "mca.png", "mca.svg", "mca.plot.csv", "video.mp4", "frames.csv"}) {
    if (std::filesystem::exists(out_dir / name)) written.push_back(out_dir / name);
  }
  return written;
}

}  // namespace pwsim::report
