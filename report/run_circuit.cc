#include "report/run_circuit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/atomic_file.h"
#include "mca/head_motion.h"
#include "plot/plot.h"
#include "report/run_mca.h"
#include "report/run_report.h"
#include "report/skill_score.h"
#include "report/training_report.h"

namespace pwsim::report {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <typename Get>
std::vector<double> Column(const std::vector<FullChairSample>& samples, Get get) {
  std::vector<double> values(samples.size());
  for (std::size_t r = 0; r < samples.size(); ++r) values[r] = get(samples[r]);
  return values;
}

bool IsCaster(const Scene& scene, int contact) {
  const auto& rows = scene.circuit->layout.rows;
  const auto row = static_cast<std::size_t>(contact / 2);
  return row < rows.size() && rows[row].role == WheelRole::kCaster;
}

int ContactCount(const std::vector<FullChairSample>& samples) {
  return samples.empty() ? 0 : samples.front().contact_count;
}

/// A polyline appended to a series, closed when `closed`, then a gap (NaN) before the next one.
void AppendPolyline(plot::Series& s, const std::vector<std::array<double, 2>>& points, bool closed) {
  for (const auto& p : points) {
    s.x.push_back(p[0]);
    s.y.push_back(p[1]);
  }
  if (closed && !points.empty()) {
    s.x.push_back(points.front()[0]);
    s.y.push_back(points.front()[1]);
  }
  s.x.push_back(kNaN);
  s.y.push_back(kNaN);
}

/// A rectangle [front, rear] × [-half_width, half_width] in a frame at (x, y) turned by yaw.
std::vector<std::array<double, 2>> Rectangle(double x, double y, double yaw, double front,
                                             double rear, double half_width) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::vector<std::array<double, 2>> out;
  for (auto [u, v] : {std::pair{front, half_width}, std::pair{rear, half_width},
                      std::pair{rear, -half_width}, std::pair{front, -half_width}}) {
    out.push_back({x + c * u - s * v, y + s * u + c * v});
  }
  return out;
}

plot::Series MakeSeries(const std::string& label, unsigned color, plot::Style style = plot::Style::kLines) {
  plot::Series s;
  s.label = label;
  s.color = color;
  s.style = style;
  return s;
}

}  // namespace

std::string ContactName(int contact, int rows) {
  if (contact >= 2 * rows) return contact == 2 * rows ? "at_l" : "at_r";
  return std::to_string(contact / 2 + 1) + (contact % 2 == 0 ? "l" : "r");
}

/// The same contact in words for a figure's legend: its row from the front, its side and kind.
std::string ContactWords(int contact, int rows, bool caster) {
  const char* side = contact % 2 == 0 ? "left" : "right";
  if (contact >= 2 * rows) return std::string("anti-tip wheel, ") + side;
  const int row = contact / 2;
  const std::string place = row == 0 ? "front" : row == rows - 1 ? "rear" : rows == 3 ? "middle" : "row " + std::to_string(row + 1);
  return place + " " + side + (caster ? " caster" : " drive wheel");
}

