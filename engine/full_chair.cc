#include "engine/full_chair.h"

#include <Eigen/Dense>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>

#include "engine/check.h"
#include "engine/input_error.h"
#include "engine/number_format.h"
#include "engine/small_rotation.h"

namespace pwsim {

const char* DriveLayoutName(DriveLayout layout) {
  switch (layout) {
    case DriveLayout::kRear: return "rear";
    case DriveLayout::kMid: return "mid";
    case DriveLayout::kFront: return "front";
  }
  return "mid";
}

namespace {

int DriveRowOf(const Chair& chair) {
  for (int i = 0; i < chair.wheel_count(); ++i) {
    if (chair.wheels[i].name == "drive") return i;
  }
  int best = 0;
  for (int i = 1; i < chair.wheel_count(); ++i) {
    if (chair.gm->alpha[i] > chair.gm->alpha[best]) best = i;
  }
  return best;
}

DriveLayout LayoutOfRow(int row, int rows) {
  if (row == 0) return DriveLayout::kFront;
  if (row == rows - 1) return DriveLayout::kRear;
  return DriveLayout::kMid;
}

/// Convex hull (Andrew's monotone chain), counter-clockwise, no collinear points.
std::vector<std::array<double, 2>> ConvexHull(std::vector<std::array<double, 2>> points) {
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  const auto cross = [](const std::array<double, 2>& o, const std::array<double, 2>& a,
                        const std::array<double, 2>& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  };
  std::vector<std::array<double, 2>> hull(2 * points.size());
  std::size_t k = 0;
  for (const auto& p : points) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0.0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i > 0; --i) {
    const auto& p = points[i - 1];
    while (k >= lower && cross(hull[k - 2], hull[k - 1], p) <= 0.0) --k;
    hull[k++] = p;
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace

ConvexPolygon ConvexPolygon::FromVertices(const std::vector<std::array<double, 2>>& vertices) {
  // every edge (a, b), starting with the closing one (p[n-1], p[0])
  ConvexPolygon polygon;
  PWSIM_DEMAND(vertices.size() <= polygon.edges.size());
  const std::array<double, 2>* a = vertices.empty() ? nullptr : &vertices.back();
  for (const std::array<double, 2>& b : vertices) {
    polygon.edges[polygon.count++] = {(*a)[0], (*a)[1], b[0] - (*a)[0], b[1] - (*a)[1]};
    a = &b;
  }
  return polygon;
}

PlanarLayout DefaultPlanarLayout(const Chair& chair, double track) {
  PWSIM_DEMAND(chair.gm.has_value() && track > 0.0);
  PlanarLayout layout;
  const int rows = chair.wheel_count();
  const int drive = DriveRowOf(chair);
  layout.layout = LayoutOfRow(drive, rows);
  double share_sum = 0.0, moment = 0.0;
  for (int i = 0; i < rows; ++i) {
    WheelRow row;
    row.role = i == drive ? WheelRole::kDrive : WheelRole::kCaster;
    row.half_track = 0.5 * track;
    row.roll_weight = chair.gm->alpha[i];
    row.load_share = chair.gm->alpha[i];
    layout.rows.push_back(row);
    share_sum += row.load_share;
    moment += row.load_share * chair.wheels[i].x;
  }
  layout.cm_x = share_sum > 0.0 ? moment / share_sum : 0.0;  // static loads = the shares
  layout.drive_radius = chair.wheels[drive].radius;
  layout.footprint_front = chair.wheels.front().x + chair.wheels.front().radius + 0.15;
  layout.footprint_rear = chair.wheels.back().x - chair.wheels.back().radius - 0.05;
  layout.footprint_half_width = 0.5 * track + 0.06;
  return layout;
}

PlanarLayout ParsePlanarLayout(YamlMap& map, const Chair& chair) {
  const double default_track = 2.0 * map.NumberOr("half_track_m", 0.28, Range::Positive(1.0, "m"));
  PlanarLayout layout = DefaultPlanarLayout(chair, default_track);
  const int rows = chair.wheel_count();
  if (map.Has("drive")) {
    const std::string drive = map.Choice("drive", {"rear", "mid", "front"});
    // the drive row: front row, last row, or the middle row of the chair's wheels
    int row = drive == "front" ? 0 : drive == "rear" ? rows - 1 : rows / 2;
    if (drive == "mid" && rows < 3) map.Fail("drive", "rear or front for a chair with 2 wheel rows", "mid");
    for (int i = 0; i < rows; ++i) layout.rows[i].role = i == row ? WheelRole::kDrive : WheelRole::kCaster;
    layout.layout = drive == "front" ? DriveLayout::kFront : drive == "rear" ? DriveLayout::kRear : DriveLayout::kMid;
    layout.drive_radius = chair.wheels[row].radius;
  }
  if (map.Has("rows")) {
    YAML::Node list = map.Sequence("rows");
    const std::string field = map.FieldName("rows");
    if (static_cast<int>(list.size()) != rows) {
      throw InputError(map.file().string(), map.LineOfKey("rows"), field,
                       "one row per chair wheel (" + std::to_string(rows) + ")",
                       std::to_string(list.size()) + " rows");
    }
    int drives = 0;
    for (int i = 0; i < rows; ++i) {
      YamlMap row(list[i], map.file(), field + "[" + std::to_string(i) + "]", map.LineOfKey("rows"));
      WheelRow& r = layout.rows[i];
      const std::string role = row.ChoiceOr("role", r.role == WheelRole::kDrive ? "drive" : "caster",
                                            {"drive", "caster", "fixed"});
      r.role = role == "drive" ? WheelRole::kDrive : role == "fixed" ? WheelRole::kFixed : WheelRole::kCaster;
      drives += r.role == WheelRole::kDrive;
      r.half_track = row.NumberOr("half_track_m", r.half_track, Range::Positive(1.0, "m"));
      r.roll_weight = row.NumberOr("roll_weight", r.roll_weight, Range::Closed(-10.0, 10.0));
      r.load_share = row.NumberOr("load_share", r.load_share, Range::Closed(0.0, 10.0));
      row.Finish();
      if (r.role == WheelRole::kDrive) layout.drive_radius = chair.wheels[i].radius;
    }
    if (drives != 1) {
      throw InputError(map.file().string(), map.LineOfKey("rows"), field, "exactly one row with role drive",
                       std::to_string(drives) + " drive rows");
    }
  }
  if (map.Has("anti_tip")) {
    YamlMap at = map.Map("anti_tip");
    layout.anti_tip.present = true;
    layout.anti_tip.x = at.Number("x_m", Range::Closed(-3.0, 3.0, "m"));
    layout.anti_tip.half_track = at.Number("half_track_m", Range::Positive(1.0, "m"));
    layout.anti_tip.clearance = at.NumberOr("clearance_m", layout.anti_tip.clearance, Range::Closed(0.0, 0.3, "m"));
    at.Finish();
  }
  if (map.Has("caster")) {
    YamlMap c = map.Map("caster");
    CasterParams& p = layout.caster;
    p.trail = c.NumberOr("trail_m", p.trail, Range::Positive(0.3, "m"));
    p.swivel_inertia = c.NumberOr("swivel_inertia_kgm2", p.swivel_inertia, Range::Positive(1.0, "kg m^2"));
    p.swivel_damping = c.NumberOr("swivel_damping_nms", p.swivel_damping, Range::Closed(0.0, 100.0, "N m s/rad"));
    p.swivel_friction = c.NumberOr("swivel_friction_nm", p.swivel_friction, Range::Closed(0.0, 100.0, "N m"));
    p.scrub_per_load = c.NumberOr("scrub_per_load_m", p.scrub_per_load, Range::Closed(0.0, 0.1, "m"));
    p.lateral_damping = c.NumberOr("lateral_damping_nspm", p.lateral_damping, Range::Positive(1e6, "N s/m"));
    p.rolling_resistance = c.NumberOr("rolling_resistance", p.rolling_resistance, Range::Closed(0.0, 0.5));
    c.Finish();
  }
  layout.cm_x = map.NumberOr("cm_x_m", layout.cm_x, Range::Closed(-2.0, 2.0, "m"));
  layout.yaw_inertia = map.NumberOr("yaw_inertia_kgm2", layout.yaw_inertia, Range::Positive(1000.0, "kg m^2"));
  layout.roll_inertia = map.NumberOr("roll_inertia_kgm2", layout.roll_inertia, Range::Positive(1000.0, "kg m^2"));
  layout.k_roll = map.NumberOr("k_roll", layout.k_roll, Range::Positive(1e8, "N m/rad"));
  layout.c_roll = map.NumberOr("c_roll", layout.c_roll, Range::Positive(1e7, "N m s/rad"));
  layout.drive_radius = map.NumberOr("drive_radius_m", layout.drive_radius, Range::Positive(1.0, "m"));
  layout.max_motor_torque = map.NumberOr("max_motor_torque_nm", layout.max_motor_torque, Range::Positive(1000.0, "N m"));
  layout.speed_loop_gain = map.NumberOr("speed_loop_gain", layout.speed_loop_gain, Range::Positive(200.0, "1/s"));
  layout.rolling_resistance = map.NumberOr("rolling_resistance", layout.rolling_resistance, Range::Closed(0.0, 0.5));
  layout.friction = map.NumberOr("friction", layout.friction, Range::Positive(2.0));
  layout.rolling_envelope = map.BoolOr("rolling_envelope", layout.rolling_envelope);
  if (map.Has("tyres")) {
    YamlMap tyres = map.Map("tyres");
    // 0: rigid; else at least 10 ms (ω_t dt <= 0.63 at 1 kHz)
    const auto period = [&](const char* key, double fallback) {
      const double t = tyres.NumberOr(key, fallback, Range::Closed(0.0, 2.0, "s"));
      if (t != 0.0 && t < 0.01) tyres.Fail(key, "0 (a rigid tyre) or a period of at least 0.01 s", FormatDouble(t));
      return t;
    };
    layout.drive_tyre_period = period("drive_period_s", layout.drive_tyre_period);
    layout.caster_tyre_period = period("caster_period_s", layout.caster_tyre_period);
    layout.tyre_damping = tyres.NumberOr("damping", layout.tyre_damping, Range::Closed(0.0, 2.0));
    tyres.Finish();
  }
  if (map.Has("footprint_m")) {
    const std::vector<double> f = map.Numbers("footprint_m", Range::Closed(-3.0, 3.0, "m"), 3, 3);
    if (!(f[0] > f[1]) || !(f[2] > 0.0)) {
      map.Fail("footprint_m", "[front, rear, half_width] with front > rear and half_width > 0",
               "[" + FormatDouble(f[0]) + ", " + FormatDouble(f[1]) + ", " + FormatDouble(f[2]) + "]");
    }
    layout.footprint_front = f[0];
    layout.footprint_rear = f[1];
    layout.footprint_half_width = f[2];
  }
  if (map.Has("controller")) {
    YamlMap controller = map.Map("controller");
    layout.controller = ParseControllerProfile(controller);
    controller.Finish();
  }
  return layout;
}

ChairSample SagittalView(const FullChairSample& s) {
  ChairSample view;
  view.tick = s.tick;
  view.drive = s.drive;
  view.z_O = s.z_O;
  view.gm = s.gm;
  view.z_gm_rate = s.z_gm_rate;
  view.pitch_gm_rate = s.pitch_gm_rate;
  view.lm = s.lm;
  view.lm_acc = s.lm_acc;
  view.pitch_torque = s.pitch_torque;
  return view;
}

FullChairSimulator::FullChairSimulator(const Chair& chair, const PlanarLayout& layout,
                                       const FloorMap& floor, double load_kg, double dt,
                                       PitchTorqueParams pitch_torque, RollTorqueParams roll_torque)
    : floor_(floor),
      layout_(layout),
      gm_(chair),
      lumped_(Discretize(MakeLumpedModelParams(chair, load_kg), dt)),
      pitch_torque_(pitch_torque),
      roll_torque_(roll_torque) {
  PWSIM_DEMAND(static_cast<int>(layout.rows.size()) == chair.wheel_count());
  PWSIM_DEMAND(layout.controller.Validate().empty());
  rows_ = chair.wheel_count();
  mass_ = MovingMass(chair, load_kg);
  cm_height_ = chair.cm_height;
  drive_row_ = -1;
  for (int i = 0; i < rows_; ++i) {
    if (layout.rows[i].role == WheelRole::kDrive) {
      PWSIM_DEMAND(drive_row_ < 0);
      drive_row_ = i;
    }
  }
  PWSIM_DEMAND(drive_row_ >= 0);
  drive_x_ = chair.wheels[drive_row_].x;
  track_ = 2.0 * layout.rows[drive_row_].half_track;
  const double e = layout.cm_x - drive_x_;
  cm_ahead_ = e;
  // I_z scales with the moving mass (occupant and chair alike about the centre of mass).
  yaw_inertia_D_ = layout.yaw_inertia * mass_ / chair.mass + mass_ * e * e;
  roll_params_ = {layout.roll_inertia + cm_height_ * cm_height_ * mass_, layout.c_roll, layout.k_roll};
  roll_axis_ = MakeAxisPropagator(roll_params_, dt);
  front_x_ = chair.wheels.front().x;
  rear_x_ = chair.wheels.back().x;
  caster_constants_ = MakeCasterStepConstants(layout.caster, dt);
  inv_mass_ = 1.0 / mass_;
  inv_yaw_inertia_D_ = 1.0 / yaw_inertia_D_;
  inv_dt_ = 1.0 / dt;
  inv_roll_inertia_ = 1.0 / roll_params_.inertia;
  inv_track_ = 1.0 / track_;
  inv_wheelbase_ = 1.0 / (front_x_ - rear_x_);
  motor_force_limit_ = layout.max_motor_torque / layout.drive_radius;
  half_mass_ = 0.5 * mass_;
  integral_gain_ = 0.25 * layout.speed_loop_gain * layout.speed_loop_gain;
  for (int i = 0; i < rows_; ++i) inv_row_track_[i] = 1.0 / (2.0 * layout.rows[i].half_track);
  target_ = ControllerTarget(layout_.controller, target_joystick_);

  ground_contacts_ = 2 * rows_;
  for (int i = 0; i < rows_; ++i) {
    const WheelRow& row = layout.rows[i];
    for (int side = 0; side < 2; ++side) {
      const int c = 2 * i + side;
      rest_x_[c] = chair.wheels[i].x;
      rest_y_[c] = side == 0 ? row.half_track : -row.half_track;
      share_[c] = 0.5 * row.load_share;
      contact_role_[c] = row.role;
    }
    roll_weight_[i] = row.roll_weight;
  }
  int contacts = ground_contacts_;
  if (layout.anti_tip.present) {
    for (int side = 0; side < 2; ++side) {
      rest_x_[contacts] = layout.anti_tip.x;
      rest_y_[contacts] = side == 0 ? layout.anti_tip.half_track : -layout.anti_tip.half_track;
      contact_role_[contacts] = WheelRole::kFixed;
      ++contacts;
    }
  }
  sample_.contact_count = contacts;

  // N_c = k_c [1 x_c y_c] G⁻¹ [ΣN, ΣxN, ΣyN]ᵀ with G = Σ k_c [1 x y]ᵀ[1 x y].
  Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
  for (int c = 0; c < ground_contacts_; ++c) {
    const Eigen::Vector3d r(1.0, rest_x_[c], rest_y_[c]);
    g += share_[c] * r * r.transpose();
  }
  PWSIM_DEMAND(std::abs(g.determinant()) > 1e-12);
  const Eigen::Matrix3d g_inv = g.inverse();
  for (int c = 0; c < ground_contacts_; ++c) {
    const Eigen::Vector3d coefficients = share_[c] * (g_inv * Eigen::Vector3d(1.0, rest_x_[c], rest_y_[c]));
    load_c0_[c] = coefficients[0];
    load_cx_[c] = coefficients[1];
    load_cy_[c] = coefficients[2];
  }
  std::vector<std::array<double, 2>> points;
  for (int c = 0; c < ground_contacts_; ++c) points.push_back({rest_x_[c], rest_y_[c]});
  support_ = ConvexPolygon::FromVertices(ConvexHull(points));
  for (int c = ground_contacts_; c < contacts; ++c) points.push_back({rest_x_[c], rest_y_[c]});
  support_anti_tip_ = ConvexPolygon::FromVertices(ConvexHull(points));

  for (int c = 0; c < ground_contacts_; ++c) {
    if (contact_role_[c] == WheelRole::kDrive) continue;
    undriven_[undriven_count_++] = c;
    pivot_x_[c] = contact_role_[c] == WheelRole::kCaster ? rest_x_[c] + layout.caster.trail : rest_x_[c];
    lever_x_[c] = pivot_x_[c] - drive_x_;
  }
  for (int c = 0; c < contacts; ++c) {
    body_x_[c] = rest_x_[c];
    body_y_[c] = rest_y_[c];
  }
  // wheels: radius and tyre per ground contact (the anti-tip wheels stay rigid points)
  if (layout.rolling_envelope) {
    for (int c = 0; c < ground_contacts_; ++c) {
      radius_[c] = chair.wheels[c / 2].radius;
      const double period = contact_role_[c] == WheelRole::kDrive ? layout.drive_tyre_period : layout.caster_tyre_period;
      if (period <= 0.0) continue;
      const double omega = 2.0 * std::numbers::pi / period;
      PWSIM_DEMAND(omega * dt <= 1.0);  // semi-implicit Euler well inside its stability bound (2)
      tyre_omega2_[c] = omega * omega;
      tyre_2zw_[c] = 2.0 * layout.tyre_damping * omega;
      tyre_static_[c] = kStandardGravity / tyre_omega2_[c];
    }
  }
}

void FullChairSimulator::PlaceCasterContact(int c) {
  const double trail = layout_.caster.trail;
  body_x_[c] = rest_x_[c] + trail * (1.0 - caster_cos_[c]);
  body_y_[c] = rest_y_[c] - trail * caster_sin_[c];
}

void FullChairSimulator::ContactsAt(const PlanarState& pose, TyreUpdate update) {
  const double c = yaw_cos_;
  const double s = yaw_sin_;
  const bool envelope = update != TyreUpdate::kPoint;
  for (int k = 0; k < sample_.contact_count; ++k) {
    WheelContact& contact = sample_.contacts[k];
    contact.x = pose.x + c * body_x_[k] - s * body_y_[k];
    contact.y = pose.y + s * body_x_[k] + c * body_y_[k];
    const double point = floor_.HeightAtNear(contact.x, contact.y, floor_hints_[k]);
    double h = point;
    if (envelope && radius_[k] > 0.0 && !floor_.LevelUnder(contact.x, contact.y, radius_[k], floor_hints_[k])) {
      // the wheel's heading in W: ψ, or ψ - δ for a caster (cos δ = 1, sin δ = 0 otherwise)
      const double ux = c * caster_cos_[k] + s * caster_sin_[k];
      const double uy = s * caster_cos_[k] - c * caster_sin_[k];
      h = floor_.EnvelopeOffLevel(contact.x, contact.y, ux, uy, radius_[k], point, floor_hints_[k]);
    }
    contact.floor_z = h;
    if (update == TyreUpdate::kStep && tyre_omega2_[k] > 0.0) {
      // the tyre (header): e = h - u, ė = ḣ - u̇; at rest on the floor (h unchanged, u = h,
      // u̇ = 0) nothing moves, exactly
      if (h != floor_z_before_[k] || contact.z != h || tyre_rate_[k] != 0.0) {
        const double floor_rate = (h - floor_z_before_[k]) * inv_dt_;
        const double e = h - contact.z;
        const double e_rate = floor_rate - tyre_rate_[k];
        const double push = tyre_omega2_[k] * e + tyre_2zw_[k] * e_rate;
        const bool on_floor = e > -tyre_static_[k] && push > -kStandardGravity;
        tyre_rate_[k] += (on_floor ? push : -kStandardGravity) * lumped_.dt;
        contact.z += tyre_rate_[k] * lumped_.dt;
        contact.airborne = !on_floor;
        // settled (below a picometre and 0.1 nm/s): back on the floor exactly, so that a wheel
        // at rest on level floor is the floor's bits again (and costs nothing)
        if (on_floor && std::abs(h - contact.z) < 1e-12 && std::abs(floor_rate - tyre_rate_[k]) < 1e-10) {
          contact.z = h;
          tyre_rate_[k] = floor_rate;
        }
      } else {
        contact.airborne = false;
      }
    } else if (update != TyreUpdate::kKeep) {
      contact.z = h;
      tyre_rate_[k] = update == TyreUpdate::kStep ? (h - floor_z_before_[k]) * inv_dt_ : 0.0;
      contact.airborne = false;
    }
    floor_z_before_[k] = h;
  }
  for (int i = 0; i < rows_; ++i) {
    sample_.z_O[i] = 0.5 * (sample_.contacts[2 * i].z + sample_.contacts[2 * i + 1].z);
  }
  // Inclination of the floor under the chair (gravity in V for the planar and load models).
  // tan of each angle from the contacts; sin and cos from it without trigonometry
  const double tan_pitch = (sample_.z_O[0] - sample_.z_O[rows_ - 1]) * inv_wheelbase_;
  const double tan_roll = (sample_.contacts[2 * drive_row_].z - sample_.contacts[2 * drive_row_ + 1].z) * inv_track_;
  if (tan_pitch != floor_tan_pitch_) {
    floor_tan_pitch_ = tan_pitch;
    floor_cos_pitch_ = 1.0 / std::sqrt(1.0 + tan_pitch * tan_pitch);
    floor_sin_pitch_ = tan_pitch * floor_cos_pitch_;
  }
  if (tan_roll != floor_tan_roll_) {
    floor_tan_roll_ = tan_roll;
    floor_cos_roll_ = 1.0 / std::sqrt(1.0 + tan_roll * tan_roll);
    floor_sin_roll_ = tan_roll * floor_cos_roll_;
  }
}

double FullChairSimulator::PitchTorqueNow() const {
  return pitch_torque_.constant + pitch_torque_.per_accel * sample_.drive.a;
}

double FullChairSimulator::RollTorqueNow() const {
  return roll_torque_.constant + roll_torque_.gravity_lever * kStandardGravity * std::sin(sample_.roll) +
         roll_torque_.per_lateral_accel * sample_.a_y;
}

void FullChairSimulator::UpdateGeometry() {
  bool same = geometry_valid_;
  for (int k = 0; k < ground_contacts_; ++k) {
    same = same && std::bit_cast<std::uint64_t>(sample_.contacts[k].z) == std::bit_cast<std::uint64_t>(geometry_z_[k]);
  }
  if (same) return;  // the same heights, bit for bit: the same outputs
  geometry_ = gm_.Evaluate(std::span<const double>(sample_.z_O.data(), rows_));
  double roll_gm = 0.0;
  for (int i = 0; i < rows_; ++i) {
    const double rise = sample_.contacts[2 * i].z - sample_.contacts[2 * i + 1].z;
    if (roll_weight_[i] == 0.0 || rise == 0.0) continue;  // level row: asin(0) = 0
    const double sine = std::clamp(rise * inv_row_track_[i], -1.0, 1.0);
    roll_gm += roll_weight_[i] * std::asin(sine);
  }
  geometry_roll_ = roll_gm;
  for (int k = 0; k < ground_contacts_; ++k) geometry_z_[k] = sample_.contacts[k].z;
  geometry_valid_ = true;
}

void FullChairSimulator::Vertical(double pitch_torque, double roll_torque) {
  const GeometricOutput gm_begin = sample_.gm;
  const double roll_begin = sample_.roll_gm;
  UpdateGeometry();
  const double roll_gm = geometry_roll_;
  sample_.gm = geometry_;
  sample_.roll_gm = roll_gm;

  const LumpedInput input{gm_begin.z, sample_.gm.z, gm_begin.pitch, sample_.gm.pitch, pitch_torque};
  sample_.lm = Step(lumped_, sample_.lm, input);
  sample_.z_gm_rate = (sample_.gm.z - gm_begin.z) * lumped_.inv_dt;
  sample_.pitch_gm_rate = (sample_.gm.pitch - gm_begin.pitch) * lumped_.inv_dt;
  sample_.roll_gm_rate = (roll_gm - roll_begin) * lumped_.inv_dt;
  sample_.pitch_torque = pitch_torque;
  sample_.lm_acc = Accelerations(lumped_.params, sample_.lm, sample_.gm.z, sample_.z_gm_rate,
                                 sample_.gm.pitch, sample_.pitch_gm_rate, pitch_torque);
  AdvanceAxis(roll_axis_, sample_.roll, sample_.roll_rate, roll_begin, sample_.roll_gm_rate, roll_torque);
  sample_.roll_torque = roll_torque;
  sample_.roll_accel = (roll_torque - roll_params_.damping * (sample_.roll_rate - sample_.roll_gm_rate) -
                        roll_params_.stiffness * (sample_.roll - roll_gm)) *
                       inv_roll_inertia_;
}

void FullChairSimulator::Loads(double a_x, double a_y) {
  const double g = kStandardGravity;
  const double cp = floor_cos_pitch_, sp = floor_sin_pitch_;
  const double cr = floor_cos_roll_, sr = floor_sin_roll_;
  const double f_x = mass_ * (-g * sp - a_x);
  const double f_y = mass_ * (-g * sr * cp - a_y);
  const double weight = mass_ * g * cr * cp;  // -F_z
  const double sum_x = layout_.cm_x * weight + cm_height_ * f_x;
  const double sum_y = cm_height_ * f_y;
  int lifted = 0;
  for (int c = 0; c < ground_contacts_; ++c) {
    WheelContact& contact = sample_.contacts[c];
    contact.load = load_c0_[c] * weight + load_cx_[c] * sum_x + load_cy_[c] * sum_y;
    contact.lift_off = !(contact.load > 0.0);
    lifted += contact.lift_off;
  }
  sample_.lift_off_count = lifted;
  const double inv_weight = 1.0 / weight;
  sample_.cop_x = sum_x * inv_weight;
  sample_.cop_y = sum_y * inv_weight;
  const bool inside = support_.Contains(sample_.cop_x, sample_.cop_y);
  if (layout_.anti_tip.present) {
    const bool inside_anti_tip = support_anti_tip_.Contains(sample_.cop_x, sample_.cop_y);
    sample_.on_anti_tip = !inside && inside_anti_tip;
    sample_.tip_over = !inside_anti_tip;
  } else {
    sample_.on_anti_tip = false;
    sample_.tip_over = !inside;
  }
  for (int c = ground_contacts_; c < sample_.contact_count; ++c) {
    sample_.contacts[c].load = 0.0;
    sample_.contacts[c].lift_off = !sample_.on_anti_tip;
  }
}

void FullChairSimulator::Equilibrium() {
  sample_.gm = gm_.Evaluate(std::span<const double>(sample_.z_O.data(), rows_));
  double roll_gm = 0.0;
  for (int i = 0; i < rows_; ++i) {
    if (roll_weight_[i] == 0.0) continue;
    roll_gm += roll_weight_[i] * std::asin(std::clamp((sample_.contacts[2 * i].z - sample_.contacts[2 * i + 1].z) /
                                                          (2.0 * layout_.rows[i].half_track), -1.0, 1.0));
  }
  sample_.roll_gm = roll_gm;
  sample_.pitch_torque = PitchTorqueNow();
  // Static equilibrium, as the sagittal ChairSimulator: springs carry the torques, no motion.
  sample_.lm.z = sample_.gm.z;
  sample_.lm.pitch = sample_.gm.pitch + sample_.pitch_torque / lumped_.params.pitch.stiffness;
  // Roll: K_φ (φ - φ_GM) = Γ_φ(φ), a contraction (M d g / K_φ << 1): fixed-point iteration.
  sample_.roll = roll_gm;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double next = roll_gm + RollTorqueNow() / roll_params_.stiffness;
    if (next == sample_.roll) break;
    sample_.roll = next;
  }
  sample_.roll_torque = RollTorqueNow();
  Loads(0.0, 0.0);
}

const FullChairSample& FullChairSimulator::Start(const PlanarState& pose, double caster_angle) {
  const int contacts = sample_.contact_count;
  sample_ = FullChairSample{};
  sample_.contact_count = contacts;
  sample_.planar = pose;
  sample_.planar.v = 0.0;
  sample_.planar.yaw_rate = 0.0;
  for (int c = 0; c < ground_contacts_; ++c) {
    if (contact_role_[c] == WheelRole::kCaster) sample_.casters[c].angle = caster_angle;
    caster_cos_[c] = std::cos(sample_.casters[c].angle);
    caster_sin_[c] = std::sin(sample_.casters[c].angle);
    if (contact_role_[c] == WheelRole::kCaster) PlaceCasterContact(c);
  }
  along_x0_ = pose.x;
  along_y0_ = pose.y;
  along_c_ = std::cos(pose.yaw);
  along_s_ = std::sin(pose.yaw);
  yaw_cos_ = along_c_;
  yaw_sin_ = along_s_;
  ContactsAt(sample_.planar, TyreUpdate::kRest);
  Equilibrium();
  return sample_;
}

const FullChairSample& FullChairSimulator::StartAlong(const PlanarState& pose, const Longitudinal& drive) {
  Start(pose, 0.0);
  sample_.drive = drive;
  // the line p = p0 + (s - s0) u, written so that s maps to x exactly when p0.x = s0, u = (1, 0)
  along_x0_ = pose.x - drive.x * along_c_;
  along_y0_ = pose.y - drive.x * along_s_;
  ContactsAt(sample_.planar, TyreUpdate::kPoint);  // the sagittal model's point contacts
  Equilibrium();  // Γ_θ from the drive's acceleration, as ChairSimulator::Start
  return sample_;
}

const FullChairSample& FullChairSimulator::AdvanceAlong(const Longitudinal& drive) {
  const double pitch_torque = PitchTorqueNow();  // held over the step (ZOH), as ChairSimulator
  const double roll_torque = RollTorqueNow();
  const PlanarState before = sample_.planar;
  PlanarState& p = sample_.planar;
  p.x = drive.x * along_c_ + along_x0_;
  p.y = drive.x * along_s_ + along_y0_;
  p.v = drive.v;
  p.yaw_rate = 0.0;
  sample_.lateral_speed = 0.0;
  sample_.a_x = drive.a;
  sample_.a_y = 0.0;
  sample_.yaw_accel = 0.0;
  const double dx = p.x - before.x, dy = p.y - before.y;
  sample_.distance += std::sqrt(dx * dx + dy * dy);
  sample_.controller = {drive.v, 0.0, drive.a, 0.0};
  sample_.drive_force = {0.5 * mass_ * drive.a, 0.5 * mass_ * drive.a};
  sample_.torque_limited = false;
  for (int c = 0; c < ground_contacts_; ++c) {
    if (contact_role_[c] != WheelRole::kCaster) continue;
    const CasterForce f = StepCaster(layout_.caster, caster_constants_, sample_.casters[c], caster_cos_[c],
                                     caster_sin_[c], pivot_x_[c], rest_y_[c], drive.v, 0.0, 0.0, sample_.contacts[c].load);
    caster_cos_[c] = f.cos_angle;
    caster_sin_[c] = f.sin_angle;
    PlaceCasterContact(c);
    sample_.contacts[c].force_x = f.fx;
    sample_.contacts[c].force_y = f.fy;
  }
  sample_.drive = drive;
  ContactsAt(p, TyreUpdate::kPoint);
  Vertical(pitch_torque, roll_torque);
  Loads(drive.a, 0.0);
  ++sample_.tick;
  return sample_;
}

const FullChairSample& FullChairSimulator::Advance(const JoystickInput& joystick) {
  if (!(joystick == target_joystick_)) {  // the targets change only with the deflection
    target_joystick_ = joystick;
    target_ = ControllerTarget(layout_.controller, joystick);
  }
  const ControllerState setpoints = StepControllerToward(layout_.controller, sample_.controller, target_, lumped_.dt);
  AdvanceSetpoints(setpoints);
  sample_.joystick = joystick;
  return sample_;
}

const FullChairSample& FullChairSimulator::AdvanceSetpoints(const ControllerState& set) {
  const double dt = lumped_.dt;
  const double g = kStandardGravity;
  const double pitch_torque = PitchTorqueNow();
  const double roll_torque = RollTorqueNow();
  const PlanarState before = sample_.planar;
  const double v = before.v;
  const double w = before.yaw_rate;
  const double half_b = 0.5 * track_;
  const double e = cm_ahead_;

  // Gravity along the floor, in V.
  const double g_x = -g * floor_sin_pitch_;
  const double g_y = -g * floor_sin_roll_ * floor_cos_pitch_;
  double force_x = mass_ * g_x;
  double moment_z = e * mass_ * g_y;

  // Drive wheels: speed loops with feed-forward, torque and traction limits, rolling resistance;
  // parking brakes once the set-points are at rest.
  const bool braked = set.speed == 0.0 && set.yaw_rate == 0.0 && set.accel == 0.0 && set.yaw_accel == 0.0;
  bool limited = false;
  std::array<double, 2> limit{};
  std::array<double, 2> rolling{};
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;  // left: v - ω b/2, right: v + ω b/2
    const int c = 2 * drive_row_ + side;
    const double wheel_speed = v + sign * w * half_b;
    const double load = std::max(sample_.contacts[c].load, 0.0);
    const WheelContact& contact = sample_.contacts[c];
    const double mu = floor_.patches.empty() ? layout_.friction : floor_.FrictionAt(contact.x, contact.y, layout_.friction);
    limit[side] = std::min(motor_force_limit_, mu * load);
    rolling[side] = braked ? 0.0 : -layout_.rolling_resistance * load * std::clamp(wheel_speed * 100.0, -1.0, 1.0);
    if (braked) {
      sample_.speed_error_integral[side] = 0.0;
      continue;
    }
    const double wheel_set = set.speed + sign * set.yaw_rate * half_b;
    const double wheel_accel = set.accel + sign * set.yaw_accel * half_b;
    const double error = wheel_set - wheel_speed;
    const double k_v = layout_.speed_loop_gain;
    double& integral = sample_.speed_error_integral[side];
    double drive = half_mass_ * (wheel_accel + k_v * error + integral_gain_ * integral);
    if (std::abs(drive) > limit[side]) {
      drive = std::copysign(limit[side], drive);
      limited = true;
    } else {
      integral += error * dt;  // no wind-up while limited
    }
    sample_.drive_force[side] = drive;
  }

