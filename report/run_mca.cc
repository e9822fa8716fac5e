#include "report/run_mca.h"

#include "mca/offline_optimum.h"
#include "mca/rail_yaw.h"
#include "mca/vehicle_prediction.h"

#include <cmath>
#include <string>

#include "mca/config.h"
#include "mca/cueing.h"
#include "mca/head_motion.h"
#include "plot/plot.h"

namespace pwsim::report {
namespace {

constexpr const char* kAxis[3] = {"x", "y", "z"};

using mca::Dof;


nlohmann::ordered_json RateCuesJson(const mca::RateCues& r) {
  return {{"count", r.count}, {"duration_s", r.duration}, {"max_rate_degps", r.max_rate / mca::kDegToRad}};
}

template <typename Get>
std::vector<double> Column(std::size_t rows, Get get) {
  std::vector<double> values(rows);
  for (std::size_t r = 0; r < rows; ++r) values[r] = get(r);
  return values;
}

}  // namespace

nlohmann::ordered_json AxisJson(const mca::AxisConsistency& c, const char* unit) {
  return {{"correlation", c.correlation},
          {std::string("rms_error_") + unit, c.rms_error},
          {"gain", c.gain},
          {"xcorr_peak", c.xcorr},
          {"lag_s", c.lag},
          {std::string("peak_true_") + unit, c.peak_true},
          {std::string("peak_platform_") + unit, c.peak_platform},
          {"wrong_sign_count", c.wrong_sign_count},
          {"wrong_sign_duration_s", c.wrong_sign_duration}};
}

nlohmann::ordered_json PlatformUsageJson(const mca::ConsistencyReport& report) {
  nlohmann::ordered_json usage = nlohmann::ordered_json::array();
  for (const mca::DofUsage& u : report.usage) {
    const bool rot = mca::IsRotational(u.dof);
    const double k = rot ? 1.0 / mca::kDegToRad : 1.0;
    usage.push_back({{"dof", std::string(mca::DofName(u.dof))},
                     {rot ? "peak_pose_deg" : "peak_pose_m", u.peak_pose * k},
                     {rot ? "peak_rate_degps" : "peak_rate_mps", u.peak_rate * k},
                     {rot ? "peak_accel_degps2" : "peak_accel_mps2", u.peak_accel * k},
                     {"pose_fraction_of_limit", u.pose_fraction},
                     {"rate_fraction_of_limit", u.rate_fraction},
                     {"accel_fraction_of_limit", u.accel_fraction}});
  }
  return usage;
}

bool WithinLimits(const mca::ConsistencyReport& report) {
  return report.limits.within && report.limits.positions_checked;
}

nlohmann::ordered_json ActuatorsJson(const mca::PlatformSpec& platform, const mca::ConsistencyReport& report) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const mca::ActuatorUsage& u : report.actuators) {
    const mca::Actuator& a = platform.mechanism.actuator(u.index);
    const bool rotary = a.kind == mca::ActuatorKind::kRotary;
    const double k = rotary ? 1.0 / mca::kDegToRad : 1.0;
    const std::string unit = rotary ? "deg" : "m";
    nlohmann::ordered_json j;
    j["name"] = a.name;
    j["kind"] = mca::ActuatorKindName(a.kind);
    if (std::isfinite(a.limits.min)) j["stroke_" + unit] = {a.limits.min * k, a.limits.max * k};
    j["position_range_" + unit] = {u.min_position * k, u.max_position * k};
    j["stroke_use"] = u.stroke_use;
    j["box_stroke_use"] = u.box_stroke_use;
    j["speed_fraction"] = u.speed_fraction;
    j["accel_fraction"] = u.accel_fraction;
    list.push_back(j);
  }
  return list;
}