TrialTable CircuitColumns(const Scene& scene, const std::vector<FullChairSample>& samples) {
  TrialTable table(samples.size());
  table.Add("t_s", Column(samples, [&](const FullChairSample& s) { return scene.clock.TimeAt(s.tick); }));
  table.Add("x_m", Column(samples, [](const FullChairSample& s) { return s.planar.x; }));
  table.Add("y_m", Column(samples, [](const FullChairSample& s) { return s.planar.y; }));
  table.Add("yaw_rad", Column(samples, [](const FullChairSample& s) { return s.planar.yaw; }));
  table.Add("v_mps", Column(samples, [](const FullChairSample& s) { return s.planar.v; }));
  table.Add("yaw_rate_radps", Column(samples, [](const FullChairSample& s) { return s.planar.yaw_rate; }));
  table.Add("lateral_speed_mps", Column(samples, [](const FullChairSample& s) { return s.lateral_speed; }));
  table.Add("ax_mps2", Column(samples, [](const FullChairSample& s) { return s.a_x; }));
  table.Add("ay_mps2", Column(samples, [](const FullChairSample& s) { return s.a_y; }));
  table.Add("yaw_acc_radps2", Column(samples, [](const FullChairSample& s) { return s.yaw_accel; }));
  table.Add("distance_m", Column(samples, [](const FullChairSample& s) { return s.distance; }));
  table.Add("joystick_forward", Column(samples, [](const FullChairSample& s) { return s.joystick.forward; }));
  table.Add("joystick_turn", Column(samples, [](const FullChairSample& s) { return s.joystick.turn; }));
  const int rows = scene.chair.wheel_count();
  for (int i = 0; i < rows; ++i) {
    table.Add("z_o" + std::to_string(i + 1) + "_m",
              Column(samples, [i](const FullChairSample& s) { return s.z_O[static_cast<std::size_t>(i)]; }));
  }
  table.Add("z_gm_m", Column(samples, [](const FullChairSample& s) { return s.gm.z; }));
  table.Add("pitch_gm_rad", Column(samples, [](const FullChairSample& s) { return s.gm.pitch; }));
  table.Add("roll_gm_rad", Column(samples, [](const FullChairSample& s) { return s.roll_gm; }));
  table.Add("z_m", Column(samples, [](const FullChairSample& s) { return s.lm.z; }));
  table.Add("pitch_rad", Column(samples, [](const FullChairSample& s) { return s.lm.pitch; }));
  table.Add("roll_rad", Column(samples, [](const FullChairSample& s) { return s.roll; }));
  table.Add("z_rate_mps", Column(samples, [](const FullChairSample& s) { return s.lm.z_rate; }));
  table.Add("pitch_rate_radps", Column(samples, [](const FullChairSample& s) { return s.lm.pitch_rate; }));
  table.Add("roll_rate_radps", Column(samples, [](const FullChairSample& s) { return s.roll_rate; }));
  const int contacts = ContactCount(samples);
  for (int c = 0; c < contacts; ++c) {
    const auto i = static_cast<std::size_t>(c);
    table.Add("load_" + ContactName(c, rows) + "_n",
              Column(samples, [i](const FullChairSample& s) { return s.contacts[i].load; }));
  }
  for (int c = 0; c < contacts; ++c) {
    if (!IsCaster(scene, c)) continue;
    const auto i = static_cast<std::size_t>(c);
    table.Add("caster_" + ContactName(c, rows) + "_rad",
              Column(samples, [i](const FullChairSample& s) { return s.casters[i].angle; }));
  }
  table.Add("lift_off_count", Column(samples, [](const FullChairSample& s) { return s.lift_off_count; }));
  table.Add("tip_over", Column(samples, [](const FullChairSample& s) { return s.tip_over ? 1.0 : 0.0; }));
  table.Add("on_anti_tip", Column(samples, [](const FullChairSample& s) { return s.on_anti_tip ? 1.0 : 0.0; }));
  table.Add("cop_x_m", Column(samples, [](const FullChairSample& s) { return s.cop_x; }));
  table.Add("cop_y_m", Column(samples, [](const FullChairSample& s) { return s.cop_y; }));
  table.Add("in_contact", Column(samples, [](const FullChairSample& s) { return s.in_contact ? 1.0 : 0.0; }));
  table.Add("contact_events", Column(samples, [](const FullChairSample& s) { return s.contact_events; }));
  table.Add("gates_passed", Column(samples, [](const FullChairSample& s) { return s.gates_passed; }));
  return table;
}

