#include "engine/vehicle/vehicle_model.h"

#include <algorithm>
#include <cmath>

namespace pwsim::vehicle {

namespace {

double Sign(double x) { return (x > 0.0) - (x < 0.0); }

/// Exact Coulomb step: speed `w` under torque `t` [N m] and a resisting torque of magnitude `res`.
double CoulombStep(double w, double t, double res, double inertia, double dt) {
  const double free = w + dt * t / inertia;
  const double drop = dt * res / inertia;
  if (std::abs(free) <= drop) return 0.0;
  return free - std::copysign(drop, free);
}

}  // namespace

std::array<std::array<double, 2>, kWheels> WheelPositions(const Vehicle& car) {
  const ChassisParams& c = car.chassis;
  const double a = c.cg_to_front;
  const double b = c.cg_to_rear();
  return {{{a, 0.5 * c.track_front}, {a, -0.5 * c.track_front}, {-b, 0.5 * c.track_rear},
           {-b, -0.5 * c.track_rear}}};
}

std::array<double, 2> StaticWheelLoads(const Vehicle& car) {
  const ChassisParams& c = car.chassis;
  const double w = c.mass * kGravity;
  return {0.5 * w * c.cg_to_rear() / c.wheelbase, 0.5 * w * c.cg_to_front / c.wheelbase};
}

VehicleState InitialState(const Vehicle& car) {
  VehicleState s;
  s.engine_speed = car.engine.idle_rpm * kRpmToRadps;
  s.engine_running = true;
  return s;
}

double KineticEnergy(const Vehicle& car, const VehicleState& s) {
  double e = 0.5 * car.chassis.mass * (s.u * s.u + s.v * s.v) + 0.5 * car.chassis.yaw_inertia * s.r * s.r;
  for (double w : s.omega) e += 0.5 * car.tyre.wheel_inertia * w * w;
  return e + 0.5 * car.engine.inertia * s.engine_speed * s.engine_speed;
}

VehicleState StepVehicle(const Vehicle& car, const VehicleState& s, const DriverInput& input,
                         double dt, StepInfo* info) {
  const ChassisParams& ch = car.chassis;
  const TyreParams& ty = car.tyre;
  const EngineParams& en = car.engine;
  const double m = ch.mass;
  const double a = ch.cg_to_front;
  const double b = ch.cg_to_rear();
  const double L = ch.wheelbase;
  const double h = ch.cg_height;
  const double R = ty.radius;
  const double Jw = ty.wheel_inertia;
  const std::array<std::array<double, 2>, kWheels> pos = WheelPositions(car);

  VehicleState n = s;

  // steering: steering wheel → road wheels (parallel steer)
  const double delta = std::clamp(input.steer / car.steering.ratio, -car.steering.max_wheel_angle,
                                  car.steering.max_wheel_angle);
  const double cd = std::cos(delta);
  const double sd = std::sin(delta);

  // normal loads from the last step's accelerations
  std::array<double, kWheels> fz{};
  {
    const double fzf = m * (kGravity * b - s.ax * h) / L;
    const double fzr = m * (kGravity * a + s.ax * h) / L;
    const double dff = m * s.ay * h * ch.roll_stiffness_front / ch.track_front;
    const double dfr = m * s.ay * h * (1.0 - ch.roll_stiffness_front) / ch.track_rear;
    fz[kFrontLeft] = std::max(0.0, 0.5 * fzf - dff);
    fz[kFrontRight] = std::max(0.0, 0.5 * fzf + dff);
    fz[kRearLeft] = std::max(0.0, 0.5 * fzr - dfr);
    fz[kRearRight] = std::max(0.0, 0.5 * fzr + dfr);
  }

  // tyre forces from the lagged slips
  std::array<TyreForce, kWheels> force{};
  std::array<double, kWheels> vcx{}, vcy{};
  double fx_body = 0.0, fy_body = 0.0, mz = 0.0;
  for (int i = 0; i < kWheels; ++i) {
    const bool front = i < 2;
    const double c = front ? cd : 1.0;
    const double sn = front ? sd : 0.0;
    const double vbx = s.u - s.r * pos[i][1];
    const double vby = s.v + s.r * pos[i][0];
    vcx[i] = vbx * c + vby * sn;
    vcy[i] = -vbx * sn + vby * c;
    force[i] = TyreForceFromState(ty, s.slip[i], fz[i], vcx[i], vcy[i], R * s.omega[i]);
    const double fxb = force[i].fx * c - force[i].fy * sn;
    const double fyb = force[i].fx * sn + force[i].fy * c;
    fx_body += fxb;
    fy_body += fyb;
    mz += pos[i][0] * fyb - pos[i][1] * fxb;
  }
  const double drag = 0.5 * ch.air_density * ch.drag_area * s.u * std::abs(s.u);
  fx_body -= drag;

  // resisting torques: brakes and rolling resistance (Coulomb)
  std::array<double, kWheels> resist{};
  const double brake = std::clamp(input.brake, 0.0, 1.0);
  for (int i = 0; i < kWheels; ++i) {
    const double tb = (i < 2 ? car.brakes.max_torque_front : car.brakes.max_torque_rear) * brake;
    resist[i] = tb + ty.rolling_resistance * fz[i] * R;
  }

  // powertrain
  const int d0 = car.gearbox.front_drive ? kFrontLeft : kRearLeft;
  const int d1 = d0 + 1;
  const bool valid_gear = input.gear >= -1 && input.gear <= car.gear_count();
  const double ratio = valid_gear ? car.GearRatio(input.gear) * car.gearbox.final_drive : 0.0;
  const double capacity = ratio != 0.0 ? ClutchCapacity(car.clutch, input.clutch) : 0.0;
  const double rpm = s.engine_speed / kRpmToRadps;
  double engine_torque = 0.0;
  double throttle = 0.0;
  double engine_friction = 0.0;  // Coulomb friction magnitude of a stopped engine
  if (s.engine_running) {
    const IdleOutput idle = IdleControl(en, s.idle, rpm, input.throttle, dt);
    throttle = idle.throttle;
    n.idle = idle.next;
    engine_torque = EngineTorque(en, rpm, throttle);
  } else {
    engine_friction = -EngineCurvesAt(en, rpm).closed_throttle;
    engine_torque = -engine_friction * Sign(s.engine_speed);
    n.idle = IdleControllerState{};
  }
  const double omega_mean = 0.5 * (s.omega[d0] + s.omega[d1]);
  const double omega_c = ratio * omega_mean;
  const double eta = car.gearbox.efficiency;

  double clutch_torque = 0.0;
  bool locked = false;
  double eta_used = eta;
  if (capacity > 0.0) {
    const double load = R * (force[d0].fx + force[d1].fx) + resist[d0] * Sign(s.omega[d0]) +
                        resist[d1] * Sign(s.omega[d1]);
    auto required = [&](double e) {
      return (engine_torque / en.inertia + ratio * load / (2.0 * Jw)) /
             (1.0 / en.inertia + e * ratio * ratio / (2.0 * Jw));
    };
    double t_req = required(eta);
    if (t_req * omega_c < 0.0) t_req = required(1.0 / eta);
    const double slip = s.engine_speed - omega_c;
    if (s.clutch_locked || slip == 0.0) {
      if (std::abs(t_req) <= capacity) {
        locked = true;
        clutch_torque = t_req;
      } else {
        clutch_torque = std::copysign(capacity, t_req);
      }
    } else {
      clutch_torque = std::copysign(capacity, slip);
    }
    eta_used = clutch_torque * omega_c >= 0.0 ? eta : 1.0 / eta;
  }

  // wheel spin
  std::array<double, kWheels> drive{};
  if (capacity > 0.0) {
    drive[d0] = drive[d1] = 0.5 * eta_used * ratio * clutch_torque;
  }
  for (int i = 0; i < kWheels; ++i) {
    n.omega[i] = CoulombStep(s.omega[i], drive[i] - R * force[i].fx, resist[i], Jw, dt);
  }
  const double omega_c_new = ratio * 0.5 * (n.omega[d0] + n.omega[d1]);

  // engine speed
  if (s.engine_running) {
    n.engine_speed = s.engine_speed + dt * (engine_torque - clutch_torque) / en.inertia;
  } else {
    n.engine_speed = CoulombStep(s.engine_speed, -clutch_torque, engine_friction, en.inertia, dt);
  }
  if (locked) {
    n.engine_speed = omega_c_new;
  } else if (capacity > 0.0) {
    // slipping: lock when the slip speed changed sign within the step
    const double slip_old = s.engine_speed - omega_c;
    const double slip_new = n.engine_speed - omega_c_new;
    if (slip_old * slip_new <= 0.0) {
      locked = true;
      n.engine_speed = omega_c_new;
    }
  }
  n.clutch_locked = locked;

  // stall and restart
  if (n.engine_running && n.engine_speed < en.stall_rpm * kRpmToRadps) n.engine_running = false;
  if (!n.engine_running && input.starter && capacity == 0.0) {
    n.engine_running = true;
    n.engine_speed = en.idle_rpm * kRpmToRadps;
    n.idle = IdleControllerState{};
  }

  // chassis: speeds, then the exact rotation of the body-frame velocity, then poses
  const double ax = fx_body / m;
  const double ay = fy_body / m;
  const double yaw_accel = mz / ch.yaw_inertia;
  n.r = s.r + dt * yaw_accel;
  {
    const double u1 = s.u + dt * ax;
    const double v1 = s.v + dt * ay;
    const double turn = n.r * dt;
    const double ct = std::cos(turn);
    const double st = std::sin(turn);
    n.u = u1 * ct + v1 * st;
    n.v = -u1 * st + v1 * ct;
  }
  n.ax = ax;
  n.ay = ay;
  n.yaw_accel = yaw_accel;
  n.yaw = s.yaw + dt * n.r;
  const double cy = std::cos(n.yaw);
  const double sy = std::sin(n.yaw);
  n.x = s.x + dt * (n.u * cy - n.v * sy);
  n.y = s.y + dt * (n.u * sy + n.v * cy);

  // roll and pitch of the body on its springs
  {
    const double roll_acc = (m * ch.roll_arm * (ay + kGravity * s.roll) - ch.roll_stiffness * s.roll -
                             ch.roll_damping * s.roll_rate) / ch.roll_inertia;
    n.roll_rate = s.roll_rate + dt * roll_acc;
    n.roll = s.roll + dt * n.roll_rate;
    const double pitch_acc = (m * ch.pitch_arm * (ax + kGravity * s.pitch) - ch.pitch_stiffness * s.pitch -
                              ch.pitch_damping * s.pitch_rate) / ch.pitch_inertia;
    n.pitch_rate = s.pitch_rate + dt * pitch_acc;
    n.pitch = s.pitch + dt * n.pitch_rate;
  }

  // tyre relaxation with the new speeds
  for (int i = 0; i < kWheels; ++i) {
    const bool front = i < 2;
    const double c = front ? cd : 1.0;
    const double sn = front ? sd : 0.0;
    const double vbx = n.u - n.r * pos[i][1];
    const double vby = n.v + n.r * pos[i][0];
    n.slip[i] = RelaxSlip(ty, s.slip[i], vbx * c + vby * sn, -vbx * sn + vby * c, R * n.omega[i], dt);
  }

  if (info != nullptr) {
    info->road_wheel_angle = delta;
    info->throttle = throttle;
    info->engine_torque = engine_torque;
    info->clutch_torque = clutch_torque;
    info->clutch_capacity = capacity;
    info->gearbox_ratio = ratio;
    info->drag_force = drag;
    info->fz = fz;
    info->force = force;
    info->vcx = vcx;
    info->vcy = vcy;
    info->drive_torque = drive;
    info->resist_torque = resist;
  }
  return n;
}

}  // namespace pwsim::vehicle