  // Casters (implicit swivel) and fixed wheels (sideways scrub) at their contacts.
  for (int n = 0; n < undriven_count_; ++n) {
    const int c = undriven_[n];
    const double py = rest_y_[c];
    const double load = sample_.contacts[c].load;
    const double vx = v - w * py;          // the pivot's (or wheel's) velocity in V
    const double vy = w * lever_x_[c];
    double fx = 0.0, fy = 0.0, lever_x = lever_x_[c], lever_y = py;
    if (contact_role_[c] == WheelRole::kCaster) {
      const CasterForce f = StepCaster(layout_.caster, caster_constants_, sample_.casters[c], caster_cos_[c],
                                       caster_sin_[c], pivot_x_[c], py, vx, vy, w, load);
      caster_cos_[c] = f.cos_angle;
      caster_sin_[c] = f.sin_angle;
      PlaceCasterContact(c);
      fx = f.fx;
      fy = f.fy;
      lever_x = f.contact_x - drive_x_;
      lever_y = f.contact_y;
    } else if (load > 0.0) {
      fx = -layout_.caster.rolling_resistance * load * std::clamp(vx * 100.0, -1.0, 1.0);
      fy = -layout_.caster.lateral_damping * vy;
    }
    sample_.contacts[c].force_x = fx;
    sample_.contacts[c].force_y = fy;
    force_x += fx;
    moment_z += lever_x * fy - lever_y * fx;
  }