nlohmann::ordered_json CircuitSummary(const Scene& scene, const std::vector<FullChairSample>& samples) {
  const CircuitSpec& circuit = *scene.circuit;
  const int rows = scene.chair.wheel_count();
  const int contacts = ContactCount(samples);
  double peak_speed = 0.0, peak_roll = 0.0, peak_yaw_rate = 0.0, peak_ay = 0.0, peak_contact_speed = 0.0;
  int contact_ticks = 0, lift_ticks = 0, lift_episodes = 0, tip_ticks = 0, anti_tip_ticks = 0;
  double first_contact_t = kNaN, first_tip_t = kNaN;
  std::vector<int> lift_per_contact(static_cast<std::size_t>(contacts), 0);
  std::vector<double> min_load(static_cast<std::size_t>(contacts), std::numeric_limits<double>::infinity());
  bool lifted_before = false;
  int events_before = samples.empty() ? 0 : samples.front().contact_events;
  for (const FullChairSample& s : samples) {
    const double t = scene.clock.TimeAt(s.tick);
    peak_speed = std::max(peak_speed, std::abs(s.planar.v));
    peak_roll = std::max(peak_roll, std::abs(s.roll));
    peak_yaw_rate = std::max(peak_yaw_rate, std::abs(s.planar.yaw_rate));
    peak_ay = std::max(peak_ay, std::abs(s.a_y));
    if (s.in_contact) {
      ++contact_ticks;
      if (std::isnan(first_contact_t)) first_contact_t = t;
    }
    if (s.contact_events > events_before) {
      peak_contact_speed = std::max(peak_contact_speed, std::abs(s.last_contact_speed));
      events_before = s.contact_events;
    }
    const bool lifted = s.lift_off_count > 0;
    lift_ticks += lifted ? 1 : 0;
    lift_episodes += lifted && !lifted_before ? 1 : 0;
    lifted_before = lifted;
    if (s.tip_over) {
      ++tip_ticks;
      if (std::isnan(first_tip_t)) first_tip_t = t;
    }
    anti_tip_ticks += s.on_anti_tip ? 1 : 0;
    for (int c = 0; c < contacts; ++c) {
      const auto i = static_cast<std::size_t>(c);
      lift_per_contact[i] += s.contacts[i].lift_off ? 1 : 0;
      min_load[i] = std::min(min_load[i], s.contacts[i].load);
    }
  }
  const double dt = scene.clock.dt();
  nlohmann::ordered_json per_contact = nlohmann::ordered_json::object();
  for (int c = 0; c < contacts; ++c) {
    const auto i = static_cast<std::size_t>(c);
    per_contact[ContactName(c, rows)] = {{"lift_off_ticks", lift_per_contact[i]},
                                         {"min_load_n", min_load[i]}};
  }
  const FullChairSample& last = samples.back();
  auto nullable = [](double v) { return std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v); };
  return {
      {"duration_s", scene.clock.TimeAt(last.tick)},
      {"distance_m", last.distance},
      {"peak_speed_mps", peak_speed},
      {"end", {{"x_m", last.planar.x}, {"y_m", last.planar.y}, {"yaw_deg", last.planar.yaw * kRadToDeg}}},
      {"gates", {{"passed", last.gates_passed},
                 {"total", circuit.gates.size()},
                 {"all_passed", last.gates_passed == static_cast<int>(circuit.gates.size())}}},
      {"contacts", {{"events", last.contact_events},
                    {"ticks", contact_ticks},
                    {"duration_s", contact_ticks * dt},
                    {"first_t_s", nullable(first_contact_t)},
                    {"peak_approach_speed_mps", peak_contact_speed}}},
      {"lift_offs", {{"ticks", lift_ticks},
                     {"episodes", lift_episodes},
                     {"duration_s", lift_ticks * dt},
                     {"per_contact", per_contact}}},
      {"tip_over", {{"ticks", tip_ticks}, {"first_t_s", nullable(first_tip_t)}}},
      {"on_anti_tip_ticks", anti_tip_ticks},
      {"peak_roll_deg", peak_roll * kRadToDeg},
      {"peak_yaw_rate_degps", peak_yaw_rate * kRadToDeg},
      {"peak_lateral_accel_mps2", peak_ay},
  };
}

