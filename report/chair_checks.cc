#include "report/chair_checks.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/atomic_file.h"
#include "engine/caster.h"
#include "engine/full_chair.h"
#include "plot/plot.h"

namespace pwsim::report {
namespace {

constexpr double kDt = 1e-3;
constexpr double kPi = std::numbers::pi;
constexpr double kG = kStandardGravity;

void Hold(FullChairSimulator& sim, JoystickInput input, double seconds) {
  const int ticks = static_cast<int>(std::lround(seconds / kDt));
  for (int k = 0; k < ticks; ++k) sim.Advance(input);
}

/// A 4-wheel rear-drive variant of `chair` (its mass, inertias, d_CM and LM): casters 0.45 m
/// ahead of the drive wheels, O_V 0.15 m ahead of the drive axle; GM α = (0.3, 0.7), β_12 = 1.
Chair RearDriveVariant(const Chair& chair) {
  Chair variant = chair;
  variant.name = chair.name + "_rear_drive_4w";
  variant.wheels = {{"front_caster", 0.30, 0.10}, {"drive", -0.15, 0.17}};
  variant.gm = GeometricParams{{0.3, 0.7}, {{0, 1, 1.0}}};
  return variant;
}

plot::Panel MakePanel(const std::string& title, const std::string& y_label) {
  plot::Panel panel;
  panel.title = title;
  panel.y_label = y_label;
  return panel;
}

/// One panel under a title, as every chair check draws it: DIR/<name>.png, .svg, .plot.csv, .gp.
void WritePanelFigure(const std::filesystem::path& stem, const std::string& title, const std::string& x_label,
                      const plot::Panel& panel) {
  plot::Figure fig;
  fig.title = title;
  fig.x_label = x_label;
  fig.panels.push_back(panel);
  plot::WriteFigure(stem, fig);
}

nlohmann::ordered_json Turn(const Chair& chair, double load, const std::filesystem::path& out) {
  const PlanarLayout layout = DefaultPlanarLayout(chair);
  const FloorMap floor;
  const ControllerProfile& p = layout.controller;
  std::vector<double> radius, v_over_w, setpoint_radius;
  double worst_kinematic = 0.0, worst_setpoint = 0.0;
  for (double forward : {0.3, 0.5, 0.7, 0.9}) {
    for (double turn : {0.3, 0.6, 0.9}) {
      FullChairSimulator sim(chair, layout, floor, load, kDt);
      sim.Start({});
      Hold(sim, {forward, turn}, 12.0);
      const FullChairSample a = sim.sample();
      Hold(sim, {forward, turn}, 4.0);
      const FullChairSample& b = sim.sample();
      const double r = (b.distance - a.distance) / (b.planar.yaw - a.planar.yaw);
      const ControllerState set = ControllerTarget(p, {forward, turn});
      radius.push_back(r);
      v_over_w.push_back(b.planar.v / b.planar.yaw_rate);
      setpoint_radius.push_back(set.speed / set.yaw_rate);
      worst_kinematic = std::max(worst_kinematic, std::abs(r - v_over_w.back()) / r);
      worst_setpoint = std::max(worst_setpoint, std::abs(r - setpoint_radius.back()) / r);
    }
  }
  plot::Panel panel = MakePanel("radius of the path (arc length / heading change over 4 s)", "path radius [m]");
  panel.series.push_back({"pwsim full-DoF chair", v_over_w, radius, plot::Style::kPoints, plot::color::kSimulated});
  panel.series.push_back({"closed form R = v/omega", v_over_w, v_over_w, plot::Style::kLines, plot::color::kReference});
  panel.series.push_back({"profile set-points v*/omega*", v_over_w, setpoint_radius, plot::Style::kPoints, plot::color::kGreen});
  WritePanelFigure(out / "chair_turn", "steady turns: the path's radius against v/omega (12 deflection pairs)",
                   "speed over turn rate of the chair, v/omega [m]", panel);
  return {{"turns", radius.size()},
          {"worst_relative_difference_radius_vs_v_over_omega", worst_kinematic},
          {"worst_relative_difference_radius_vs_setpoints", worst_setpoint}};
}

nlohmann::ordered_json Spot(const Chair& chair, double load) {
  const PlanarLayout layout = DefaultPlanarLayout(chair);
  const FloorMap floor;
  FullChairSimulator sim(chair, layout, floor, load, kDt);
  sim.Start({});
  Hold(sim, {0.0, 1.0}, 3.0);
  const FullChairSample swung = sim.sample();
  Hold(sim, {0.0, 1.0}, 6.0);
  const FullChairSample& s = sim.sample();
  const double c = std::cos(s.planar.yaw), sn = std::sin(s.planar.yaw);
  // the drive-axle midpoint D = O_V + R(ψ) (x_D, 0)
  const double dx = s.planar.x + c * sim.drive_x() - swung.planar.x - std::cos(swung.planar.yaw) * sim.drive_x();
  const double dy = s.planar.y + sn * sim.drive_x() - swung.planar.y - std::sin(swung.planar.yaw) * sim.drive_x();
  return {{"yaw_rate_radps", s.planar.yaw_rate},
          {"max_turn_rate_radps", layout.controller.max_turn_rate},
          {"axle_midpoint_drift_over_6s_m", std::hypot(dx, dy)},
          {"axle_midpoint_offset_after_caster_swing_m", std::hypot(swung.planar.x, swung.planar.y)}};
}

nlohmann::ordered_json Caster(const Chair& chair, double load, const std::filesystem::path& out) {
  const PlanarLayout layout = DefaultPlanarLayout(chair);
  const FloorMap floor;
  FullChairSimulator sim(chair, layout, floor, load, kDt);
  sim.Start({}, 0.05);
  Hold(sim, {-0.8, 0.0}, 3.0);
  Hold(sim, {0.0, 0.0}, 1.0);
  const double angle0 = sim.sample().casters[0].angle;
  const double s0 = sim.sample().drive.x;
  std::vector<double> travel, angle_deg, law_deg;
  double s_at_10 = NAN, s_at_10_over_e = NAN;
  // the law starts where the caster leaves its friction dead band: fit its start at tan(δ/2) = 10
  for (int k = 0; k < 4000; ++k) {
    const FullChairSample& s = sim.Advance({0.6, 0.0});
    const double q = std::abs(std::tan(0.5 * s.casters[0].angle));
    if (std::isnan(s_at_10) && q < 10.0) s_at_10 = s.drive.x;
    if (!std::isnan(s_at_10) && std::isnan(s_at_10_over_e) && q < 10.0 / std::exp(1.0)) s_at_10_over_e = s.drive.x;
    travel.push_back(s.drive.x - s0);
    angle_deg.push_back(std::abs(s.casters[0].angle) * 180.0 / kPi);
  }
  for (double s : travel) {
    const double law = std::isnan(s_at_10) || s + s0 < s_at_10
                           ? NAN
                           : std::abs(KinematicCasterAngle(2.0 * std::atan(10.0), layout.caster.trail, s + s0 - s_at_10));
    law_deg.push_back(law * 180.0 / kPi);
  }
  plot::Panel panel = MakePanel("swivel angle |delta| (180 deg: trailing backwards, 0: trailing forwards)", "caster swivel angle [deg]");
  panel.series.push_back({"pwsim caster (swivel inertia, friction, scrub)", travel, angle_deg, plot::Style::kLines, plot::color::kSimulated});
  panel.series.push_back({"kinematic law tan(d/2) = tan(d0/2) exp(-s/t)", travel, law_deg, plot::Style::kLines, plot::color::kReference});
  WritePanelFigure(out / "chair_caster", "caster realignment after reversing (front-left caster, 0.6 deflection forward)",
                   "travel forward [m]", panel);
  const double e_travel = s_at_10_over_e - s_at_10;
  return {{"trail_m", layout.caster.trail},
          {"angle_after_reversing_deg", angle0 * 180.0 / kPi},
          {"travel_for_factor_e_m", e_travel},
          {"relative_difference_to_trail", (e_travel - layout.caster.trail) / layout.caster.trail},
          {"final_angle_deg", angle_deg.back()}};
}

nlohmann::ordered_json Pull(const Chair& chair, double load, const std::filesystem::path& out) {
  const Chair variant = RearDriveVariant(chair);
  const PlanarLayout layout = DefaultPlanarLayout(variant);
  const FloorMap floor;
  plot::Panel panel = MakePanel("heading (left positive)", "heading [deg]");
  nlohmann::ordered_json result;
  double left = 0.0, right = 0.0;
  for (double start_deg : {90.0, 0.0, -90.0}) {
    FullChairSimulator sim(variant, layout, floor, load, kDt);
    sim.Start({}, start_deg * kPi / 180.0);
    std::vector<double> t, yaw;
    for (int k = 1; k <= 3000; ++k) {
      const FullChairSample& s = sim.Advance({0.8, 0.0});
      if (k % 10 == 0) {
        t.push_back(k * kDt);
        yaw.push_back(s.planar.yaw * 180.0 / kPi);
      }
    }
    const std::string name = start_deg > 0 ? "casters pointing left" : start_deg < 0 ? "casters pointing right" : "casters straight";
    panel.series.push_back({name, t, yaw, plot::Style::kLines, 0});
    if (start_deg > 0) left = sim.sample().planar.yaw;
    if (start_deg < 0) right = sim.sample().planar.yaw;
    result[start_deg > 0 ? "heading_after_3s_casters_left_deg" : start_deg < 0 ? "heading_after_3s_casters_right_deg"
                                                                               : "heading_after_3s_casters_straight_deg"] =
        sim.sample().planar.yaw * 180.0 / kPi;
  }
  WritePanelFigure(out / "chair_pull", "rear-drive 4-wheel variant started with its casters across (0.8 deflection forward)",
                   "time [s]", panel);
  result["pulls_toward_the_casters"] = left > 0.0 && right < 0.0;
  result["mirror_asymmetry_deg"] = (left + right) * 180.0 / kPi;
  return result;
}

nlohmann::ordered_json Roll(const Chair& chair, double load, const std::filesystem::path& out) {
  const PlanarLayout layout = DefaultPlanarLayout(chair);
  const double mass = MovingMass(chair, load);
  RollTorqueParams torque;
  torque.gravity_lever = mass * chair.cm_height;
  double gamma = 0.0;
  for (const WheelRow& row : layout.rows) gamma += row.roll_weight;
  std::vector<double> grade_pct, simulated_deg, closed_deg;
  double worst = 0.0;
  for (double grade = 0.0; grade <= 0.0801; grade += 0.01) {
    FloorMap floor;
    floor.features = {PlaneFeature(1.0, 20.0, -3.0, 3.0, 0.0, grade, 1.0)};
    FullChairSimulator sim(chair, layout, floor, load, kDt, {}, torque);
    sim.Start({});
    Hold(sim, {0.6, 0.0}, 6.0);
    Hold(sim, {0.0, 0.0}, 4.0);
    const double roll_gm = gamma * std::asin(grade);
    double phi = roll_gm;  // K (φ - φ_GM) = M g d sin φ, Newton
    for (int i = 0; i < 50; ++i) {
      phi -= (layout.k_roll * (phi - roll_gm) - torque.gravity_lever * kG * std::sin(phi)) /
             (layout.k_roll - torque.gravity_lever * kG * std::cos(phi));
    }
    grade_pct.push_back(100.0 * grade);
    simulated_deg.push_back(sim.sample().roll * 180.0 / kPi);
    closed_deg.push_back(phi * 180.0 / kPi);
    worst = std::max(worst, std::abs(sim.sample().roll - phi));
  }
  plot::Panel panel = MakePanel("roll of the lumped model, left side up", "roll angle [deg]");
  panel.series.push_back({"pwsim full-DoF chair", grade_pct, simulated_deg, plot::Style::kPoints, plot::color::kSimulated});
  panel.series.push_back({"closed form K_phi (phi - phi_GM) = M g d sin phi", grade_pct, closed_deg, plot::Style::kLines, plot::color::kReference});
  WritePanelFigure(out / "chair_roll", "static roll on a cross-slope (chair stopped on it)",
                   "cross-slope grade [%]", panel);
  return {{"k_roll_nmprad", layout.k_roll}, {"gravity_lever_kgm", torque.gravity_lever}, {"worst_abs_difference_rad", worst},
          {"roll_at_8pct_deg", simulated_deg.back()}};
}

nlohmann::ordered_json Braking(const Chair& chair, double load, const std::filesystem::path& out) {
  const Chair variant = RearDriveVariant(chair);
  const PlanarLayout layout = DefaultPlanarLayout(variant);
  const FloorMap floor;
  FullChairSimulator sim(variant, layout, floor, load, kDt);
  sim.Start({});
  Hold(sim, {1.0, 0.0}, 3.0);
  const double mass = MovingMass(variant, load);
  const double length = variant.wheels[0].x - variant.wheels[1].x;
  const double h = variant.cm_height;
  std::vector<double> t, front, closed;
  double worst = 0.0;
  for (int k = 1; k <= 2500; ++k) {
    const FullChairSample& s = sim.Advance({0.0, 0.0});
    const double expected = mass * (kG * (layout.cm_x - variant.wheels[1].x) - s.a_x * h) / length;
    const double measured = s.contacts[0].load + s.contacts[1].load;
    worst = std::max(worst, std::abs(measured - expected) / expected);
    if (k % 5 == 0) {
      t.push_back(k * kDt);
      front.push_back(measured);
      closed.push_back(expected);
    }
  }
  plot::Panel panel = MakePanel("load on the front (caster) row", "front-row load [N]");
  panel.series.push_back({"pwsim full-DoF chair", t, front, plot::Style::kLines, plot::color::kSimulated});
  panel.series.push_back({"closed form M (g (x_c - x_r) - a_x h) / L", t, closed, plot::Style::kLines, plot::color::kReference});
  WritePanelFigure(out / "chair_braking", "load transfer while braking from 1.6 m/s (rear-drive 4-wheel variant)",
                   "time after releasing the joystick [s]", panel);
  return {{"worst_relative_difference", worst}, {"static_front_load_n", mass * kG * (layout.cm_x - variant.wheels[1].x) / length}};
}

nlohmann::ordered_json Tip(const Chair& chair, double load, const std::filesystem::path& out) {
  const Chair variant = RearDriveVariant(chair);
  PlanarLayout layout = DefaultPlanarLayout(variant);
  // The closed form (x_c - x_r)/h takes each wheel's contact under its axle: point contacts and
  // rigid tyres. Wheels of radius R touch a slope R sin(grade) off that point and their tyres
  // yield, which moves the grade; they have their own closed-form checks
  // (tests/engine/full_chair_wheels_test.cc).
  layout.rolling_envelope = false;
  const double h = variant.cm_height;
  const auto tips_at = [&](double grade, const PlanarLayout& l, double* front_load) {
    FloorMap floor;
    floor.features = {PlaneFeature(-5.0, 5.0, -5.0, 5.0, grade, 0.0, 0.0)};
    FullChairSimulator sim(variant, l, floor, load, kDt);
    const FullChairSample& s = sim.Start({});
    if (front_load) *front_load = s.contacts[0].load + s.contacts[1].load;
    return s.tip_over;
  };
  const auto critical_grade = [&](const PlanarLayout& l) {
    double lo = 0.0, hi = 2.0;  // bisection on the tip-over flag
    for (int i = 0; i < 50; ++i) {
      const double mid = 0.5 * (lo + hi);
      (tips_at(mid, l, nullptr) ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  };
  std::vector<double> grade_pct, front;
  for (double grade = 0.0; grade <= 0.5; grade += 0.01) {
    double f = 0.0;
    tips_at(grade, layout, &f);
    grade_pct.push_back(100.0 * grade);
    front.push_back(f);
  }
  const double closed = (layout.cm_x - variant.wheels[1].x) / h;
  const double found = critical_grade(layout);
  layout.anti_tip = {true, -0.45, 0.2, 0.05};
  const double closed_anti_tip = (layout.cm_x - layout.anti_tip.x) / h;
  const double found_anti_tip = critical_grade(layout);
  plot::Panel panel = MakePanel("front-row load (negative: lifted, reported, not clipped)", "front-row load [N]");
  panel.series.push_back({"pwsim full-DoF chair (at rest)", grade_pct, front, plot::Style::kLinesPoints, plot::color::kSimulated});
  panel.series.push_back({"tip-over grade (x_c - x_r)/h", {100.0 * closed, 100.0 * closed},
                          {*std::min_element(front.begin(), front.end()), *std::max_element(front.begin(), front.end())},
                          plot::Style::kLines, plot::color::kReference});
  WritePanelFigure(out / "chair_tip", "facing up a slope: load on the front row until the chair tips back",
                   "grade [%]", panel);
  return {{"tip_grade_closed_form", closed},
          {"tip_grade_found", found},
          {"tip_grade_closed_form_deg", std::atan(closed) * 180.0 / kPi},
          {"anti_tip_x_m", layout.anti_tip.x},
          {"tip_grade_with_anti_tip_closed_form", closed_anti_tip},
          {"tip_grade_with_anti_tip_found", found_anti_tip}};
}

}  // namespace

nlohmann::ordered_json RunChairChecks(const Chair& chair, const std::filesystem::path& chair_file,
                                      double load_kg, const std::filesystem::path& out_dir) {
  std::filesystem::create_directories(out_dir);
  nlohmann::ordered_json result;
  result["format"] = "pwsim-chair-checks/1";
  result["chair"] = {{"name", chair.name}, {"file", chair_file.string()}, {"load_kg", load_kg}};
  result["data"] = "same-model simulation against closed forms (no measured chair)";
  result["turn"] = Turn(chair, load_kg, out_dir);
  result["spot"] = Spot(chair, load_kg);
  result["caster"] = Caster(chair, load_kg, out_dir);
  result["pull"] = Pull(chair, load_kg, out_dir);
  result["roll"] = Roll(chair, load_kg, out_dir);
  result["braking"] = Braking(chair, load_kg, out_dir);
  result["tip"] = Tip(chair, load_kg, out_dir);
  WriteFileAtomically(out_dir / "chair_checks.json", result.dump(2) + "\n");
  return result;
}

}  // namespace pwsim::report
