#include "report/car_checks.h"

#include <algorithm>
#include <cmath>

#include "engine/atomic_file.h"
#include "engine/vehicle/driver_inputs.h"
#include "engine/vehicle/vehicle_model.h"
#include "plot/plot.h"

namespace pwsim::report {
namespace {

using namespace vehicle;

constexpr double kDt = 1e-3;

VehicleState Rolling(const Vehicle& car, double speed, int gear) {
  VehicleState s = InitialState(car);
  s.u = speed;
  for (double& w : s.omega) w = speed / car.tyre.radius;
  if (gear > 0) {
    s.engine_speed = car.GearRatio(gear) * car.gearbox.final_drive * s.omega[0];
    s.clutch_locked = true;
  }
  return s;
}

nlohmann::ordered_json Understeer(const Vehicle& car, const std::filesystem::path& out) {
  const ChassisParams& c = car.chassis;
  const std::array<double, 2> fz = StaticWheelLoads(car);
  const double cf = 2.0 * CorneringStiffness(car.tyre, fz[0]);
  const double cr = 2.0 * CorneringStiffness(car.tyre, fz[1]);
  const double k_closed = c.mass / c.wheelbase * (c.cg_to_rear() / cf - c.cg_to_front / cr);
  const double speed = 20.0;
  std::vector<double> ay, excess_deg;
  for (double steer_deg = 2.0; steer_deg <= 60.0; steer_deg += 2.0) {
    VehicleState s = Rolling(car, speed, 4);
    double integral = 0.0;
    for (int k = 0; k < 12000; ++k) {
      DriverInput in;
      in.gear = 4;
      const double e = speed - s.u;
      integral += e * kDt;
      in.throttle = std::clamp(0.2 + 0.5 * e + 0.2 * integral, 0.0, 1.0);
      in.steer = steer_deg * kPi / 180.0;
      s = StepVehicle(car, s, in, kDt);
    }
    if (!(std::abs(s.u - speed) < 0.5)) break;  // beyond the grip at this speed
    ay.push_back(s.u * s.r);
    excess_deg.push_back((steer_deg * kPi / 180.0 / car.steering.ratio - c.wheelbase * s.r / s.u) * 180.0 / kPi);
  }
  // measured gradient over the linear range (a_y < 2 m/s²), least squares through the origin
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < ay.size(); ++i) {
    if (ay[i] > 2.0) continue;
    sxy += ay[i] * excess_deg[i] * kPi / 180.0;
    sxx += ay[i] * ay[i];
  }
  const double k_measured = sxx > 0.0 ? sxy / sxx : 0.0;
  std::vector<double> line(ay.size());
  for (std::size_t i = 0; i < ay.size(); ++i) line[i] = k_closed * ay[i] * 180.0 / kPi;
  plot::Figure fig;
  fig.title = "steady-state cornering at 20 m/s: the model against the linear single-track model";
  fig.x_label = "lateral acceleration a_y [m/s²]";
  plot::Panel p;
  p.title = "road-wheel angle beyond the Ackermann angle, delta - L/R";
  p.y_label = "steer angle beyond Ackermann [deg]";
  p.series.push_back({"pwsim car model (steady state after 12 s)", ay, excess_deg, plot::Style::kLinesPoints, plot::color::kSimulated});
  p.series.push_back({"single-track model K a_y (closed form)", ay, line, plot::Style::kLines, plot::color::kReference});
  fig.panels.push_back(p);
  plot::WriteFigure(out / "car_understeer", fig);
  return {{"speed_mps", speed},
          {"front_axle_cornering_stiffness_nprad", cf},
          {"rear_axle_cornering_stiffness_nprad", cr},
          {"understeer_gradient_closed_form_radpmps2", k_closed},
          {"understeer_gradient_closed_form_degpg", k_closed * 180.0 / kPi * kGravity},
          {"understeer_gradient_measured_radpmps2", k_measured},
          {"relative_difference", (k_measured - k_closed) / k_closed},
          {"max_steady_ay_mps2", ay.empty() ? 0.0 : ay.back()}};
}

nlohmann::ordered_json Launch(const Vehicle& car, const std::filesystem::path& out) {
  PathDriverParams p;
  p.upshift_rpm = 6000.0;
  p.launch_rpm = 3000.0;
  p.launch_time = 0.8;
  p.shift_time = 0.4;
  p.speed_gain = 5.0;
  PathDriver driver(p, {{0.0, 0.0}, {3000.0, 0.0}}, {{0.0, 45.0}, {3000.0, 45.0}});
  VehicleState s = InitialState(car);
  std::vector<double> t, kmh, rpm, gear;
  double t100 = -1.0;
  for (int k = 0; k < 20000; ++k) {
    const DriverInput in = driver.Step(car, s, kDt);
    s = StepVehicle(car, s, in, kDt);
    if (t100 < 0.0 && s.u >= 100.0 / 3.6) t100 = (k + 1) * kDt;
    if (k % 10 == 0) {
      t.push_back((k + 1) * kDt);
      kmh.push_back(s.u * 3.6);
      rpm.push_back(EngineRpm(s));
      gear.push_back(in.gear);
    }
  }
  double p_max = 0.0, rpm_at_p_max = 0.0;
  for (const TorquePoint& q : car.engine.map) {
    if (q.rpm <= car.engine.max_rpm && q.full_load * q.rpm * kRpmToRadps > p_max) {
      p_max = q.full_load * q.rpm * kRpmToRadps;
      rpm_at_p_max = q.rpm;
    }
  }
  const double v = 100.0 / 3.6;
  plot::Figure fig;
  fig.title = "0-100 km/h, closed-loop driver shifting at 6000 rpm";
  fig.x_label = "time [s]";
  fig.panels.push_back({"vehicle speed", "speed [km/h]", {{"speed", t, kmh, plot::Style::kLines, plot::color::kSimulated}}, {}, false, 0.0, 0.0});
  fig.panels.push_back({"engine speed", "engine speed [rpm]", {{"engine", t, rpm, plot::Style::kLines, plot::color::kReference}}, {}, false, 0.0, 0.0});
  fig.panels.push_back({"gear engaged", "gear", {{"gear", t, gear, plot::Style::kSteps, plot::color::kGreen}}, {}, false, 0.0, 0.0, 1.0});
  plot::WriteFigure(out / "car_launch", fig);
  return {{"zero_to_100_kmh_s", t100},
          {"max_power_kw", p_max / 1000.0},
          {"at_rpm", rpm_at_p_max},
          {"power_bound_s", car.chassis.mass * v * v / (2.0 * p_max)},
          {"speed_after_20_s_kmh", kmh.back()}};
}

nlohmann::ordered_json Energy(const Vehicle& car, const std::filesystem::path& out) {
  VehicleState s = InitialState(car);
  const double ke0 = KineticEnergy(car, s);
  double engine = 0, clutch = 0, driveline = 0, tyre = 0, drag = 0, resist = 0;
  std::vector<double> t, work, balance;
  for (int k = 0; k < 8000; ++k) {
    const double time = k * kDt;
    DriverInput in;
    in.gear = time < 4.0 ? 1 : 2;
    const bool shifting = time > 3.8 && time < 4.5;
    in.throttle = shifting ? 0.0 : 0.5;
    in.clutch = time < 2.0 ? 0.7 * (1.0 - time / 2.0) : (shifting ? (time < 4.0 ? 1.0 : 0.7 * (4.5 - time) / 0.5) : 0.0);
    StepInfo info;
    const VehicleState n = StepVehicle(car, s, in, kDt, &info);
    const double we = 0.5 * (s.engine_speed + n.engine_speed);
    engine += info.engine_torque * we * kDt;
    double wheel_side = 0.0;
    for (int i = 0; i < kWheels; ++i) {
      const double w = 0.5 * (s.omega[i] + n.omega[i]);
      wheel_side += info.drive_torque[i] * w;
      tyre += (info.force[i].fx * (car.tyre.radius * w - info.vcx[i]) - info.force[i].fy * info.vcy[i]) * kDt;
      resist += info.resist_torque[i] * std::abs(w) * kDt;
    }
    const double wc = info.gearbox_ratio * 0.25 * (s.omega[0] + n.omega[0] + s.omega[1] + n.omega[1]);
    clutch += info.clutch_torque * (we - wc) * kDt;
    driveline += (info.clutch_torque * wc - wheel_side) * kDt;
    drag += info.drag_force * 0.5 * (s.u + n.u) * kDt;
    s = n;
    if (k % 10 == 0) {
      t.push_back((k + 1) * kDt);
      work.push_back(engine / 1000.0);
      balance.push_back((KineticEnergy(car, s) - ke0 + clutch + driveline + tyre + drag + resist) / 1000.0);
    }
  }
  const double dke = KineticEnergy(car, s) - ke0;
  plot::Figure fig;
  fig.title = "work-energy balance over a launch in 1st and 2nd gear";
  fig.x_label = "time [s]";
  fig.panels.push_back({"engine work against kinetic energy + losses", "energy [kJ]",
                        {{"engine work (integral of T_e w_e)", t, work, plot::Style::kLines, plot::color::kSimulated},
                         {"dKE + clutch + driveline + tyre + drag + rolling losses", t, balance, plot::Style::kLines, plot::color::kReference}},
                        {}, false, 0.0, 0.0});
  plot::WriteFigure(out / "car_energy", fig);
  const double losses = clutch + driveline + tyre + drag + resist;
  return {{"engine_work_j", engine},       {"kinetic_energy_gain_j", dke},  {"clutch_loss_j", clutch},
          {"driveline_loss_j", driveline}, {"tyre_slip_loss_j", tyre},     {"drag_loss_j", drag},
          {"rolling_loss_j", resist},      {"residual_j", engine - dke - losses},
          {"residual_fraction", (engine - dke - losses) / engine}};
}

nlohmann::ordered_json Stall(const Vehicle& car, const std::filesystem::path& out) {
  std::vector<double> t, dropped, slow;
  VehicleState a = InitialState(car), b = InitialState(car);
  bool a_stalled = false, b_stalled = false;
  for (int k = 0; k < 4000; ++k) {
    const double time = k * kDt;
    DriverInput in_a;
    in_a.gear = 5;
    in_a.clutch = std::max(0.0, 1.0 - time / 0.1);
    a = StepVehicle(car, a, in_a, kDt);
    DriverInput in_b;
    in_b.gear = 1;
    in_b.throttle = std::clamp(0.15 + 0.002 * (1800.0 - EngineRpm(b)), 0.0, 1.0);
    in_b.clutch = std::clamp(0.7 * (1.0 - time / 1.5), 0.0, 1.0);
    b = StepVehicle(car, b, in_b, kDt);
    a_stalled = a_stalled || !a.engine_running;
    b_stalled = b_stalled || !b.engine_running;
    if (k % 5 == 0) {
      t.push_back(time);
      dropped.push_back(EngineRpm(a));
      slow.push_back(EngineRpm(b));
    }
  }
  plot::Figure fig;
  fig.title = "stall: clutch dropped in 5th at idle, against a slow release in 1st holding 1800 rpm";
  fig.x_label = "time [s]";
  fig.panels.push_back({"engine speed", "engine speed [rpm]",
                        {{"5th, clutch dropped in 0.1 s, no throttle", t, dropped, plot::Style::kLines, plot::color::kReference},
                         {"1st, clutch released over 1.5 s with throttle", t, slow, plot::Style::kLines, plot::color::kSimulated}},
                        {}, false, 0.0, 0.0});
  plot::WriteFigure(out / "car_stall", fig);
  return {{"dropped_in_fifth_stalls", a_stalled}, {"slow_release_in_first_stalls", b_stalled},
          {"stall_rpm", car.engine.stall_rpm}};
}

nlohmann::ordered_json Ratios(const Vehicle& car) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int gear = 1; gear <= car.gear_count(); ++gear) {
    const double i = car.GearRatio(gear) * car.gearbox.final_drive;
    const double speed = 2500.0 * kRpmToRadps / i * car.tyre.radius;  // 2500 rpm
    VehicleState s = Rolling(car, speed, gear);
    for (int k = 0; k < 3000; ++k) {
      DriverInput in;
      in.gear = gear;
      in.throttle = 0.3;
      s = StepVehicle(car, s, in, kDt);
    }
    const double wheel = 0.5 * (s.omega[0] + s.omega[1]);
    rows.push_back({{"gear", gear},
                    {"ratio_total", i},
                    {"engine_rpm", EngineRpm(s)},
                    {"wheel_times_ratios_rpm", wheel * i / kRpmToRadps},
                    {"speed_times_ratios_rpm", s.u / car.tyre.radius * i / kRpmToRadps},
                    {"clutch_locked", s.clutch_locked}});
  }
  return rows;
}

}  // namespace

nlohmann::ordered_json RunCarChecks(const Vehicle& car, const std::filesystem::path& vehicle_file,
                                    const std::filesystem::path& out_dir) {
  std::filesystem::create_directories(out_dir);
  nlohmann::ordered_json result;
  result["format"] = "pwsim-car-checks/1";
  result["vehicle"] = {{"name", car.name}, {"file", vehicle_file.string()}};
  result["data"] = "same-model simulation against closed forms (no measured car)";
  result["understeer"] = Understeer(car, out_dir);
  result["launch"] = Launch(car, out_dir);
  result["energy"] = Energy(car, out_dir);
  result["stall"] = Stall(car, out_dir);
  result["locked_clutch_ratios"] = Ratios(car);
  WriteFileAtomically(out_dir / "car_checks.json", result.dump(2) + "\n");
  return result;
}

}  // namespace pwsim::report