void AddCircuitMotionCueing(const Scene& scene, const std::vector<FullChairSample>& samples,
                            TrialTable& table, nlohmann::ordered_json& summary,
                            const std::filesystem::path& out_dir, const McaChoice& mca_choice) {
  // X_WV per tick: (x, y, z) with R = Rz(ψ) Ry(−θ) Rx(φ), the platform's convention (mca/dof.h)
  std::vector<mca::DofArray> body(samples.size());
  VisualPose visual;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const FullChairSample& s = samples[k];
    body[k] = {s.planar.x, s.planar.y, s.lm.z, s.roll, s.lm.pitch, s.planar.yaw};
    visual.x.push_back(s.planar.x);
    visual.y.push_back(s.planar.y);
    visual.z.push_back(s.lm.z);
    visual.roll.push_back(s.roll);
    visual.pitch.push_back(s.lm.pitch);
    visual.yaw.push_back(s.planar.yaw);
  }
  const std::vector<mca::HeadMotion> head =
      mca::HeadMotionFromBodyTrack(body, scene.occupant.head_offset, scene.clock.dt());
  const std::vector<double> t = table.Column("t_s");  // a copy: the stage adds columns
  AddMotionCueingStage(scene, t, head, visual, table, summary, out_dir, mca_choice);
  AddHeadForceBound(scene, samples, head, t, summary, out_dir);
}

void AddHeadForceBound(const Scene& scene, const std::vector<FullChairSample>& samples,
                       const std::vector<mca::HeadMotion>& head, const std::vector<double>& t,
                       nlohmann::ordered_json& summary, const std::filesystem::path& out_dir) {
  double peak_speed = 0.0, peak_yaw_rate = 0.0;
  for (const FullChairSample& s : samples) {
    peak_speed = std::max(peak_speed, std::abs(s.planar.v));
    peak_yaw_rate = std::max(peak_yaw_rate, std::abs(s.planar.yaw_rate));
  }
  const HeadForceBound bound = ComputeHeadForceBound(scene.chair, *scene.circuit, scene.load_kg, scene.pitch_torque,
                                                     scene.occupant.head_offset, peak_speed, peak_yaw_rate);
  // |f_H − (0, 0, g)| per tick; a wall contact (the tick before to the tick after) apart
  const std::size_t n = std::min(head.size(), samples.size());
  std::vector<double> deviation(n, kNaN), at_wall(n, kNaN), limit(n, bound.total);
  double peak = 0.0, peak_t = 0.0, wall_peak = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const mca::HeadMotion& h = head[k];
    const double d = std::sqrt(h.fs[0] * h.fs[0] + h.fs[1] * h.fs[1] + (h.fs[2] - mca::kGravity) * (h.fs[2] - mca::kGravity));
    const bool wall = samples[k].in_contact || (k > 0 && samples[k - 1].in_contact) || (k + 1 < n && samples[k + 1].in_contact);
    (wall ? at_wall : deviation)[k] = d;
    if (wall) {
      wall_peak = std::max(wall_peak, d);
    } else if (d > peak) {
      peak = d;
      peak_t = k < t.size() ? t[k] : 0.0;
    }
  }
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < bound.envelope_slope.size(); ++i) {
    rows.push_back({{"envelope_slope", bound.envelope_slope[i]}, {"contact_rate_mps", bound.contact_rate[i]}});
  }
  summary["head_force"] = {
      {"bound_mps2", bound.total},
      {"peak_mps2", peak},
      {"peak_t_s", peak_t},
      {"within_bound", peak <= bound.total},
      {"wall_contact_peak_mps2", wall_peak},
      {"derivation", "engine/circuit.h ComputeHeadForceBound; docs/circuits.md, head specific-force bound"},
      {"links", {{"wheel_speed_mps", bound.wheel_speed},
                 {"rows", rows},
                 {"gm_rates", {bound.gm_z_rate, bound.gm_pitch_rate, bound.gm_roll_rate}},
                 {"heave_accel_mps2", bound.heave_accel},
                 {"pitch_accel_radps2", bound.pitch_accel},
                 {"roll_accel_radps2", bound.roll_accel},
                 {"pitch_rate_radps", bound.pitch_rate},
                 {"roll_rate_radps", bound.roll_rate},
                 {"planar_accel_mps2", bound.planar_accel},
                 {"yaw_accel_radps2", bound.yaw_accel},
                 {"tilt_rad", bound.tilt}}}};
  // head_force.png: the deviation against the bound (log scale: the bound is loose)
  plot::Figure figure;
  figure.title = "pwsim run: " + scene.name + ", head specific force against its plausibility bound";
  figure.x_label = "time [s]";
  plot::Panel panel;
  panel.title = "how far the push felt at the head departs from gravity alone, and the most this floor, chair and drive allow (log scale)";
  panel.y_label = "specific force beyond gravity [m/s²]";
  panel.log_y = true;
  const auto series = [&](const char* label, unsigned color, const std::vector<double>& y, int dash) {
    plot::Series s;
    s.label = label;
    s.x.assign(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(std::min(n, t.size())));
    s.y.assign(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(s.x.size()));
    for (double& v : s.y) v = v > 1e-3 ? v : kNaN;  // log axis: nothing below 1 mm/s^2
    s.color = color;
    s.dash = dash;
    return s;
  };
  panel.series.push_back(series("at the head", 0x0072B2, deviation, 0));
  if (wall_peak > 0.0) panel.series.push_back(series("at a wall contact (impact, outside the bound)", 0xD55E00, at_wall, 0));
  panel.series.push_back(series("plausibility bound (docs/circuits.md)", 0x111111, limit, 2));
  figure.panels.push_back(panel);
  plot::WriteFigure(out_dir / "head_force.png", figure);
}