  if (braked) {
    // F_L + F_R and F_R - F_L that bring v and ω to 0 within the step (equations below).
    const double sum = -mass_ * v * inv_dt_ - force_x - mass_ * e * w * w;
    const double difference = (-yaw_inertia_D_ * w * inv_dt_ - moment_z + mass_ * e * v * w) * (2.0 * inv_track_);
    sample_.drive_force = {0.5 * (sum - difference), 0.5 * (sum + difference)};
  }
  for (int side = 0; side < 2; ++side) {
    const int c = 2 * drive_row_ + side;
    double& drive = sample_.drive_force[side];
    if (braked && std::abs(drive) > limit[side]) {
      drive = std::copysign(limit[side], drive);
      limited = true;
    }
    sample_.contacts[c].force_x = drive + rolling[side];
    sample_.contacts[c].force_y = 0.0;
    force_x += drive + rolling[side];
    moment_z += -rest_y_[c] * (drive + rolling[side]);
  }
  sample_.torque_limited = limited;

  // Constrained rigid body about D (semi-implicit Euler).
  const double v_dot = force_x * inv_mass_ + e * w * w;
  const double w_dot = (moment_z - mass_ * e * v * w) * inv_yaw_inertia_D_;
  PlanarState& p = sample_.planar;
  p.v = braked && !limited ? 0.0 : v + v_dot * dt;  // held exactly by the brakes
  p.yaw_rate = braked && !limited ? 0.0 : w + w_dot * dt;
  // midpoint heading ψ + ω dt/2, then the new heading ψ + ω dt, by two half-step rotations
  const double half_turn = 0.5 * p.yaw_rate * dt;
  double ch = yaw_cos_, sh = yaw_sin_;
  if (half_turn != 0.0) {
    const SmallRotation half_step = MakeSmallRotation(half_turn);  // cos, sin evaluated once
    ApplyRotation(yaw_cos_, yaw_sin_, half_step);
    ch = yaw_cos_;
    sh = yaw_sin_;
    ApplyRotation(yaw_cos_, yaw_sin_, half_step);
  }
  const double lateral = -p.yaw_rate * drive_x_;
  p.x = before.x + (p.v * ch - lateral * sh) * dt;
  p.y = before.y + (p.v * sh + lateral * ch) * dt;
  p.yaw = before.yaw + p.yaw_rate * dt;
  sample_.lateral_speed = lateral;
  const double a_x = (p.v - v) * inv_dt_ + p.yaw_rate * p.yaw_rate * drive_x_;
  const double a_y = -(p.yaw_rate - w) * inv_dt_ * drive_x_ + p.yaw_rate * p.v;
  sample_.a_x = a_x;
  sample_.a_y = a_y;
  sample_.yaw_accel = (p.yaw_rate - w) * inv_dt_;
  const double dx = p.x - before.x, dy = p.y - before.y;
  sample_.distance += std::sqrt(dx * dx + dy * dy);
  sample_.controller = set;
  sample_.drive = {sample_.drive.x + dx * ch + dy * sh, p.v, a_x};

  ContactsAt(p, TyreUpdate::kStep);
  // Loads before Vertical (neither reads what the other writes): the loads feed the next tick's
  // forces, the vertical model only itself, so the next tick can start while it completes.
  Loads(a_x, a_y);
  Vertical(pitch_torque, roll_torque);
  ++sample_.tick;
  return sample_;
}

void FullChairSimulator::OverridePlanar(const PlanarState& planar) {
  if (planar.yaw != sample_.planar.yaw) {
    yaw_cos_ = std::cos(planar.yaw);
    yaw_sin_ = std::sin(planar.yaw);
  }
  sample_.planar = planar;
  if (planar.v == 0.0 && planar.yaw_rate == 0.0) {
    sample_.controller = ControllerState{};
    sample_.speed_error_integral = {0.0, 0.0};
    sample_.lateral_speed = 0.0;
  }
  ContactsAt(planar, TyreUpdate::kKeep);
}

void FullChairSimulator::SetCircuitStatus(bool in_contact, int contact_events, double last_contact_speed,
                                          int gates_passed) {
  sample_.in_contact = in_contact;
  sample_.contact_events = contact_events;
  sample_.last_contact_speed = last_contact_speed;
  sample_.gates_passed = gates_passed;
}

}  // namespace pwsim