nlohmann::ordered_json LimitsJson(const mca::PlatformSpec& platform, const mca::ConsistencyReport& report) {
  const mca::ActuatorLimitsCheck& c = report.limits;
  nlohmann::ordered_json j;
  j["within_limits"] = WithinLimits(report);
  j["from"] = "actuator positions q = IK(command pose), what the drives get; their differences per tick; "
              "every q checked back by forward kinematics";
  j["tolerance"] = mca::kLimitTolerance;
  j["tolerance_what"] = "relative: speed and acceleration up to limit x (1 + tolerance), stroke ends +- tolerance x stroke";
  j["forward_residual"] = c.forward_residual;
  j["forward_tolerance"] = mca::kForwardTolerance;
  j["ik_failures"] = c.ik_failures;
  j["worst_fraction"] = c.worst_fraction;
  if (c.worst_actuator >= 0) {
    j["worst"] = platform.mechanism.actuator(c.worst_actuator).name + " " + c.worst_what;
  }
  return j;
}

nlohmann::ordered_json PerceivedJson(const mca::PerceivedError& p) {
  return {{"rms_error", p.rms},
          {"what", "RMS of platform - vehicle over the otolith channels [m/s^2] and the canal channels [rad/s] x 10"},
          {"correlation", p.correlation.zero_lag},
          {"xcorr_peak", p.correlation.peak},
          {"lag_s", p.correlation.lag}};
}

nlohmann::ordered_json ConsistencyJson(const mca::ConsistencyReport& report) {
  nlohmann::ordered_json consistency;
  for (std::size_t i = 0; i < 3; ++i) consistency["otolith"][kAxis[i]] = AxisJson(report.otolith[i], "mps2");
  for (std::size_t i = 0; i < 3; ++i) consistency["canals"][kAxis[i]] = AxisJson(report.canals[i], "radps");
  return consistency;
}

WrongSignCues CountWrongSignCues(const mca::ConsistencyReport& report) {
  WrongSignCues out;
  for (const auto* axes : {&report.otolith, &report.canals}) {
    for (const mca::AxisConsistency& c : *axes) {
      out.count += c.wrong_sign_count;
      out.duration_s += c.wrong_sign_duration;
    }
  }
  return out;
}

nlohmann::ordered_json ComparisonJson(const mca::McaConfig& config, const std::vector<mca::HeadMotion>& head, double dt,
                                      mca::VehiclePredictor* predictor, bool rail_yaw) {
  nlohmann::ordered_json j;
  j["what"] = "this trial's head motion through each algorithm: the washout, the MPC without preview (as live), "
              "the offline ceiling (mca/offline_optimum.h)";
  auto row = [&](const mca::CueingTrace& trace, bool mpc) {
    nlohmann::ordered_json r = PerceivedJson(mca::EvaluatePerceivedError(trace, dt));
    r.erase("what");
    if (mpc) r["fallbacks_to_washout"] = trace.mpc.fallbacks;
    return r;
  };
  mca::McaConfig washout = config;
  washout.algorithm = mca::McaAlgorithm::kWashout;
  j["washout"] = row(rail_yaw ? mca::RunRailYawCueing(washout, head, dt) : mca::RunCueing(washout, head, dt), false);
  mca::McaConfig mpc = config;
  mpc.algorithm = mca::McaAlgorithm::kMpc;
  mpc.mpc.preview = false;
  j["mpc"] = row(rail_yaw ? mca::RunRailYawCueing(mpc, head, dt, predictor) : mca::RunCueing(mpc, head, dt, predictor), true);
  j["mpc"]["prediction"] = predictor != nullptr ? "the vehicle model with the driver's present input held"
                                                : "the present input's transients decaying";
  j["offline"] = row(mca::RunOfflineOptimum(config, head, dt, rail_yaw), false);
  return j;
}