void WriteCircuitFigures(const Scene& scene, const std::vector<FullChairSample>& samples,
                         const std::filesystem::path& out_dir) {
  const CircuitSpec& circuit = *scene.circuit;
  const PlanarLayout& layout = circuit.layout;
  const int rows = scene.chair.wheel_count();
  const int contacts = ContactCount(samples);
  const auto ticks_per_s = static_cast<std::size_t>(std::max<std::int64_t>(1, scene.clock.TicksFor(1.0)));
  const std::size_t plot_step = std::max<std::size_t>(1, ticks_per_s / 100);  // 100 points/s

  // --- top view ---
  plot::Series walls = MakeSeries("walls", 0x444444);
  for (const Wall& w : circuit.walls) {
    const double dx = w.to.x - w.from.x, dy = w.to.y - w.from.y;
    const double len = std::hypot(dx, dy);
    if (!(len > 0.0)) continue;
    AppendPolyline(walls, Rectangle(w.from.x, w.from.y, std::atan2(dy, dx), len, 0.0, w.thickness / 2.0), true);
  }
  plot::Series obstacles = MakeSeries("obstacles", 0x0072B2);
  for (const Obstacle& o : circuit.obstacles) {
    if (o.shape == Obstacle::Shape::kBox) {
      AppendPolyline(obstacles, Rectangle(o.centre.x, o.centre.y, o.yaw, o.half_length, -o.half_length, o.half_width), true);
      continue;
    }
    std::vector<std::array<double, 2>> ring;
    for (int k = 0; k < 24; ++k) {
      const double a = 2.0 * 3.14159265358979323846 * k / 24;
      ring.push_back({o.centre.x + o.radius * std::cos(a), o.centre.y + o.radius * std::sin(a)});
    }
    AppendPolyline(obstacles, ring, true);
  }
  plot::Series relief = MakeSeries("floor relief (features, height grid)", 0xE69F00);
  for (const FloorFeature& f : circuit.floor.features) {
    AppendPolyline(relief, {{f.x_min, f.y_min}, {f.x_max, f.y_min}, {f.x_max, f.y_max}, {f.x_min, f.y_max}}, true);
  }
  if (circuit.floor.grid) {
    const HeightGrid& g = *circuit.floor.grid;
    const double x1 = g.x0 + (g.nx - 1) * g.cell, y1 = g.y0 + (g.ny - 1) * g.cell;
    AppendPolyline(relief, {{g.x0, g.y0}, {x1, g.y0}, {x1, y1}, {g.x0, y1}}, true);
  }
  plot::Series gates = MakeSeries("gates (left to right post)", 0x009E73, plot::Style::kLinesPoints);
  for (const Gate& g : circuit.gates) AppendPolyline(gates, {{g.left.x, g.left.y}, {g.right.x, g.right.y}}, false);
  plot::Series path = MakeSeries("path of O_V", 0xD55E00);
  for (std::size_t k = 0; k < samples.size(); k += plot_step) {
    path.x.push_back(samples[k].planar.x);
    path.y.push_back(samples[k].planar.y);
  }
  plot::Series footprint = MakeSeries("footprint, once a second", 0x999999);
  plot::Series casters = MakeSeries("caster rolling direction (yaw + swivel angle)", 0xCC79A7);
  for (std::size_t k = 0; k < samples.size(); k += ticks_per_s) {
    const FullChairSample& s = samples[k];
    AppendPolyline(footprint, Rectangle(s.planar.x, s.planar.y, s.planar.yaw, layout.footprint_front,
                                        layout.footprint_rear, layout.footprint_half_width), true);
    for (int c = 0; c < contacts; ++c) {
      if (!IsCaster(scene, c)) continue;
      const auto i = static_cast<std::size_t>(c);
      const double heading = s.planar.yaw + s.casters[i].angle;
      constexpr double kMark = 0.15;  // [m] drawn length
      AppendPolyline(casters, {{s.contacts[i].x, s.contacts[i].y},
                               {s.contacts[i].x + kMark * std::cos(heading), s.contacts[i].y + kMark * std::sin(heading)}},
                     false);
    }
  }
  plot::Series hits = MakeSeries("wall/obstacle contact begins (O_V there)", 0x111111, plot::Style::kPoints);
  plot::Series lifted = MakeSeries("wheel lifted off (load <= 0)", 0xE69F00, plot::Style::kPoints);
  int events = samples.empty() ? 0 : samples.front().contact_events;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const FullChairSample& s = samples[k];
    if (s.contact_events > events) {
      hits.x.push_back(s.planar.x);
      hits.y.push_back(s.planar.y);
      events = s.contact_events;
    }
    if (k % (10 * plot_step) != 0) continue;
    for (int c = 0; c < contacts; ++c) {
      const auto i = static_cast<std::size_t>(c);
      if (!s.contacts[i].lift_off) continue;
      lifted.x.push_back(s.contacts[i].x);
      lifted.y.push_back(s.contacts[i].y);
    }
  }
  plot::Figure top;
  top.title = "pwsim run: " + scene.name + " from above";
  top.x_label = "along the room [m]";
  // a map: as tall as the path's extent needs at ~650 px of plot width (beside the key)
  double x_lo = 0.0, x_hi = 1.0, y_lo = 0.0, y_hi = 1.0;
  bool first = true;
  for (const plot::Series* series : {&walls, &obstacles, &gates, &path}) {
    for (std::size_t i = 0; i < series->x.size(); ++i) {
      if (!std::isfinite(series->x[i])) continue;
      x_lo = first ? series->x[i] : std::min(x_lo, series->x[i]);
      x_hi = first ? series->x[i] : std::max(x_hi, series->x[i]);
      y_lo = first ? series->y[i] : std::min(y_lo, series->y[i]);
      y_hi = first ? series->y[i] : std::max(y_hi, series->y[i]);
      first = false;
    }
  }
  const double aspect = (y_hi - y_lo + 1.0) / std::max(x_hi - x_lo + 1.0, 1e-3);
  top.width_px = 1100;
  top.panel_height_px = static_cast<int>(std::clamp(120.0 + 560.0 * aspect, 360.0, 1100.0));
  plot::Panel map;
  map.title = "path, casters and contacts";
  map.y_label = "across the room, to the left [m]";
  map.equal_axes = true;
  for (plot::Series* s : {&walls, &obstacles, &relief, &gates, &footprint, &path, &casters, &hits, &lifted}) {
    if (s->x.empty()) {  // keep the legend stable: an empty series is one NaN point
      s->x.push_back(kNaN);
      s->y.push_back(kNaN);
    }
    map.series.push_back(*s);
  }
  top.panels.push_back(map);
  plot::WriteFigure(out_dir / "top_view.png", top);

  // --- caster angles and wheel loads over time ---
  std::vector<double> t;
  for (std::size_t k = 0; k < samples.size(); k += plot_step) t.push_back(scene.clock.TimeAt(samples[k].tick));
  auto over_time = [&](const std::string& label, auto get) {
    plot::Series s;
    s.label = label;
    s.x = t;
    for (std::size_t k = 0; k < samples.size(); k += plot_step) s.y.push_back(get(samples[k]));
    return s;
  };
  plot::Panel angles;
  angles.title = "caster swivel angles (0: rolling straight ahead, +-180: reversing)";
  angles.y_label = "swivel angle [deg]";
  plot::Panel loads;
  loads.title = "wheel loads (<= 0: lifted off)";
  loads.y_label = "load [N]";
  for (int c = 0; c < contacts; ++c) {
    const auto i = static_cast<std::size_t>(c);
    const std::string words = ContactWords(c, rows, IsCaster(scene, c));
    loads.series.push_back(over_time(words, [i](const FullChairSample& s) { return s.contacts[i].load; }));
    if (IsCaster(scene, c)) {
      angles.series.push_back(over_time(words, [i](const FullChairSample& s) { return s.casters[i].angle * kRadToDeg; }));
    }
  }
  plot::Panel lift;
  lift.title = "wheels lifted off";
  lift.y_label = "wheels off the floor [number]";
  lift.series.push_back(over_time("wheels lifted off", [](const FullChairSample& s) { return s.lift_off_count; }));
  double most_lifted = 0.0;
  for (double v : lift.series.back().y) most_lifted = std::max(most_lifted, v);
  lift.y_min = -0.2;  // a count: from none, whole wheels up to at least one
  lift.y_max = std::max(1.0, most_lifted) + 0.2;
  plot::Figure wheels;
  wheels.title = "pwsim run: " + scene.name + ", casters and wheel loads";
  wheels.x_label = "time [s]";
  if (!angles.series.empty()) wheels.panels.push_back(angles);
  wheels.panels.push_back(loads);
  wheels.panels.push_back(lift);
  plot::WriteFigure(out_dir / "wheels.png", wheels);
}

