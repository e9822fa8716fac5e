// Checks of the car model against closed forms and physics (issue 13, item 6). Truths come from
// closed forms written out here (linear single-track model, gear kinematics, work-energy), not
// from the code under test.
#include "engine/vehicle/vehicle_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "engine/vehicle/driver_inputs.h"
#include "engine/vehicle/vehicle_params.h"

namespace pwsim::vehicle {
namespace {

constexpr double kDt = 1e-3;

Vehicle Car() { return ReadVehicleFile(PWSIM_SOURCE_DIR "/assets/cars/midsize.yaml"); }

using Controls = std::function<DriverInput(double t, const VehicleState& s)>;

/// Runs `seconds` from `state`; calls `each` after every step with the step's info.
VehicleState Drive(const Vehicle& car, VehicleState state, double seconds, const Controls& controls,
                 const std::function<void(double, const VehicleState&, const VehicleState&,
                                          const DriverInput&, const StepInfo&)>& each = nullptr) {
  const long ticks = std::lround(seconds / kDt);
  for (long k = 0; k < ticks; ++k) {
    const double t = static_cast<double>(k) * kDt;
    const DriverInput in = controls(t, state);
    StepInfo info;
    const VehicleState next = StepVehicle(car, state, in, kDt, &info);
    if (each) each(t, state, next, in, info);
    state = next;
  }
  return state;
}

TEST(VehicleModel, AtRestStaysAtRestWithoutBlowUp) {
  const Vehicle car = Car();
  VehicleState s = Drive(car, InitialState(car), 10.0, [](double t, const VehicleState&) {
    DriverInput in;
    in.steer = 3.0 * std::sin(t);  // steering at standstill: tyres deflect, nothing diverges
    return in;
  });
  EXPECT_TRUE(std::isfinite(s.u) && std::isfinite(s.v) && std::isfinite(s.r));
  EXPECT_LT(std::hypot(s.x, s.y), 0.05);
  EXPECT_LT(std::abs(s.yaw), 0.01);
  EXPECT_TRUE(s.engine_running);
  // idle control holds the engine near idle in neutral
  EXPECT_NEAR(EngineRpm(s), car.engine.idle_rpm, 25.0);
}

TEST(VehicleModel, BrakedToAStopSettles) {
  const Vehicle car = Car();
  VehicleState s = InitialState(car);
  s.u = 15.0;
  for (double& w : s.omega) w = 15.0 / car.tyre.radius;
  s = Drive(car, s, 8.0, [](double, const VehicleState&) {
    DriverInput in;
    in.brake = 0.6;
    in.clutch = 1.0;
    return in;
  });
  EXPECT_LT(std::abs(s.u), 1e-3);
  EXPECT_LT(std::abs(s.omega[0]), 1e-3);
  // stopping distance from 15 m/s at ≤ μ g: at least v²/(2 μ g)
  EXPECT_GT(s.x, 15.0 * 15.0 / (2.0 * car.tyre.mu_x * kGravity));
}

TEST(Tyre, PureSlipIsTheMagicFormula) {
  const TyreParams t = Car().tyre;
  const double fz = 4000.0;
  // closed form: F = D sin(C atan(Bx - E(Bx - atan Bx))), B = BCD/(C D)
  const double c_alpha = t.cornering_c1 * std::sin(2.0 * std::atan(fz / t.cornering_c2));
  for (double alpha : {0.01, 0.05, 0.1, 0.2, -0.08}) {
    const double d = t.mu_y * fz;
    const double b = c_alpha / (t.shape_y * d);
    const double x = std::tan(alpha);
    const double expected =
        d * std::sin(t.shape_y * std::atan(b * x - t.curvature_y * (b * x - std::atan(b * x))));
    EXPECT_NEAR(CombinedSlipForce(t, 0.0, x, fz).fy, expected, 1e-9 * d) << alpha;
  }
  for (double kappa : {0.01, 0.05, 0.15, -0.3}) {
    const double d = t.mu_x * fz;
    const double b = t.slip_stiffness * fz / (t.shape_x * d);
    const double expected =
        d * std::sin(t.shape_x * std::atan(b * kappa - t.curvature_x * (b * kappa - std::atan(b * kappa))));
    EXPECT_NEAR(CombinedSlipForce(t, kappa, 0.0, fz).fx, expected, 1e-9 * d) << kappa;
  }
}

TEST(Tyre, CombinedSlipStaysInsideTheFrictionEllipse) {
  const TyreParams t = Car().tyre;
  const double fz = 4000.0;
  double worst = 0.0;
  for (double kappa = -0.5; kappa <= 0.5; kappa += 0.01) {
    for (double a = -0.4; a <= 0.4; a += 0.01) {
      const TyreForce f = CombinedSlipForce(t, kappa, a, fz);
      const double e = std::pow(f.fx / (t.mu_x * fz), 2) + std::pow(f.fy / (t.mu_y * fz), 2);
      worst = std::max(worst, e);
      // braking or driving reduces the lateral force at the same slip angle
      if (std::abs(kappa) > 0.05 && std::abs(a) > 0.01) {
        EXPECT_LT(std::abs(f.fy), std::abs(CombinedSlipForce(t, 0.0, a, fz).fy));
      }
    }
  }
  EXPECT_LE(worst, 1.0 + 1e-12);
  EXPECT_GT(worst, 0.95);  // and the ellipse is reached
}

TEST(VehicleModel, LockedClutchEngineSpeedIsWheelSpeedTimesRatios) {
  const Vehicle car = Car();
  VehicleState s = InitialState(car);
  // rolling at 15 m/s in third, clutch released, part throttle
  s.u = 15.0;
  for (double& w : s.omega) w = 15.0 / car.tyre.radius;
  const double i3 = car.gearbox.ratios[2] * car.gearbox.final_drive;
  s.engine_speed = i3 * 15.0 / car.tyre.radius;
  s.clutch_locked = true;
  s = Drive(car, s, 5.0, [](double, const VehicleState&) {
    DriverInput in;
    in.gear = 3;
    in.throttle = 0.3;
    return in;
  });
  EXPECT_TRUE(s.clutch_locked);
  const double wheel = 0.5 * (s.omega[kFrontLeft] + s.omega[kFrontRight]);
  EXPECT_NEAR(s.engine_speed, 1.4 * 3.9 * wheel, 1e-9 * s.engine_speed);
  // and the vehicle speed: n = u/R · i within the driving slip (< 1 %)
  EXPECT_NEAR(s.engine_speed, 1.4 * 3.9 * s.u / car.tyre.radius, 0.01 * s.engine_speed);
}

TEST(VehicleModel, ClutchDroppedInHighGearAtIdleStalls) {
  const Vehicle car = Car();
  bool stalled = false;
  const VehicleState s =
      Drive(car, InitialState(car), 3.0, [](double t, const VehicleState&) {
        DriverInput in;
        in.gear = 5;
        in.clutch = std::max(0.0, 1.0 - t / 0.1);  // dropped within 0.1 s
        return in;
      }, [&](double, const VehicleState&, const VehicleState& n, const DriverInput&, const StepInfo&) {
        stalled = stalled || !n.engine_running;
      });
  EXPECT_TRUE(stalled);
  EXPECT_FALSE(s.engine_running);
  EXPECT_LT(EngineRpm(s), 50.0);
  EXPECT_LT(s.u, 1.0);  // the car barely moves
}

TEST(VehicleModel, SlowClutchReleaseInFirstWithThrottleDoesNotStall) {
  const Vehicle car = Car();
  // the pedal comes up over 1.5 s while the right foot holds about 1800 rpm, as a driver does
  const VehicleState s = Drive(car, InitialState(car), 4.0, [](double t, const VehicleState& st) {
    DriverInput in;
    in.gear = 1;
    in.throttle = std::clamp(0.15 + 0.002 * (1800.0 - EngineRpm(st)), 0.0, 1.0);
    in.clutch = std::clamp(0.7 * (1.0 - t / 1.5), 0.0, 1.0);
    return in;
  });
  EXPECT_TRUE(s.engine_running);
  EXPECT_TRUE(s.clutch_locked);
  EXPECT_GT(s.u, 2.0);
}

/// Steady-state cornering at constant speed: δ = L/R + K a_y with the understeer gradient of the
/// linear single-track model K = (m/L)(b/C_f - a/C_r), C_f, C_r the axle cornering stiffnesses at
/// the static loads.
TEST(VehicleModel, SteadyStateCorneringMatchesTheSingleTrackUndersteerGradient) {
  const Vehicle car = Car();
  const ChassisParams& c = car.chassis;
  const double fz_f = 0.5 * c.mass * kGravity * c.cg_to_rear() / c.wheelbase;
  const double fz_r = 0.5 * c.mass * kGravity * c.cg_to_front / c.wheelbase;
  const double cf = 2.0 * car.tyre.cornering_c1 * std::sin(2.0 * std::atan(fz_f / car.tyre.cornering_c2));
  const double cr = 2.0 * car.tyre.cornering_c1 * std::sin(2.0 * std::atan(fz_r / car.tyre.cornering_c2));
  const double k_expected = c.mass / c.wheelbase * (c.cg_to_rear() / cf - c.cg_to_front / cr);
  ASSERT_GT(k_expected, 0.0);  // the shipped car understeers

  const double speed = 20.0;
  std::vector<double> ay, excess;
  for (double steer_deg : {5.0, 10.0, 15.0}) {
    VehicleState s = InitialState(car);
    s.u = speed;
    for (double& w : s.omega) w = speed / car.tyre.radius;
    const double i4 = car.gearbox.ratios[3] * car.gearbox.final_drive;
    s.engine_speed = i4 * s.omega[0];
    s.clutch_locked = true;
    double integral = 0.0;
    s = Drive(car, s, 12.0, [&](double, const VehicleState& st) {
      DriverInput in;
      in.gear = 4;
      const double e = speed - st.u;
      integral += e * kDt;
      in.throttle = std::clamp(0.2 + 0.5 * e + 0.2 * integral, 0.0, 1.0);
      in.steer = steer_deg * kPi / 180.0;
      return in;
    });
    const double delta = steer_deg * kPi / 180.0 / car.steering.ratio;
    const double lateral = s.u * s.r;
    ay.push_back(lateral);
    excess.push_back(delta - c.wheelbase * s.r / s.u);
    EXPECT_NEAR(s.ay, lateral, 0.02 * lateral);  // steady: a_y = u r
  }
  // slope of (δ - L/R) over a_y by least squares through the origin region
  double sxy = 0, sxx = 0, mx = 0, my = 0;
  for (std::size_t i = 0; i < ay.size(); ++i) { mx += ay[i]; my += excess[i]; }
  mx /= static_cast<double>(ay.size());
  my /= static_cast<double>(ay.size());
  for (std::size_t i = 0; i < ay.size(); ++i) {
    sxy += (ay[i] - mx) * (excess[i] - my);
    sxx += (ay[i] - mx) * (ay[i] - mx);
  }
  const double k_measured = sxy / sxx;
  EXPECT_LT(ay.back(), 2.5);  // linear range
  EXPECT_NEAR(k_measured, k_expected, 0.1 * k_expected) << "ay " << ay[0] << " " << ay[1] << " " << ay[2];
}

/// Work-energy over a launch: engine work = Δ kinetic energy + every dissipation.
TEST(VehicleModel, EnergyBalanceOverALaunch) {
  const Vehicle car = Car();
  const VehicleState s0 = InitialState(car);
  double engine_work = 0, clutch_loss = 0, driveline_loss = 0, tyre_loss = 0, drag_loss = 0, resist_loss = 0;
  const VehicleState s1 = Drive(car, s0, 8.0, [](double t, const VehicleState&) {
    DriverInput in;
    in.gear = t < 4.0 ? 1 : 2;
    const bool shifting = t > 3.8 && t < 4.5;
    in.throttle = shifting ? 0.0 : 0.5;
    in.clutch = t < 2.0 ? 0.7 * (1.0 - t / 2.0) : (shifting ? (t < 4.0 ? 1.0 : 0.7 * (4.5 - t) / 0.5) : 0.0);
    return in;
  }, [&](double, const VehicleState& a, const VehicleState& b, const DriverInput&, const StepInfo& info) {
    const double we = 0.5 * (a.engine_speed + b.engine_speed);
    engine_work += info.engine_torque * we * kDt;
    const double ratio = info.gearbox_ratio;
    double wheel_side = 0.0;
    for (int i = 0; i < kWheels; ++i) {
      const double w = 0.5 * (a.omega[i] + b.omega[i]);
      wheel_side += info.drive_torque[i] * w;
      // tyre: power from the wheel into the contact minus power into the body
      tyre_loss += info.force[i].fx * (car.tyre.radius * w - info.vcx[i]) * kDt - info.force[i].fy * info.vcy[i] * kDt;
      resist_loss += info.resist_torque[i] * std::abs(w) * kDt;
    }
    const double wc = ratio * 0.5 * (0.5 * (a.omega[0] + b.omega[0]) + 0.5 * (a.omega[1] + b.omega[1]));
    clutch_loss += info.clutch_torque * (we - wc) * kDt;
    driveline_loss += (info.clutch_torque * wc - wheel_side) * kDt;
    drag_loss += info.drag_force * 0.5 * (a.u + b.u) * kDt;
  });
  ASSERT_GT(s1.u, 8.0);
  const double dke = KineticEnergy(car, s1) - KineticEnergy(car, s0);
  const double losses = clutch_loss + driveline_loss + tyre_loss + drag_loss + resist_loss;
  EXPECT_GT(clutch_loss, 0.0);
  EXPECT_GT(driveline_loss, 0.0);
  EXPECT_NEAR(engine_work, dke + losses, 0.01 * engine_work)
      << "work " << engine_work << " dKE " << dke << " clutch " << clutch_loss << " driveline " << driveline_loss
      << " tyre " << tyre_loss << " drag " << drag_loss << " resist " << resist_loss;
}

/// 0-100 km/h with the closed-loop driver shifting near peak power: plausible for a 110 kW,
/// 1.45 t car (8-12 s), and never faster than the power limit m v²/(2 P_max).
TEST(VehicleModel, ZeroToHundredIsPlausible) {
  const Vehicle car = Car();
  PathDriverParams p;
  p.upshift_rpm = 6000.0;
  p.launch_rpm = 3000.0;
  p.launch_time = 0.8;
  p.shift_time = 0.4;
  p.speed_gain = 5.0;
  PathDriver driver(p, {{0.0, 0.0}, {2000.0, 0.0}}, {{0.0, 40.0}, {2000.0, 40.0}});
  VehicleState s = InitialState(car);
  double t100 = -1.0;
  for (long k = 0; k < 30000 && t100 < 0.0; ++k) {
    s = StepVehicle(car, s, driver.Step(car, s, kDt), kDt);
    if (s.u >= 100.0 / 3.6) t100 = static_cast<double>(k + 1) * kDt;
  }
  double p_max = 0.0;
  for (const TorquePoint& q : car.engine.map) p_max = std::max(p_max, q.full_load * q.rpm * kRpmToRadps);
  const double v = 100.0 / 3.6;
  EXPECT_GT(t100, car.chassis.mass * v * v / (2.0 * p_max));
  EXPECT_GT(t100, 8.0);
  EXPECT_LT(t100, 12.0);
}

TEST(VehicleModel, Deterministic) {
  const Vehicle car = Car();
  auto drive = [&] {
    return Drive(car, InitialState(car), 6.0, [](double t, const VehicleState&) {
      DriverInput in;
      in.gear = 1;
      in.throttle = 0.4;
      in.clutch = std::clamp(0.7 * (1.0 - t / 1.5), 0.0, 1.0);
      in.steer = 0.5 * std::sin(t);
      return in;
    });
  };
  EXPECT_EQ(drive(), drive());
}

}  // namespace
}  // namespace pwsim::vehicle