void AddCueMotionColumns(const mca::McaConfig& config, const mca::CueingTrace& trace,
                         TrialTable& table) {
  const std::size_t n = trace.commands.size();
  for (std::size_t i = 0; i < 3; ++i) {
    table.Add(std::string("head_fs_") + kAxis[i] + "_mps2", Column(n, [&](std::size_t k) { return trace.truth[k].fs[i]; }));
  }
  for (std::size_t i = 0; i < 3; ++i) {
    table.Add(std::string("head_w_") + kAxis[i] + "_radps", Column(n, [&](std::size_t k) { return trace.truth[k].w[i]; }));
  }
  for (Dof dof : mca::kAllDofs) {
    if (!config.platform.Has(dof)) continue;
    const auto i = static_cast<std::size_t>(mca::Index(dof));
    table.Add("plat_" + std::string(mca::DofName(dof)) + "_" + std::string(mca::DofUnit(dof)),
              Column(n, [&](std::size_t k) { return trace.commands[k].pose[i]; }));
  }
  for (std::size_t i = 0; i < 3; ++i) {
    table.Add(std::string("head_plat_fs_") + kAxis[i] + "_mps2",
              Column(n, [&](std::size_t k) { return trace.delivered[k].fs[i]; }));
  }
  for (std::size_t i = 0; i < 3; ++i) {
    table.Add(std::string("head_plat_w_") + kAxis[i] + "_radps",
              Column(n, [&](std::size_t k) { return trace.delivered[k].w[i]; }));
  }
}

void AddVestibularColumns(const mca::CueingTrace& trace, TrialTable& table) {
  const std::size_t n = trace.commands.size();
  for (const char* who : {"true", "plat"}) {
    const auto& perceived = std::string(who) == "true" ? trace.perceived_true : trace.perceived_platform;
    for (std::size_t i = 0; i < 3; ++i) {
      table.Add(std::string("vest_") + who + "_oto_" + kAxis[i] + "_mps2",
                Column(n, [&](std::size_t k) { return perceived[k].fs[i]; }));
    }
    for (std::size_t i = 0; i < 3; ++i) {
      table.Add(std::string("vest_") + who + "_scc_" + kAxis[i] + "_radps",
                Column(n, [&](std::size_t k) { return perceived[k].w[i]; }));
    }
  }
  table.Add("mca_fault", Column(n, [&](std::size_t k) { return trace.commands[k].fault ? 1.0 : 0.0; }));
}

void McaChoice::Apply(mca::McaConfig& config) const {
  if (platform) {
    config.platform = mca::ReadPlatformFile(*platform);
    config.platform_source = platform->string();
  }
  if (algorithm) config.algorithm = *algorithm;
  if (preview) config.mpc.preview = true;
}


nlohmann::ordered_json AlgorithmJson(const mca::McaConfig& config, const mca::CueingTrace& trace) {
  nlohmann::ordered_json j;
  j["name"] = mca::McaAlgorithmName(trace.algorithm);
  if (trace.whole_trial) {
    j["name"] = "offline";
    j["what"] = "the whole trial optimised at once, open loop (mca/offline_optimum.h): the ceiling";
  } else if (trace.algorithm == mca::McaAlgorithm::kMpc) {
    j["preview"] = trace.preview     ? "the whole trial ahead (recorded or simulated)"
                   : trace.predictor ? "none: the vehicle model run ahead with the driver's present input held"
                                     : "none: the present input's transients decay (prediction_decay_s " +
                                           std::to_string(config.mpc.prediction_decay) + ")";
    j["horizon_s"] = config.mpc.control_period + (config.mpc.BlockCount() - 1) * config.mpc.block;
    j["control_period_s"] = config.mpc.control_period;
    j["blocks"] = config.mpc.BlockCount();
    j["solver"] = config.mpc.solver == mca::QpAlgorithm::kActiveSet
                      ? std::string("dual active set (mca/qp_active_set.h)")
                      : std::string("alglib minqp ") + std::string(mca::QpAlgorithmName(config.mpc.solver));
    j["solves"] = trace.mpc.solves;
    j["fallbacks_to_washout"] = trace.mpc.fallbacks;
    j["fallbacks_what"] = "control steps whose QP failed and followed the classical washout";
  }
  return j;
}