std::vector<std::filesystem::path> RunCircuitScene(const Scene& scene, const std::string& scene_path,
                                                   int decimate, const RenderStageOptions& render,
                                                   const std::filesystem::path& out_dir,
                                                   const McaChoice& mca_choice, std::string* skill_line) {
  const std::vector<FullChairSample> samples = SimulateCircuitScene(scene);
  TrialTable table = CircuitColumns(scene, samples);
  nlohmann::ordered_json summary = RunSummary(scene, scene_path, table);
  summary.erase("speed_mps");  // a straight drive's set speed; the circuit reports its own
  summary["peak_roll"] = Peak(table, "roll_rad", "rad");
  summary["circuit"] = CircuitSummary(scene, samples);
  const std::vector<TrainingTick> trace = TrainingTrace(scene, samples);
  const TrainingMetrics training = ComputeTrainingMetrics(*scene.circuit, trace, scene.clock.dt());
  summary["training"] = TrainingJson(training);
  std::filesystem::create_directories(out_dir);
  WriteTrainingPage(training, "pwsim run " + scene_path, out_dir);
  const std::string line = ScoreSkillItem(scene, scene_path, trace, out_dir);  // a skill item: score.json
  if (skill_line != nullptr) *skill_line = line;
  AddCircuitMotionCueing(scene, samples, table, summary, out_dir, mca_choice);  // all four platform axes
  WriteCircuitFigures(scene, samples, out_dir);
  table.WriteCsv(out_dir / "trial.csv", decimate);
  RenderTrial(scene, table, render, summary, out_dir);  // the occupant's view of the circuit
  WriteFileAtomically(out_dir / "summary.json", summary.dump(2) + "\n");
  std::vector<std::filesystem::path> written;
  for (const char* name : {"trial.csv", "summary.json", "mca.png", "mca_lateral.png", "head_force.png", "top_view.png",
                           "wheels.png", "training.md", "score.json", "video.mp4", "video_lossless.mkv", "frames.csv"}) {
    if (std::filesystem::exists(out_dir / name)) written.push_back(out_dir / name);
  }
  return written;
}

}  // namespace pwsim::report
