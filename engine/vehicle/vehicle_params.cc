#include "engine/vehicle/vehicle_params.h"

#include <cmath>

#include "engine/input_error.h"
#include "engine/number_format.h"

namespace pwsim::vehicle {

double Vehicle::GearRatio(int gear) const {
  if (gear == 0) return 0.0;
  if (gear < 0) return gearbox.reverse;
  if (gear > gear_count()) return 0.0;
  return gearbox.ratios[static_cast<std::size_t>(gear - 1)];
}

Vehicle MakeMidsizeCar() {
  Vehicle car;
  car.name = "midsize";
  car.description = "mid-size front-drive saloon, 2.0 l petrol, 5-speed manual";
  car.engine.map = {{0.0, 0.0, -8.0},       {500.0, 90.0, -10.0},   {1000.0, 140.0, -14.0},
                    {1500.0, 160.0, -17.0}, {2000.0, 175.0, -20.0}, {3000.0, 188.0, -26.0},
                    {4000.0, 195.0, -32.0}, {5000.0, 190.0, -38.0}, {6000.0, 175.0, -45.0},
                    {6500.0, 160.0, -48.0}, {7000.0, 120.0, -52.0}};
  return car;
}

std::string Validate(const Vehicle& car) {
  const ChassisParams& c = car.chassis;
  if (!(c.cg_to_front > 0.0 && c.cg_to_front < c.wheelbase)) {
    return "chassis.cg_to_front_m must lie strictly between 0 and wheelbase_m";
  }
  const std::vector<TorquePoint>& map = car.engine.map;
  if (map.size() < 2) return "engine.torque_map needs at least 2 points";
  if (map.front().rpm != 0.0) return "engine.torque_map must start at 0 rpm";
  for (std::size_t i = 1; i < map.size(); ++i) {
    if (!(map[i].rpm > map[i - 1].rpm)) return "engine.torque_map rpm must rise strictly";
  }
  for (const TorquePoint& p : map) {
    if (p.closed_throttle > p.full_load) {
      return "engine.torque_map: closed-throttle torque above full-load torque at " +
             FormatDouble(p.rpm) + " rpm";
    }
  }
  if (!(car.engine.stall_rpm < car.engine.idle_rpm && car.engine.idle_rpm < car.engine.max_rpm)) {
    return "engine: need stall_rpm < idle_rpm < max_rpm";
  }
  if (car.engine.max_rpm > map.back().rpm) return "engine.max_rpm beyond the torque map";
  if (!(car.clutch.engaged_pedal < car.clutch.free_pedal)) {
    return "clutch: need engaged_pedal < free_pedal";
  }
  if (car.gearbox.ratios.empty()) return "gearbox.ratios: at least one forward gear";
  for (std::size_t i = 1; i < car.gearbox.ratios.size(); ++i) {
    if (!(car.gearbox.ratios[i] < car.gearbox.ratios[i - 1])) {
      return "gearbox.ratios must fall from first to top gear";
    }
  }
  if (!(car.gearbox.reverse < 0.0)) return "gearbox.reverse must be negative";
  return "";
}

namespace {

void Fail(YamlMap& map, const std::string& key, const std::string& expected, const std::string& got) {
  map.Fail(key, expected, got);
}

}  // namespace

Vehicle ParseVehicle(YamlMap& map) {
  Vehicle car;
  car.name = map.String("name");
  car.description = map.StringOr("description", "");

  YamlMap ch = map.Map("chassis");
  ChassisParams& c = car.chassis;
  c.mass = ch.Number("mass_kg", Range::Closed(100.0, 2.0e4, "kg"));
  c.yaw_inertia = ch.Number("yaw_inertia_kgm2", Range::Positive(1.0e5, "kg m^2"));
  c.roll_inertia = ch.Number("roll_inertia_kgm2", Range::Positive(1.0e5, "kg m^2"));
  c.pitch_inertia = ch.Number("pitch_inertia_kgm2", Range::Positive(1.0e5, "kg m^2"));
  c.wheelbase = ch.Number("wheelbase_m", Range::Closed(1.0, 6.0, "m"));
  c.cg_to_front = ch.Number("cg_to_front_m", Range::Positive(6.0, "m"));
  c.cg_height = ch.Number("cg_height_m", Range::Closed(0.1, 2.0, "m"));
  c.track_front = ch.Number("track_front_m", Range::Closed(0.8, 3.0, "m"));
  c.track_rear = ch.Number("track_rear_m", Range::Closed(0.8, 3.0, "m"));
  c.width = ch.Number("width_m", Range::Closed(1.0, 3.0, "m"));
  c.roll_arm = ch.Number("roll_arm_m", Range::Closed(0.0, 2.0, "m"));
  c.pitch_arm = ch.Number("pitch_arm_m", Range::Closed(0.0, 2.0, "m"));
  c.roll_stiffness = ch.Number("roll_stiffness_nmprad", Range::Positive(1.0e7, "N m/rad"));
  c.roll_damping = ch.Number("roll_damping_nmsprad", Range::Positive(1.0e6, "N m s/rad"));
  c.pitch_stiffness = ch.Number("pitch_stiffness_nmprad", Range::Positive(1.0e7, "N m/rad"));
  c.pitch_damping = ch.Number("pitch_damping_nmsprad", Range::Positive(1.0e6, "N m s/rad"));
  c.roll_stiffness_front = ch.Number("roll_stiffness_front_share", Range::Closed(0.0, 1.0));
  c.drag_area = ch.Number("drag_area_m2", Range::Closed(0.0, 10.0, "m^2"));
  c.air_density = ch.NumberOr("air_density_kgpm3", 1.2, Range::Closed(0.0, 2.0, "kg/m^3"));
  ch.Finish();
  if (!(c.cg_to_front < c.wheelbase)) {
    Fail(map, "chassis", "cg_to_front_m < wheelbase_m", FormatDouble(c.cg_to_front));
  }
  // the body must not tip over in a steady roll: K_φ > m g h_φ
  if (!(c.roll_stiffness > c.mass * kGravity * c.roll_arm)) {
    Fail(map, "chassis", "roll_stiffness_nmprad > mass·g·roll_arm (statically stable roll)",
         FormatDouble(c.roll_stiffness));
  }
  if (!(c.pitch_stiffness > c.mass * kGravity * c.pitch_arm)) {
    Fail(map, "chassis", "pitch_stiffness_nmprad > mass·g·pitch_arm (statically stable pitch)",
         FormatDouble(c.pitch_stiffness));
  }

  YamlMap ty = map.Map("tyre");
  TyreParams& t = car.tyre;
  t.radius = ty.Number("radius_m", Range::Closed(0.1, 1.0, "m"));
  t.wheel_inertia = ty.Number("wheel_inertia_kgm2", Range::Positive(50.0, "kg m^2"));
  t.mu_x = ty.Number("mu_x", Range::Positive(3.0));
  t.mu_y = ty.Number("mu_y", Range::Positive(3.0));
  t.shape_x = ty.Number("shape_x", Range::Closed(1.0, 2.0));
  t.shape_y = ty.Number("shape_y", Range::Closed(1.0, 2.0));
  t.curvature_x = ty.Number("curvature_x", Range{-10.0, 1.0, false, true, ""});
  t.curvature_y = ty.Number("curvature_y", Range{-10.0, 1.0, false, true, ""});
  t.slip_stiffness = ty.Number("slip_stiffness_per_load", Range::Positive(100.0));
  t.cornering_c1 = ty.Number("cornering_c1_nprad", Range::Positive(1.0e6, "N/rad"));
  t.cornering_c2 = ty.Number("cornering_c2_n", Range::Positive(1.0e5, "N"));
  t.relax_x = ty.Number("relaxation_x_m", Range::Positive(5.0, "m"));
  t.relax_y = ty.Number("relaxation_y_m", Range::Positive(5.0, "m"));
  t.low_speed = ty.Number("low_speed_mps", Range::Positive(10.0, "m/s"));
  t.low_speed_damping = ty.Number("low_speed_damping_nspm", Range::Closed(0.0, 1.0e5, "N s/m"));
  t.carcass_damping_time = ty.Number("carcass_damping_time_s", Range::Closed(0.0, 0.1, "s"));
  t.rolling_resistance = ty.Number("rolling_resistance", Range::Closed(0.0, 0.2));
  ty.Finish();

  YamlMap en = map.Map("engine");
  EngineParams& e = car.engine;
  e.inertia = en.Number("inertia_kgm2", Range::Positive(10.0, "kg m^2"));
  e.idle_rpm = en.Number("idle_rpm", Range::Positive(3000.0, "rpm"));
  e.stall_rpm = en.Number("stall_rpm", Range::Positive(3000.0, "rpm"));
  e.max_rpm = en.Number("max_rpm", Range::Positive(20000.0, "rpm"));
  e.idle_gain = en.Number("idle_gain_per_rpm", Range::Closed(0.0, 1.0, "1/rpm"));
  e.idle_integral_gain = en.Number("idle_integral_gain_per_rpms", Range::Closed(0.0, 10.0, "1/(rpm s)"));
  e.idle_max_throttle = en.Number("idle_max_throttle", Range::Closed(0.0, 1.0));
  {
    YAML::Node rows = en.Sequence("torque_map");
    const std::string field = en.FieldName("torque_map");
    e.map.clear();
    for (std::size_t i = 0; i < rows.size(); ++i) {
      YamlMap row(rows[i], en.file(), field + "[" + std::to_string(i) + "]", en.LineOfKey("torque_map"));
      TorquePoint p;
      p.rpm = row.Number("rpm", Range::Closed(0.0, 20000.0, "rpm"));
      p.full_load = row.Number("full_load_nm", Range::Closed(0.0, 1.0e4, "N m"));
      p.closed_throttle = row.Number("closed_throttle_nm", Range::Closed(-1.0e4, 0.0, "N m"));
      row.Finish();
      if (i == 0 && p.rpm != 0.0) row.Fail("rpm", "the first point at 0 rpm", FormatDouble(p.rpm));
      if (i > 0 && !(p.rpm > e.map.back().rpm)) {
        row.Fail("rpm", "rpm rising strictly", FormatDouble(p.rpm) + " after " + FormatDouble(e.map.back().rpm));
      }
      e.map.push_back(p);
    }
    if (e.map.size() < 2) {
      throw InputError(en.file().string(), en.LineOfKey("torque_map"), field,
                       "at least 2 points {rpm, full_load_nm, closed_throttle_nm}",
                       std::to_string(e.map.size()) + " points");
    }
  }
  en.Finish();
  if (!(e.stall_rpm < e.idle_rpm && e.idle_rpm < e.max_rpm)) {
    Fail(map, "engine", "stall_rpm < idle_rpm < max_rpm",
         FormatDouble(e.stall_rpm) + ", " + FormatDouble(e.idle_rpm) + ", " + FormatDouble(e.max_rpm));
  }
  if (e.max_rpm > e.map.back().rpm) {
    Fail(map, "engine", "max_rpm within the torque map (≤ its last rpm)", FormatDouble(e.max_rpm));
  }

  YamlMap cl = map.Map("clutch");
  car.clutch.max_torque = cl.Number("max_torque_nm", Range::Positive(1.0e4, "N m"));
  car.clutch.engaged_pedal = cl.Number("engaged_pedal", Range::Closed(0.0, 1.0));
  car.clutch.free_pedal = cl.Number("free_pedal", Range::Closed(0.0, 1.0));
  cl.Finish();
  if (!(car.clutch.engaged_pedal < car.clutch.free_pedal)) {
    Fail(map, "clutch", "engaged_pedal < free_pedal", FormatDouble(car.clutch.engaged_pedal));
  }

  YamlMap gb = map.Map("gearbox");
  const std::string convention =
      gb.Choice("ratio_convention", {"input_over_output", "output_over_input"});
  const bool invert = convention == "output_over_input";
  std::vector<double> ratios = gb.Numbers("ratios", Range::Positive(20.0), 1, 10);
  double reverse = gb.Number("reverse", Range{-20.0, 0.0, false, true, ""});
  double final_drive = gb.Number("final_drive", Range::Positive(20.0));
  if (invert) {
    for (double& r : ratios) r = 1.0 / r;
    reverse = 1.0 / reverse;
    final_drive = 1.0 / final_drive;
  }
  for (std::size_t i = 1; i < ratios.size(); ++i) {
    if (!(ratios[i] < ratios[i - 1])) {
      gb.Fail("ratios", "ratios falling from first to top gear (as ω_in/ω_out)",
              "gear " + std::to_string(i + 1) + " = " + FormatDouble(ratios[i]));
    }
  }
  car.gearbox.ratios = ratios;
  car.gearbox.reverse = reverse;
  car.gearbox.final_drive = final_drive;
  car.gearbox.efficiency = gb.Number("efficiency", Range{0.0, 1.0, true, false, ""});
  car.gearbox.front_drive = gb.Choice("driven_axle", {"front", "rear"}) == "front";
  gb.Finish();

  YamlMap br = map.Map("brakes");
  car.brakes.max_torque_front = br.Number("max_torque_front_nm", Range::Closed(0.0, 2.0e4, "N m"));
  car.brakes.max_torque_rear = br.Number("max_torque_rear_nm", Range::Closed(0.0, 2.0e4, "N m"));
  br.Finish();

  YamlMap st = map.Map("steering");
  car.steering.ratio = st.Number("ratio", Range::Positive(50.0));
  car.steering.max_wheel_angle =
      st.Number("max_wheel_angle_deg", Range::Positive(60.0, "deg")) * kPi / 180.0;
  st.Finish();
  return car;
}

Vehicle ReadVehicleFile(const std::filesystem::path& file) {
  return ReadTaggedYamlFile(file, "pwsim-vehicle/1", ParseVehicle);
}

}  // namespace pwsim::vehicle