void AddMotionCueing(const Scene& scene, const std::vector<ChairSample>& samples, TrialTable& table,
                     nlohmann::ordered_json& summary, const std::filesystem::path& out_dir,
                     const McaChoice& choice) {
  const std::size_t n = samples.size();
  std::vector<mca::HeadMotion> head(n);
  for (std::size_t k = 0; k < n; ++k) head[k] = mca::HeadMotionFromChair(samples[k], scene.occupant.head_offset);
  VisualPose visual;
  visual.x = Column(n, [&](std::size_t k) { return samples[k].drive.x; });
  visual.z = Column(n, [&](std::size_t k) { return samples[k].lm.z; });
  visual.pitch = Column(n, [&](std::size_t k) { return samples[k].lm.pitch; });
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k) t[k] = scene.clock.TimeAt(samples[k].tick);
  mca::ChairRolloutPredictor predictor(scene);  // the MPC's vehicle model without preview
  AddMotionCueingStage(scene, t, head, visual, table, summary, out_dir, choice, &predictor);
}

void AddMotionCueingStage(const Scene& scene, const std::vector<double>& t,
                          const std::vector<mca::HeadMotion>& head, const VisualPose& visual,
                          TrialTable& table, nlohmann::ordered_json& summary,
                          const std::filesystem::path& out_dir, const McaChoice& choice,
                          mca::VehiclePredictor* predictor) {
  mca::McaConfig config = mca::LoadMcaConfig(scene);
  choice.Apply(config);
  const double dt = scene.clock.dt();
  const std::size_t n = head.size();
  const bool planar = !visual.yaw.empty();  // a chair free in the plane: every axis reported
  const mca::CueingTrace trace = choice.offline ? mca::RunOfflineOptimum(config, head, dt)
                                                : mca::RunCueing(config, head, dt, predictor);
  const mca::ConsistencyReport report = mca::EvaluateConsistency(config, trace, dt);

  // trial.csv columns
  AddCueMotionColumns(config, trace, table);
  // the vehicle motion to show: the chair pose X_WV (render/ puts the eyes at head_offset on it)
  table.Add("vis_x_m", visual.x);
  if (planar) table.Add("vis_y_m", visual.y);
  table.Add("vis_z_m", visual.z);
  if (planar) table.Add("vis_roll_rad", visual.roll);
  table.Add("vis_pitch_rad", visual.pitch);
  if (planar) table.Add("vis_yaw_rad", visual.yaw);
  table.Add("vis_tilt_pitch_rad", Column(n, [&](std::size_t k) { return trace.commands[k].tilt_pitch; }));
  table.Add("vis_tilt_roll_rad", Column(n, [&](std::size_t k) { return trace.commands[k].tilt_roll; }));
  // the vehicle's sustained attitude the platform presents (a slope, a ramp: shown by the visuals)
  if (config.platform.Has(Dof::kPitch)) {
    table.Add("plat_bank_pitch_rad", Column(n, [&](std::size_t k) { return trace.commands[k].bank_pitch; }));
  }
  if (config.platform.Has(Dof::kRoll)) {
    table.Add("plat_bank_roll_rad", Column(n, [&](std::size_t k) { return trace.commands[k].bank_roll; }));
  }
  AddVestibularColumns(trace, table);

  // summary.json
  nlohmann::ordered_json mca_json;
  mca_json["algorithm"] = AlgorithmJson(config, trace);
  nlohmann::ordered_json platform_json;
  platform_json["name"] = config.platform.name;
  platform_json["source"] = config.platform_source;
  platform_json["usage"] = PlatformUsageJson(report);
  if (planar) platform_json["axes_in_use"] = AxesInUse(report);
  platform_json["within_limits"] = WithinLimits(report);
  mca_json["platform"] = platform_json;
  mca_json["actuators"] = ActuatorsJson(config.platform, report);
  mca_json["limits"] = LimitsJson(config.platform, report);
  mca_json["perceived"] = PerceivedJson(report.perceived);
  if (choice.compare) mca_json["comparison"] = ComparisonJson(config, head, dt, predictor, false);
  double max_tilt = 0.0, max_roll_tilt = 0.0, max_bank_pitch = 0.0, max_bank_roll = 0.0;
  for (const mca::McaCommand& c : trace.commands) {
    max_tilt = std::max(max_tilt, std::abs(c.tilt_pitch));
    max_roll_tilt = std::max(max_roll_tilt, std::abs(c.tilt_roll));
    max_bank_pitch = std::max(max_bank_pitch, std::abs(c.bank_pitch));
    max_bank_roll = std::max(max_bank_roll, std::abs(c.bank_roll));
  }
  mca_json["tilt"] = {{"max_pitch_deg", max_tilt / mca::kDegToRad},
                      {"rate_limit_degps", config.washout.tilt_pitch.max_rate / mca::kDegToRad},
                      {"pitch_rate_above_threshold", RateCuesJson(report.tilt_pitch)},
                      {"roll_rate_above_threshold", RateCuesJson(report.tilt_roll)}};
  mca_json["tilt"]["max_bank_pitch_deg"] = max_bank_pitch / mca::kDegToRad;
  mca_json["tilt"]["max_bank_roll_deg"] = max_bank_roll / mca::kDegToRad;
  mca_json["tilt"]["band"] = "the platform's pitch and roll rates beyond or against the vehicle's own stay within "
                             "the tilt-rate threshold (mca/mpc.h); bank: the vehicle's sustained attitude presented";
  if (planar) {
    mca_json["tilt"]["max_roll_deg"] = max_roll_tilt / mca::kDegToRad;
    mca_json["tilt"]["roll_rate_limit_degps"] = config.washout.tilt_roll.max_rate / mca::kDegToRad;
  }
  mca_json["consistency"] = ConsistencyJson(report);
  const WrongSignCues wrong = CountWrongSignCues(report);
  mca_json["false_cues"] = {{"wrong_sign_count", wrong.count},
                            {"wrong_sign_duration_s", wrong.duration_s},
                            {"tilt_rate_count", report.tilt_pitch.count + report.tilt_roll.count},
                            {"tilt_rate_duration_s", report.tilt_pitch.duration + report.tilt_roll.duration}};
  mca_json["fault_ticks"] = report.fault_ticks;
  summary["mca"] = mca_json;

  // mca.png: vehicle against platform at the head
  auto series = [&](const std::string& label, unsigned color, auto get) {
    plot::Series s;
    s.label = label;
    s.x = t;
    s.y = Column(n, get);
    s.color = color;
    return s;
  };
  auto panel = [](const char* title, const char* y_label, std::vector<plot::Series> series_list) {
    plot::Panel p;
    p.title = title;
    p.y_label = y_label;
    p.series = std::move(series_list);
    return p;
  };
  plot::Figure figure;
  figure.title = "What the occupant feels at the head: in the real chair (vehicle) and on the " +
                 config.platform.name + " motion platform";
  figure.x_label = "time [s]";
  const std::string in_chair = "in the real chair (vehicle)", on_platform = "on the platform";
  figure.panels.push_back(panel("forward push felt (surge specific force, forward +)", "surge force [m/s²]",
                           {series(in_chair, plot::color::kVehicle, [&](std::size_t k) { return trace.truth[k].fs[0]; }),
                            series(on_platform, plot::color::kPlatform, [&](std::size_t k) { return trace.delivered[k].fs[0]; })}));
  figure.panels.push_back(panel("vertical push felt beyond gravity (heave specific force - g, up +)", "heave force - g [m/s²]",
                           {series(in_chair, plot::color::kVehicle, [&](std::size_t k) { return trace.truth[k].fs[2] - mca::kGravity; }),
                            series(on_platform, plot::color::kPlatform, [&](std::size_t k) { return trace.delivered[k].fs[2] - mca::kGravity; })}));
  figure.panels.push_back(panel("pitch rate (nose-up +)", "pitch rate [deg/s]",
                           {series(in_chair, plot::color::kVehicle, [&](std::size_t k) { return -trace.truth[k].w[1] / mca::kDegToRad; }),
                            series(on_platform, plot::color::kPlatform, [&](std::size_t k) { return -trace.delivered[k].w[1] / mca::kDegToRad; })}));
  figure.panels.push_back(panel("platform pitch (nose-up +) and the part of it that tilts the occupant to present a sustained push",
                           "pitch angle [deg]",
                           {series("platform pitch", plot::color::kGreen,
                                   [&](std::size_t k) { return trace.commands[k].pose[mca::Index(Dof::kPitch)] / mca::kDegToRad; }),
                            series("of which tilt coordination", plot::color::kTilt,
                                   [&](std::size_t k) { return trace.commands[k].tilt_pitch / mca::kDegToRad; })}));
  std::filesystem::create_directories(out_dir);
  plot::WriteFigure(out_dir / "mca.png", figure);
  if (!planar) return;

  // mca_lateral.png: the axes a turning chair adds (sway force by roll tilt, roll and yaw)
  plot::Figure lateral;
  lateral.title = "Sideways motion felt at the head: in the real chair (vehicle) and on the " +
                  config.platform.name + " motion platform";
  lateral.x_label = "time [s]";
  lateral.panels.push_back(panel("sideways push felt (sway specific force, to the left +)", "sway force [m/s²]",
                            {series(in_chair, plot::color::kVehicle, [&](std::size_t k) { return trace.truth[k].fs[1]; }),
                             series(on_platform, plot::color::kPlatform, [&](std::size_t k) { return trace.delivered[k].fs[1]; })}));
  lateral.panels.push_back(panel("roll rate (left side up +)", "roll rate [deg/s]",
                            {series(in_chair, plot::color::kVehicle, [&](std::size_t k) { return trace.truth[k].w[0] / mca::kDegToRad; }),
                             series(on_platform, plot::color::kPlatform, [&](std::size_t k) { return trace.delivered[k].w[0] / mca::kDegToRad; })}));
  lateral.panels.push_back(panel("yaw rate (turning left +)", "yaw rate [deg/s]",
                            {series(in_chair, plot::color::kVehicle, [&](std::size_t k) { return trace.truth[k].w[2] / mca::kDegToRad; }),
                             series(on_platform, plot::color::kPlatform, [&](std::size_t k) { return trace.delivered[k].w[2] / mca::kDegToRad; })}));
  lateral.panels.push_back(panel("platform roll (left side up +), the part of it that tilts the occupant, and platform yaw",
                            "angle [deg]",
                            {series("platform roll", plot::color::kGreen,
                                    [&](std::size_t k) { return trace.commands[k].pose[mca::Index(Dof::kRoll)] / mca::kDegToRad; }),
                             series("of which tilt coordination", plot::color::kTilt,
                                    [&](std::size_t k) { return trace.commands[k].tilt_roll / mca::kDegToRad; }),
                             series("platform yaw", plot::color::kPurple,
                                    [&](std::size_t k) { return trace.commands[k].pose[mca::Index(Dof::kYaw)] / mca::kDegToRad; })}));
  plot::WriteFigure(out_dir / "mca_lateral.png", lateral);
}

nlohmann::ordered_json AxesInUse(const mca::ConsistencyReport& report, double min_fraction) {
  nlohmann::ordered_json axes = nlohmann::ordered_json::array();
  for (const mca::DofUsage& u : report.usage) {
    if (u.pose_fraction >= min_fraction) axes.push_back(std::string(mca::DofName(u.dof)));
  }
  return axes;
}

}  // namespace pwsim::report
