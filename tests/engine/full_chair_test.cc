// The full-DoF chair against the sagittal path (bit for bit on a straight run) and against
// closed forms derived here, independently of engine/full_chair.cc and engine/caster.cc.

#include "engine/full_chair.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "engine/scene.h"

namespace pwsim {
namespace {

constexpr double kG = 9.80665;
constexpr double kPi = std::numbers::pi;

// Tests that the straight run of scenes/speed_cushion.yaml through the full-DoF chair gives
// every sagittal quantity of today's trial.csv (x, v, a, Z_Oi, X_GM, X_M, rates, accelerations,
// torque) equal to the sagittal ChairSimulator's to 1e-9 (they are in fact identical bits), and
// that roll, lateral motion and yaw stay exactly 0.
TEST(FullChairTest, StraightRunReproducesTheSagittalChairSimulator) {
  const Scene scene = LoadScene(DefaultScenePath(PWSIM_SOURCE_DIR));
  const std::vector<ChairSample> sagittal = SimulateScene(scene);
  const std::vector<FullChairSample> full = SimulateSceneFullChair(scene);
  ASSERT_EQ(sagittal.size(), full.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < sagittal.size(); ++k) {
    const ChairSample& a = sagittal[k];
    const ChairSample b = SagittalView(full[k]);
    ASSERT_EQ(a.tick, b.tick);
    const double diffs[] = {a.drive.x - b.drive.x, a.drive.v - b.drive.v, a.drive.a - b.drive.a,
                            a.gm.z - b.gm.z, a.gm.pitch - b.gm.pitch, a.lm.z - b.lm.z,
                            a.lm.pitch - b.lm.pitch, a.lm.z_rate - b.lm.z_rate,
                            a.lm.pitch_rate - b.lm.pitch_rate, a.lm_acc.z - b.lm_acc.z,
                            a.lm_acc.pitch - b.lm_acc.pitch, a.z_gm_rate - b.z_gm_rate,
                            a.pitch_gm_rate - b.pitch_gm_rate, a.pitch_torque - b.pitch_torque};
    for (double d : diffs) worst = std::max(worst, std::abs(d));
    for (int i = 0; i < scene.chair.wheel_count(); ++i) worst = std::max(worst, std::abs(a.z_O[i] - b.z_O[i]));
    ASSERT_EQ(full[k].planar.y, 0.0);
    ASSERT_EQ(full[k].planar.yaw, 0.0);
    ASSERT_EQ(full[k].roll, 0.0);
  }
  EXPECT_LE(worst, 1e-9);
  // by construction the same operations on the same numbers: identical bits
  EXPECT_EQ(worst, 0.0);
  EXPECT_GT(std::abs(sagittal[3000].lm.pitch), 1e-3);  // the cushion was really crossed
}

struct Rig {
  Chair chair = MakeTableOneChair();
  PlanarLayout layout = DefaultPlanarLayout(chair);
  FloorMap floor;
  double load = 100.0;
};

/// Holds one joystick deflection for `seconds`; returns the samples.
std::vector<FullChairSample> Hold(FullChairSimulator& sim, JoystickInput input, double seconds) {
  std::vector<FullChairSample> out;
  const int ticks = static_cast<int>(std::lround(seconds / sim.dt()));
  for (int k = 0; k < ticks; ++k) out.push_back(sim.Advance(input));
  return out;
}

// Tests the steady turn: the path's radius of curvature (arc length over heading change, last
// 5 s) equals v/ω of the chair to 0.5 %, and v, ω reach the profile's closed-form set-points
// v* = s(f) v_fwd, ω* = s(t) ω_max (1 - (1 - ρ) s(f)), s(d) = (d - d0)/(1 - d0), to 0.5 %
// (the speed loops' integral action removes the droop under rolling resistance).
TEST(FullChairTest, SteadyTurnRadiusIsSpeedOverYawRate) {
  Rig rig;
  FullChairSimulator sim(rig.chair, rig.layout, rig.floor, rig.load, 1e-3);
  sim.Start({});
  Hold(sim, {0.5, 0.5}, 15.0);
  const FullChairSample a = sim.sample();
  Hold(sim, {0.5, 0.5}, 5.0);
  const FullChairSample b = sim.sample();
  const double radius = (b.distance - a.distance) / (b.planar.yaw - a.planar.yaw);
  EXPECT_NEAR(radius, b.planar.v / b.planar.yaw_rate, 0.005 * radius);

  const ControllerProfile& p = rig.layout.controller;
  const double s = (0.5 - p.deadband) / (1.0 - p.deadband);
  const double v_set = s * p.max_forward_speed;
  const double w_set = s * p.max_turn_rate * (1.0 - (1.0 - p.turn_rate_at_speed) * s);
  EXPECT_NEAR(b.planar.v, v_set, 0.005 * v_set);
  EXPECT_NEAR(b.planar.yaw_rate, w_set, 0.005 * w_set);
  EXPECT_NEAR(radius, v_set / w_set, 0.01 * radius);
  // turning left: a_y = v ω > 0 loads the right (outer) wheels
  EXPECT_GT(b.contacts[3].load, b.contacts[2].load);
  EXPECT_NEAR(b.a_y, b.planar.v * b.planar.yaw_rate, 1e-3);
}

// Tests turning on the spot (full turn, no forward deflection): once the casters have swung
// round, the drive-axle midpoint (O_V of the mid-drive Table I chair) stays put to a millimetre
// over a whole turn while the chair turns at ω_max (the casters' swing moves it by 2 cm at most).
TEST(FullChairTest, TurnsOnTheSpot) {
  Rig rig;
  FullChairSimulator sim(rig.chair, rig.layout, rig.floor, rig.load, 1e-3);
  sim.Start({});
  Hold(sim, {0.0, 1.0}, 3.0);
  const FullChairSample swung = sim.sample();
  EXPECT_LT(std::hypot(swung.planar.x, swung.planar.y), 0.02);
  Hold(sim, {0.0, 1.0}, 6.0);
  const FullChairSample& s = sim.sample();
  EXPECT_LT(std::hypot(s.planar.x - swung.planar.x, s.planar.y - swung.planar.y), 1e-3);
  EXPECT_NEAR(s.planar.yaw_rate, rig.layout.controller.max_turn_rate, 0.005 * rig.layout.controller.max_turn_rate);
  EXPECT_GT(s.planar.yaw - swung.planar.yaw, 2.0 * kPi);  // more than a whole turn
}

// Tests the kinematic caster law: rolling a distance s forward, tan(δ/2) = tan(δ0/2) e^(-s/t)
// (from δ' = -sin δ / t in distance; solved by separation of variables). A stiff tyre and a
// light, frictionless fork follow it to 0.01 rad from δ0 = 170°.
TEST(FullChairTest, CasterFollowsTheKinematicLawInItsLimit) {
  CasterParams params;
  params.swivel_inertia = 1e-6;
  params.swivel_damping = 0.0;
  params.swivel_friction = 0.0;
  params.scrub_per_load = 0.0;
  params.lateral_damping = 1e5;
  CasterState state{170.0 * kPi / 180.0, 0.0};
  const double v = 0.8, dt = 1e-4;
  double worst = 0.0;
  for (int k = 1; k <= 5000; ++k) {
    StepCaster(params, state, 0.4, 0.25, v, 0.0, 0.0, 400.0, dt);
    const double s = v * k * dt;
    const double expected = 2.0 * std::atan(std::tan(85.0 * kPi / 180.0) * std::exp(-s / params.trail));
    worst = std::max(worst, std::abs(state.angle - expected));
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(std::abs(state.angle), 0.01);  // 8 trails travelled: tan(85°) e^-8 ≈ 0.004
}

// Tests caster realignment on the chair after reversing: the casters swing round (|δ| near π)
// while reversing, and driving forward again tan(δ/2) falls by e over about one trail of travel
// (time constant t/v; within 25 % with the default friction and inertia).
TEST(FullChairTest, CastersRealignAfterReversingWithTimeConstantTrailOverSpeed) {
  Rig rig;
  FullChairSimulator sim(rig.chair, rig.layout, rig.floor, rig.load, 1e-3);
  sim.Start({}, 0.05);
  Hold(sim, {-0.8, 0.0}, 3.0);
  EXPECT_GT(std::abs(sim.sample().casters[0].angle), 170.0 * kPi / 180.0);
  Hold(sim, {0.0, 0.0}, 2.0);
  // forward: measure travel between tan(δ/2) = 10 and 10/e on the front-left caster
  double s_start = NAN, s_end = NAN;
  for (int k = 0; k < 8000 && std::isnan(s_end); ++k) {
    const FullChairSample& s = sim.Advance({0.6, 0.0});
    const double q = std::abs(std::tan(0.5 * s.casters[0].angle));
    if (std::isnan(s_start) && q < 10.0) s_start = s.drive.x;
    if (!std::isnan(s_start) && q < 10.0 / std::exp(1.0)) s_end = s.drive.x;
  }
  ASSERT_FALSE(std::isnan(s_end));
  EXPECT_NEAR(s_end - s_start, rig.layout.caster.trail, 0.25 * rig.layout.caster.trail);
  Hold(sim, {0.6, 0.0}, 2.0);
  EXPECT_LT(std::abs(sim.sample().casters[0].angle), 0.05);  // within the swivel friction's dead band
}

/// A 4-wheel rear-drive chair: casters at x = 0.30, drive wheels at x = -0.15.
Chair FourWheelChair() {
  Chair chair;
  chair.name = "pw4_rear";
  chair.mass = 60.0;
  chair.inertia = 8.0;
  chair.cm_height = 0.5;
  chair.wheels = {{"front_caster", 0.30, 0.1}, {"drive", -0.15, 0.17}};
  chair.gm = GeometricParams{{0.3, 0.7}, {{0, 1, 1.0}}};
  chair.lm = LumpedParams{};
  return chair;
}

// Tests the pull of a rear-drive chair started with its casters across. Independent argument:
// a caster that must swivel against its friction T_f is held by a drag T_f/t at its contact,
// and the contact of a caster pointing left (δ = +90°) lies t to the right of its pivot; both
// drags act backward right of the centre line, a yaw moment M_z = -Σ y F_x = -2 T_f < 0: the
// chair pulls right. Casters pointing right pull it left by the same amount (mirror), and toe-in
// casters (left +90°, right -90° is not a start the chair offers, so: straight casters) do not
// pull at all.
TEST(FullChairTest, RearDriveChairStartedWithCastersAcrossPullsTowardThem) {
  const Chair chair = FourWheelChair();
  PlanarLayout layout = DefaultPlanarLayout(chair);
  EXPECT_EQ(layout.layout, DriveLayout::kRear);
  const FloorMap floor;
  const auto heading_after = [&](double caster_angle) {
    FullChairSimulator sim(chair, layout, floor, 80.0, 1e-3);
    sim.Start({}, caster_angle);
    Hold(sim, {0.8, 0.0}, 2.0);
    return sim.sample().planar.yaw;
  };
  const double left = heading_after(kPi / 2.0);
  const double right = heading_after(-kPi / 2.0);
  const double straight = heading_after(0.0);
  EXPECT_GT(left, 1e-3);
  EXPECT_LT(right, -1e-3);
  EXPECT_NEAR(left, -right, 1e-9 * std::abs(left));
  EXPECT_NEAR(straight, 0.0, 1e-12);
}

// Tests static roll on a cross-slope z = g_y y: the geometric roll is φ_GM = Σγ_i asin(g_y)
// (each row's contacts 2 h_i apart rise 2 h_i g_y), and the lumped roll axis settles where its
// spring holds the load's gravity moment, K_φ (φ - φ_GM) = M g d sin φ (solved here by Newton).
TEST(FullChairTest, StaticRollOnACrossSlope) {
  Rig rig;
  const double grade = 0.06;
  rig.floor.features = {PlaneFeature(1.0, 20.0, -3.0, 3.0, 0.0, grade, 1.0)};
  RollTorqueParams roll;
  const double mass = rig.chair.mass + rig.load;
  roll.gravity_lever = mass * rig.chair.cm_height;
  FullChairSimulator sim(rig.chair, rig.layout, rig.floor, rig.load, 1e-3, {}, roll);
  sim.Start({});
  Hold(sim, {0.6, 0.0}, 6.0);
  Hold(sim, {0.0, 0.0}, 4.0);
  const FullChairSample& s = sim.sample();
  ASSERT_GT(s.planar.x, 4.0);
  ASSERT_LT(s.planar.x, 10.0);
  EXPECT_NEAR(s.planar.v, 0.0, 1e-6);
  double gamma = 0.0;
  for (const WheelRow& row : rig.layout.rows) gamma += row.roll_weight;
  const double roll_gm = gamma * std::asin(grade);
  EXPECT_NEAR(s.roll_gm, roll_gm, 1e-6);  // casters a hair off straight move their contacts
  const double k = rig.layout.k_roll, lever = mass * rig.chair.cm_height;
  double phi = roll_gm;
  for (int i = 0; i < 50; ++i) phi -= (k * (phi - roll_gm) - lever * kG * std::sin(phi)) / (k - lever * kG * std::cos(phi));
  EXPECT_NEAR(s.roll, phi, 1e-6);
  EXPECT_GT(phi - roll_gm, 1e-3);  // the gravity moment is visible
  EXPECT_NEAR(s.planar.yaw, 0.0, 0.01);  // the downhill wheel's rolling resistance: a slight drift
}

// Tests load transfer under braking on a two-row chair: moments about the rear contact line
// give N_front = M (g (x_c - x_r) - a_x h) / L with L = x_f - x_r, h = d_CM, a_x < 0 braking.
TEST(FullChairTest, LoadTransferUnderBraking) {
  const Chair chair = FourWheelChair();
  const PlanarLayout layout = DefaultPlanarLayout(chair);
  const FloorMap floor;
  FullChairSimulator sim(chair, layout, floor, 80.0, 1e-3);
  sim.Start({});
  Hold(sim, {1.0, 0.0}, 3.0);
  const FullChairSample cruise = sim.sample();
  std::vector<FullChairSample> stop = Hold(sim, {0.0, 0.0}, 0.5);
  const FullChairSample& s = stop.back();
  ASSERT_LT(s.a_x, -0.8);
  const double mass = chair.mass + 80.0;
  const double length = chair.wheels[0].x - chair.wheels[1].x;
  const double x_c = layout.cm_x, x_r = chair.wheels[1].x, h = chair.cm_height;
  const double front = mass * (kG * (x_c - x_r) - s.a_x * h) / length;
  EXPECT_NEAR(s.contacts[0].load + s.contacts[1].load, front, 1e-9 * front);
  EXPECT_GT(s.contacts[0].load + s.contacts[1].load,
            cruise.contacts[0].load + cruise.contacts[1].load + 0.8 * mass * h / length);
  const double total = s.contacts[0].load + s.contacts[1].load + s.contacts[2].load + s.contacts[3].load;
  EXPECT_NEAR(total, mass * kG, 1e-9 * total);
}

// Tests the tip-over slope: facing up a slope of grade G (tan of its angle) the weight's line
// of action meets the floor h G behind the centre of mass; the chair tips back when that point
// passes the rearmost contact, G* = (x_c - x_r) / h, or with anti-tip wheels at x_a,
// G** = (x_c - x_a) / h. Below it no wheel lifts; just above, the front wheels report lift-off.
TEST(FullChairTest, TipOverSlopeMatchesItsGeometricClosedForm) {
  const Chair chair = FourWheelChair();
  PlanarLayout layout = DefaultPlanarLayout(chair);
  const double h = chair.cm_height;
  layout.rolling_envelope = false;  // the closed form is of contacts at the wheels' lowest points
  const double critical = (layout.cm_x - chair.wheels[1].x) / h;
  const auto state_on = [&](double grade, const PlanarLayout& l) {
    FloorMap floor;
    floor.features = {PlaneFeature(-5.0, 5.0, -5.0, 5.0, grade, 0.0, 0.0)};
    FullChairSimulator sim(chair, l, floor, 80.0, 1e-3);
    return sim.Start({});  // at rest: the static loads
  };
  const FullChairSample below = state_on(critical - 0.01, layout);
  const FullChairSample above = state_on(critical + 0.01, layout);
  EXPECT_FALSE(below.tip_over);
  EXPECT_EQ(below.lift_off_count, 0);
  EXPECT_TRUE(above.tip_over);
  EXPECT_TRUE(above.contacts[0].lift_off);
  EXPECT_TRUE(above.contacts[1].lift_off);
  EXPECT_LT(above.contacts[0].load, 0.0);  // reported, not clipped

  layout.anti_tip = {true, -0.45, 0.2, 0.05};
  const double critical_anti_tip = (layout.cm_x - layout.anti_tip.x) / h;
  const FullChairSample held = state_on(critical + 0.01, layout);
  EXPECT_FALSE(held.tip_over);
  EXPECT_TRUE(held.on_anti_tip);
  EXPECT_FALSE(state_on(critical_anti_tip - 0.01, layout).tip_over);
  EXPECT_TRUE(state_on(critical_anti_tip + 0.01, layout).tip_over);
}

// Tests a bump under the left wheels only: the chair rolls left side up (φ_GM > 0) while
// crossing, then returns level; the right contacts stay on the floor (z = 0).
TEST(FullChairTest, BumpUnderOneSideRollsTheChair) {
  Rig rig;
  // plateau 2.1-2.2: only one row on it at a time (rows 0.38 m apart)
  rig.floor.features = {BumpFeature(2.0, 2.3, 0.1, 1.0, 0.04, 0.1)};
  rig.layout.rolling_envelope = false;  // the closed form is of point contacts (the tyres overshoot it)
  FullChairSimulator sim(rig.chair, rig.layout, rig.floor, rig.load, 1e-3);
  sim.Start({});
  double max_roll_gm = 0.0, max_right_z = 0.0, max_roll = 0.0;
  for (const FullChairSample& s : Hold(sim, {0.5, 0.0}, 8.0)) {
    max_roll_gm = std::max(max_roll_gm, s.roll_gm);
    max_roll = std::max(max_roll, s.roll);
    for (int i = 0; i < 3; ++i) max_right_z = std::max(max_right_z, std::abs(s.contacts[2 * i + 1].z));
  }
  EXPECT_NEAR(max_roll_gm, 0.66 * std::asin(0.04 / 0.56), 1e-9);  // the drive row on the plateau
  EXPECT_GT(max_roll, 0.5 * max_roll_gm);
  EXPECT_EQ(max_right_z, 0.0);
  EXPECT_LT(std::abs(sim.sample().roll), 1e-4);
}

}  // namespace
}  // namespace pwsim

namespace pwsim {
namespace {

// Tests rear, mid and front drive on the 6-wheel chair (the drive row chosen by the layout):
// in a steady turn the drive-axle midpoint D runs on a circle of radius v/ω (circumradius
// abc / (4 area) of three of its positions, 1.5 s apart, to 0.5 %), and held straight the chair
// keeps its heading exactly (a left-right symmetric chair).
TEST(FullChairTest, RearMidAndFrontDriveTurnOnCirclesOfRadiusSpeedOverYawRate) {
  const Chair chair = MakeTableOneChair();
  const FloorMap floor;
  for (const char* drive : {"rear", "mid", "front"}) {
    const YamlDocument doc = LoadYamlString(std::string("{drive: ") + drive + "}", "layout.yaml");
    YamlMap map(doc.root, doc.file, "");
    const PlanarLayout layout = ParsePlanarLayout(map, chair);
    map.Finish();
    FullChairSimulator sim(chair, layout, floor, 100.0, 1e-3);
    sim.Start({});
    Hold(sim, {0.6, 0.0}, 5.0);
    EXPECT_EQ(sim.sample().planar.yaw, 0.0) << drive;
    EXPECT_EQ(sim.sample().planar.y, 0.0) << drive;
    Hold(sim, {0.6, 0.5}, 12.0);
    std::array<std::array<double, 2>, 3> d{};
    for (auto& point : d) {
      Hold(sim, {0.6, 0.5}, 1.5);
      const PlanarState& p = sim.sample().planar;
      point = {p.x + std::cos(p.yaw) * sim.drive_x(), p.y + std::sin(p.yaw) * sim.drive_x()};
    }
    const double a = std::hypot(d[1][0] - d[0][0], d[1][1] - d[0][1]);
    const double b = std::hypot(d[2][0] - d[1][0], d[2][1] - d[1][1]);
    const double c = std::hypot(d[2][0] - d[0][0], d[2][1] - d[0][1]);
    const double area = 0.5 * std::abs((d[1][0] - d[0][0]) * (d[2][1] - d[0][1]) - (d[2][0] - d[0][0]) * (d[1][1] - d[0][1]));
    const double radius = a * b * c / (4.0 * area);
    const PlanarState& p = sim.sample().planar;
    EXPECT_NEAR(radius, p.v / p.yaw_rate, 0.005 * radius) << drive;
  }
}

// Tests that Advance (which keeps the controller's targets while the deflection stays) is the
// controller's StepController followed by AdvanceSetpoints, bit for bit, through deflections
// that hold, change, repeat, and are NaN or out of range (read as 0).
TEST(FullChairTest, AdvanceIsTheControllerStepThenTheSetpoints) {
  Rig rig;
  rig.floor.features = {PlaneFeature(1.0, 6.0, -3.0, 3.0, 0.0, 0.04, 0.5)};
  FullChairSimulator held(rig.chair, rig.layout, rig.floor, rig.load, 1e-3);
  FullChairSimulator stepped(rig.chair, rig.layout, rig.floor, rig.load, 1e-3);
  held.Start({});
  stepped.Start({});
  const std::array<JoystickInput, 6> deflections{
      {{0.8, 0.0}, {0.8, 0.5}, {std::nan(""), 0.5}, {0.8, 0.5}, {-0.6, 1.5}, {0.0, 0.0}}};
  for (int k = 0; k < 12000; ++k) {
    const JoystickInput joystick = deflections[(k / 700) % deflections.size()];
    const FullChairSample& a = held.Advance(joystick);
    const ControllerState set = StepController(rig.layout.controller, stepped.sample().controller, joystick, 1e-3);
    const FullChairSample& b = stepped.AdvanceSetpoints(set);
    ASSERT_EQ(a.controller, b.controller) << k;
    ASSERT_EQ(a.planar, b.planar) << k;
    ASSERT_EQ(a.roll, b.roll) << k;
  }
  EXPECT_GT(std::abs(held.sample().planar.yaw), 0.5);  // it really turned
}

}  // namespace
}  // namespace pwsim
