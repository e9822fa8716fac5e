// Wheels over the floor (engine/floor_map.h EnvelopeAt, engine/full_chair.h tyres) against
// closed forms written here: the wheel-centre arc round a step's edge, a gap narrower than the
// wheel, a slope, the climb's duration at speed v, and the fall and landing off a ledge.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <vector>

#include "engine/circuit.h"
#include "engine/floor_map.h"
#include "engine/full_chair.h"
#include "engine/scene.h"

namespace pwsim {
namespace {

constexpr double kG = 9.80665;

/// z_env by the floor map, its hint set by the point lookup first (as the chair does).
double Envelope(const FloorMap& floor, double x, double y, double heading, double radius) {
  FloorHint hint;
  const double point = floor.HeightAtNear(x, y, hint);
  return floor.EnvelopeAt(x, y, std::cos(heading), std::sin(heading), radius, point, hint);
}

/// The centre of a wheel of radius R, less R, before a step of height h at x_e (closed form):
/// on the floor until it touches the edge, then the arc h + √(R² − d²) − R, d = x_e − x.
double StepArc(double x, double x_e, double h, double radius) {
  const double d = x_e - x;
  if (d >= radius) return 0.0;
  if (d <= 0.0) return h;
  return std::max(0.0, h + std::sqrt(radius * radius - d * d) - radius);
}

// Tests the envelope before a sharp step (h = 5 cm, R = 0.1 and 0.17 m), taken square and at
// 30 deg (the distance to the edge in the wheel's plane is then d / cos 30°), and off its far
// edge (the mirror image): the closed-form arc to 1e-9 m, every millimetre.
TEST(WheelEnvelopeTest, CentreRidesTheArcRoundAStepsEdge) {
  const double h = 0.05;
  FloorMap floor;
  floor.features = {BumpFeature(1.0, 3.0, -5.0, 5.0, h, 0.0)};
  for (const double radius : {0.10, 0.17}) {
    for (int k = 0; k <= 400; ++k) {
      const double x = 0.8 + 0.001 * k;
      EXPECT_NEAR(Envelope(floor, x, 0.0, 0.0, radius), StepArc(x, 1.0, h, radius), 1e-9) << "R " << radius << " x " << x;
      const double angle = std::numbers::pi / 6.0;
      const double oblique = StepArc(1.0 - (1.0 - x) / std::cos(angle), 1.0, h, radius);
      EXPECT_NEAR(Envelope(floor, x, 0.0, angle, radius), oblique, 1e-9) << "30 deg, x " << x;
      const double mirrored = 4.0 - x;  // the far edge at 3.0, driven either way
      EXPECT_NEAR(Envelope(floor, mirrored, 0.0, 0.0, radius), StepArc(x, 1.0, h, radius), 1e-9);
      EXPECT_NEAR(Envelope(floor, mirrored, 0.0, std::numbers::pi, radius), StepArc(x, 1.0, h, radius), 1e-9);
    }
  }
  // where the whole disc is on level floor, the point height itself, exactly
  EXPECT_EQ(Envelope(floor, 0.5, 0.0, 0.0, 0.1), 0.0);
  EXPECT_EQ(Envelope(floor, 2.0, 0.0, 0.0, 0.1), h);
}

// Tests a gap (a dip 5 cm deep): a wheel of R = 0.1 over a gap 10 cm wide sinks only
// R − √(R² − w²/4) = 13.4 mm at its middle; over a gap 30 cm wide (> 2R) it reaches the bottom;
// on a slope m along its heading the centre stands R √(1 + m²) above the plane at its x.
TEST(WheelEnvelopeTest, GapNarrowerThanTheWheelAndSlope) {
  const double radius = 0.1, depth = 0.05;
  FloorMap narrow;
  narrow.features = {BumpFeature(1.0, 1.1, -5.0, 5.0, -depth, 0.0)};
  const double sink = radius - std::sqrt(radius * radius - 0.05 * 0.05);
  EXPECT_NEAR(Envelope(narrow, 1.05, 0.0, 0.0, radius), -sink, 1e-9);
  EXPECT_NEAR(Envelope(narrow, 1.05, 0.0, 0.0, 0.0), -depth, 0.0);  // a point falls in
  double deepest = 0.0;
  for (int k = 0; k <= 300; ++k) deepest = std::min(deepest, Envelope(narrow, 0.9 + 0.001 * k, 0.0, 0.0, radius));
  EXPECT_NEAR(deepest, -sink, 1e-9);
  FloorMap wide;
  wide.features = {BumpFeature(1.0, 1.3, -5.0, 5.0, -depth, 0.0)};
  EXPECT_NEAR(Envelope(wide, 1.15, 0.0, 0.0, radius), -depth, 1e-12);

  FloorMap slope;
  const double m = 0.1;
  slope.features = {PlaneFeature(-5.0, 5.0, -5.0, 5.0, m, 0.0, 0.0)};  // z = m x about x = 0
  EXPECT_NEAR(Envelope(slope, 0.3, 0.0, 0.0, radius), m * 0.3 + radius * (std::sqrt(1.0 + m * m) - 1.0), 1e-12);
  // across the slope (heading along y) the wheel's plane is level: the point height
  EXPECT_NEAR(Envelope(slope, 0.3, 0.0, std::numbers::pi / 2, radius), m * 0.3, 1e-12);
}

// Tests the envelope over a piecewise-linear profile (the speed cushion, alone and beside a
// bump it does not reach) and over a cross-slope's tapered edge, headed along x, at 40 deg and
// back, against a brute-force maximum of z(p + s u) + √(R² − s²) over s sampled every 10 µm.
TEST(WheelEnvelopeTest, ProfileAndTapersAgainstBruteForce) {
  FloorMap cushion;
  cushion.profile = MakeSpeedCushion();
  FloorMap beside = cushion;
  beside.features = {BumpFeature(1.0, 5.0, 3.0, 4.0, 0.05, 0.0)};
  FloorMap taper;
  taper.features = {PlaneFeature(1.0, 4.0, -2.0, 2.0, 0.0, 0.05, 1.0)};
  for (const FloorMap* floor : {&cushion, &beside, &taper}) {
    for (const double heading : {0.0, 0.7, std::numbers::pi}) {
      const double ux = std::cos(heading), uy = std::sin(heading), radius = 0.17;
      for (double x = 1.5; x < 4.3; x += 0.0371) {
        const double y = floor == &taper ? 1.6 : 0.0;
        double truth = -1.0;
        for (int k = -17000; k <= 17000; ++k) {
          const double s = 1e-5 * k;
          truth = std::max(truth, floor->HeightAt(x + s * ux, y + s * uy) + std::sqrt(radius * radius - s * s) - radius);
        }
        // the taper's plane is a quadratic along an oblique line, taken by its chord: within
        // κ (2R)² / 8, κ = 2 |g_y u_x u_y| / ramp (< 1 mm here); the profile is exact
        ASSERT_NEAR(Envelope(*floor, x, y, heading, radius), truth, floor == &taper ? 1e-3 : 5e-6) << x << " " << heading;
      }
    }
  }
}

/// The Table I chair driven straight at `speed` by its set-points (no controller ramp).
struct StraightRig {
  Chair chair = MakeTableOneChair();
  PlanarLayout layout = DefaultPlanarLayout(chair);
  FloorMap floor;
};

ControllerState Cruise(double speed) { return {speed, 0.0, 0.0, 0.0}; }

// Tests the climb of a 5 cm kerb (sharp edge across the whole path) at 0.6 m/s: the front-left
// caster's envelope rises over √(2Rh − h²) / v (R = 0.1 m: 0.144 s), along the arc as a
// function of its contact's x (1e-6 m); the height the GM reads through the tyre rises without
// a jump (its largest step per tick below 2 mm) and settles on the kerb.
TEST(WheelEnvelopeTest, ClimbTakesRootTwoRhOverSpeed) {
  StraightRig rig;
  const double h = 0.05, edge = 2.5, speed = 0.6;
  rig.floor.features = {BumpFeature(edge, 8.0, -5.0, 5.0, h, 0.0)};
  FullChairSimulator sim(rig.chair, rig.layout, rig.floor, 100.0, 1e-3);
  sim.Start({});
  for (int k = 0; k < 3000; ++k) sim.AdvanceSetpoints(Cruise(speed));  // up to speed, 0.3 m before
  const double radius = rig.chair.wheels[0].radius;
  int climbing = 0;
  double v_sum = 0.0, largest_step = 0.0, previous_z = sim.sample().contacts[0].z;
  for (int k = 0; k < 1500; ++k) {
    const FullChairSample& s = sim.AdvanceSetpoints(Cruise(speed));
    const WheelContact& c = s.contacts[0];
    if (c.floor_z > 1e-12 && c.floor_z < h - 1e-12) {
      ++climbing;
      v_sum += s.planar.v;
      EXPECT_NEAR(c.floor_z, StepArc(c.x, edge, h, radius), 1e-6);
    }
    largest_step = std::max(largest_step, std::abs(c.z - previous_z));
    previous_z = c.z;
  }
  ASSERT_GT(climbing, 0);
  const double v = v_sum / climbing;
  EXPECT_NEAR(v, speed, 0.1 * speed);  // the kerb pitches the chair nose-up: it slows a little
  EXPECT_NEAR(climbing * sim.dt(), std::sqrt(2.0 * radius * h - h * h) / v, 2e-3);
  EXPECT_LT(largest_step, 2e-3);
  EXPECT_NEAR(sim.sample().contacts[0].z, h, 1e-6);
}

// Tests the fall off a 5 cm ledge at 1.5 m/s (above √(g R): the caster leaves the edge): the
// front-left wheel is airborne, then lands after the free fall of its height less the tyre's
// static deflection δ_s = g / ω_t², t = √(2 (Δz − δ_s) / g) (to 10 %: the tyre extends over a few
// ms first); in flight it falls at g exactly; after it lands it settles on the floor.
TEST(WheelEnvelopeTest, LedgeDropLandsAfterFreeFall) {
  StraightRig rig;
  const double drop = 0.05, edge = 1.0, speed = 1.5;
  rig.floor.features = {BumpFeature(-5.0, edge, -5.0, 5.0, drop, 0.0)};
  FullChairSimulator sim(rig.chair, rig.layout, rig.floor, 100.0, 1e-3);
  sim.Start({-1.5, 0.0, 0.0, 0.0, 0.0});  // at rest on the ledge
  double t = 0.0, leave = NAN, land = NAN, previous_rate = NAN, previous_z = drop;
  bool free_fall_at_g = true;
  int flights = 0;
  for (int k = 0; k < 4000 && std::isnan(land); ++k) {
    const FullChairSample& s = sim.AdvanceSetpoints(Cruise(speed));
    t += sim.dt();
    const WheelContact& c = s.contacts[0];
    const double rate = (c.z - previous_z) / sim.dt();
    if (std::isnan(leave) && c.x > edge) leave = t - (c.x - edge) / s.planar.v;  // the edge passed
    if (c.airborne && !std::isnan(previous_rate)) {
      free_fall_at_g = free_fall_at_g && std::abs((rate - previous_rate) / sim.dt() + kG) < 1e-6;
      if (flights == 0) ++flights;
    }
    if (flights > 0 && !c.airborne && c.z < drop / 2) land = t;
    previous_rate = c.airborne ? rate : NAN;
    previous_z = c.z;
  }
  ASSERT_FALSE(std::isnan(leave));
  ASSERT_FALSE(std::isnan(land));
  EXPECT_TRUE(free_fall_at_g);
  const double omega = 2.0 * std::numbers::pi / rig.layout.caster_tyre_period;
  const double expected = std::sqrt(2.0 * (drop - kG / (omega * omega)) / kG);
  EXPECT_NEAR(land - leave, expected, 0.1 * expected);
  for (int k = 0; k < 1000; ++k) sim.AdvanceSetpoints(Cruise(speed));
  EXPECT_NEAR(sim.sample().contacts[0].z, 0.0, 1e-6);
  EXPECT_FALSE(sim.sample().contacts[0].airborne);
}

// Tests that a chair at rest on level floor keeps its contacts at the floor's bits, and that
// without the envelope (rolling_envelope false) a wheel over the gap falls to its bottom.
TEST(WheelEnvelopeTest, LevelRestIsExactAndPointContactsFallIn) {
  StraightRig rig;
  FullChairSimulator rest(rig.chair, rig.layout, rig.floor, 100.0, 1e-3);
  rest.Start({});
  for (int k = 0; k < 500; ++k) rest.AdvanceSetpoints({});
  for (int c = 0; c < rest.sample().contact_count; ++c) EXPECT_EQ(rest.sample().contacts[c].z, 0.0);

  rig.floor.features = {BumpFeature(1.0, 1.1, -5.0, 5.0, -0.05, 0.0)};
  const auto deepest = [&](bool envelope) {
    PlanarLayout layout = rig.layout;
    layout.rolling_envelope = envelope;
    FullChairSimulator sim(rig.chair, layout, rig.floor, 100.0, 1e-3);
    sim.Start({});
    double low = 0.0;
    for (int k = 0; k < 3000; ++k) low = std::min(low, sim.AdvanceSetpoints(Cruise(0.5)).contacts[0].floor_z);
    return low;
  };
  EXPECT_NEAR(deepest(false), -0.05, 1e-12);
  // the envelope's V at the gap's middle (slope ±tan 30°) is sampled every v dt = 0.5 mm
  EXPECT_NEAR(deepest(true), -(0.1 - std::sqrt(0.1 * 0.1 - 0.05 * 0.05)), 0.6 * 0.5e-3);
}

/// A straight wall along y at x = 3 m, the chair driven at `heading` [rad] from the origin at a
/// constant deflection forward; returns its samples.
std::vector<FullChairSample> IntoAWall(double heading, double wall_friction, CircuitSpec& circuit) {
  const Chair chair = MakeTableOneChair();
  circuit.layout = DefaultPlanarLayout(chair);
  circuit.walls = {Wall{{3.0, -20.0}, {3.0, 20.0}, 0.1, "wall"}};
  circuit.start = {0.0, 0.0, heading, 0.0, 0.0};
  circuit.wall_friction = wall_friction;
  circuit.joystick.kind = JoystickSource::Kind::kTable;
  circuit.joystick.t = {0.0};
  circuit.joystick.forward = {0.6};
  circuit.joystick.turn = {0.0};
  CircuitRunner runner(chair, circuit, 100.0, 1e-3);
  std::vector<FullChairSample> run{runner.Start()};
  for (int k = 1; k <= 8000; ++k) run.push_back(runner.Advance(k * 1e-3));
  return run;
}

// Tests the wall's Coulomb friction (engine/circuit.h, Contacts) against its closed form: a
// chair driven into a wall at incidence α (from the wall's normal) keeps, on the tick it meets
// the wall, the speed along it |u_t| − μ_w |u_n| = v (sin α − μ_w cos α) (to 0.2 % of v dt); it
// slides on along the wall when tan α > μ_w (α with tan α = 1.5 and 3 μ_w), pushed on at its
// speed v at v (sin α − μ_w cos α) (to 0.1 %), and stops when tan α < μ_w (tan α = 0.6 μ_w: v = 0
// and it moves along the wall no more than the free ticks that close the last gap, v dt).
TEST(WallFrictionTest, SlidesWhenTanIncidenceExceedsFriction) {
  const double mu = 0.4, dt = 1e-3;
  for (const double ratio : {1.5, 0.6, 3.0}) {
    const double alpha = std::atan(ratio * mu);
    CircuitSpec circuit;
    const std::vector<FullChairSample> run = IntoAWall(alpha, mu, circuit);
    std::size_t first = 0;
    for (std::size_t k = 1; k < run.size() && first == 0; ++k) {
      if (run[k].contact_events > 0) first = k;
    }
    ASSERT_GT(first, 1u) << ratio;
    // the velocity it came with: its last free tick's
    const double ux = (run[first - 1].planar.x - run[first - 2].planar.x) / dt;
    const double uy = (run[first - 1].planar.y - run[first - 2].planar.y) / dt;
    const double v = std::hypot(ux, uy);
    const double expected = std::max(0.0, v * (std::sin(alpha) - mu * std::cos(alpha)));
    EXPECT_NEAR((run[first].planar.y - run[first - 1].planar.y) / dt, expected, 2e-3 * v) << ratio;
    EXPECT_NEAR(run[first].last_contact_speed, v * std::cos(alpha), 2e-3 * v) << ratio;
    const double along = run.back().planar.y - run[first].planar.y;
    if (ratio > 1.0) {
      // pushed on at v, it slides at v (sin α − μ_w cos α) (over the last second)
      const FullChairSample& end = run.back();
      const FullChairSample& second_before = run[run.size() - 1001];
      ASSERT_TRUE(second_before.in_contact) << ratio;
      const double slide = (end.planar.y - second_before.planar.y) / 1.0;
      EXPECT_NEAR(slide, end.planar.v * (std::sin(alpha) - mu * std::cos(alpha)), 1e-3 * end.planar.v) << ratio;
      EXPECT_GT(along, 0.05) << ratio;
    } else {
      EXPECT_LT(along, v * dt) << ratio;  // at most the last gap's closing, free ticks at the heading
      EXPECT_EQ(run.back().planar.v, 0.0) << ratio;
    }
    EXPECT_EQ(run.back().contact_events, 1) << ratio;  // one contact, however long
    for (const FullChairSample& s : run) ASSERT_LT(s.planar.x, 3.0) << ratio;
  }
}

/// Sum of the loads of the drive wheels and of the others [N].
void DriveAndOtherLoads(const FullChairSimulator& sim, double& drive, double& others) {
  drive = others = 0.0;
  for (int c = 0; c < 2 * sim.wheel_count(); ++c) {
    const bool driven = sim.layout().rows[static_cast<std::size_t>(c / 2)].role == WheelRole::kDrive;
    (driven ? drive : others) += sim.sample().contacts[c].load;
  }
}

// Tests the drive wheels' grip on a slope with the brakes on (a slippery patch, μ = 0.2): the
// chair holds while the slope asks less than μ N_drive, M g sin θ <= μ N_drive (slip onset at
// tan θ* = μ κ, κ the drive wheels' share of the weight), and slides otherwise with
// a = (M g sin θ − μ N_drive − f_c N_others) / M (to 1 % of g sin θ; f_c the casters' rolling
// resistance).
TEST(SlipTest, ParkedChairSlipsWhenTheSlopeAsksMoreThanItsGrip) {
  const Chair chair = MakeTableOneChair();
  const PlanarLayout layout = DefaultPlanarLayout(chair);
  const double mu = 0.2;
  int held = 0, slid = 0;
  for (const double grade : {0.06, 0.1, 0.12, 0.14, 0.16, 0.2}) {
    FloorMap floor;
    floor.features = {PlaneFeature(-20.0, 20.0, -20.0, 20.0, grade, 0.0, 0.0)};
    floor.patches = {FrictionPatch{"wet", -20.0, 20.0, -20.0, 20.0, mu}};
    FullChairSimulator sim(chair, layout, floor, 100.0, 1e-3);
    sim.Start({});
    const double sine = grade / std::sqrt(1.0 + grade * grade);
    const double demand = sim.mass() * kG * sine;
    double drive = 0.0, others = 0.0;
    DriveAndOtherLoads(sim, drive, others);
    for (int k = 0; k < 1000; ++k) sim.AdvanceSetpoints({});
    const double moved = std::hypot(sim.sample().planar.x, sim.sample().planar.y);
    if (demand <= mu * drive) {
      ++held;
      EXPECT_LT(moved, 1e-9) << grade;
      EXPECT_FALSE(sim.sample().torque_limited) << grade;
    } else {
      ++slid;
      DriveAndOtherLoads(sim, drive, others);
      const double expected = (demand - mu * drive - layout.caster.rolling_resistance * others) / sim.mass();
      // from rest over 1 s; to 1 % of the slope's pull (the casters' rolling resistance is
      // regularised below 1 cm/s)
      EXPECT_NEAR(-sim.sample().planar.v / 1.0, expected, 0.01 * kG * sine) << grade;
      EXPECT_TRUE(sim.sample().torque_limited) << grade;
    }
  }
  EXPECT_GT(held, 0);
  EXPECT_GT(slid, 0);
}

// Tests a skid: the chair at 1.2 m/s on a slippery floor (μ = 0.15) braked at once (the
// set-points at rest) stops after v² / (2 a), a = (μ N_drive + f_c N_others) / M (v² / (2 μ g)
// when the drive wheels carry the whole weight), to 2 %.
TEST(SlipTest, SkidDistanceIsVSquaredOverTwiceTheGripDeceleration) {
  StraightRig rig;
  const double mu = 0.15;
  rig.floor.patches = {FrictionPatch{"wet", -50.0, 50.0, -50.0, 50.0, mu}};
  FullChairSimulator sim(rig.chair, rig.layout, rig.floor, 100.0, 1e-3);
  sim.Start({});
  for (int k = 0; k < 4000; ++k) sim.AdvanceSetpoints(Cruise(1.2));
  const double v0 = sim.sample().planar.v, x0 = sim.sample().planar.x;
  sim.AdvanceSetpoints({});
  double drive = 0.0, others = 0.0;
  DriveAndOtherLoads(sim, drive, others);  // under the skid's deceleration
  const double a = (mu * drive + rig.layout.caster.rolling_resistance * others) / sim.mass();
  for (int k = 0; k < 5000 && sim.sample().planar.v > 0.0; ++k) sim.AdvanceSetpoints({});
  EXPECT_EQ(sim.sample().planar.v, 0.0);
  EXPECT_NEAR(sim.sample().planar.x - x0, v0 * v0 / (2.0 * a), 0.02 * v0 * v0 / (2.0 * a));
  EXPECT_LT(a, mu * kG);  // the casters carry part of the weight: longer than v² / (2 μ g)
}

using Vec3 = std::array<double, 3>;

/// The head's position in W of a sample: p = (x, y, Z_M) + Rz(ψ) Ry(−θ_M) Rx(φ_M) p_VH.
Vec3 HeadPosition(const FullChairSample& s, const Vec3& r) {
  const double cr = std::cos(s.roll), sr = std::sin(s.roll);
  const double cp = std::cos(-s.lm.pitch), sp = std::sin(-s.lm.pitch);
  const double cy = std::cos(s.planar.yaw), sy = std::sin(s.planar.yaw);
  const Vec3 a{r[0], cr * r[1] - sr * r[2], sr * r[1] + cr * r[2]};   // Rx
  const Vec3 b{cp * a[0] + sp * a[2], a[1], -sp * a[0] + cp * a[2]};  // Ry
  return {s.planar.x + cy * b[0] - sy * b[1], s.planar.y + sy * b[0] + cy * b[1], s.lm.z + b[2]};
}

/// |f_H − (0, 0, g)| at sample k by central differences: f_H = Rᵀ (p̈ + g e_z), so
/// |f_H − g e_z| = |p̈ + g e_z − R g e_z| (a rotation keeps lengths).
double HeadForceDeviation(const std::vector<FullChairSample>& run, std::size_t k, const Vec3& r, double dt) {
  const Vec3 a = HeadPosition(run[k - 1], r), b = HeadPosition(run[k], r), c = HeadPosition(run[k + 1], r);
  const FullChairSample& s = run[k];
  // R e_z: the third column of Rz(ψ) Ry(−θ) Rx(φ)
  const double cr = std::cos(s.roll), sr = std::sin(s.roll), cp = std::cos(-s.lm.pitch), sp = std::sin(-s.lm.pitch);
  const double cy = std::cos(s.planar.yaw), sy = std::sin(s.planar.yaw);
  const Vec3 col_b{cp * 0.0 + sp * cr, -sr, -sp * 0.0 + cp * cr};
  const Vec3 up{cy * col_b[0] - sy * col_b[1], sy * col_b[0] + cy * col_b[1], col_b[2]};
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double accel = (c[i] - 2.0 * b[i] + a[i]) / (dt * dt) + (i == 2 ? kG : 0.0);
    sum += (accel - kG * up[i]) * (accel - kG * up[i]);
  }
  return std::sqrt(sum);
}

// Tests the plausibility bound (engine/circuit.h ComputeHeadForceBound) on every shipped
// circuit: the head's specific force, by central differences of the head's position written
// here, stays within the bound computed from the run's own peak speed and yaw rate at every tick
// away from a wall contact; the bound is finite (rolling envelope) and not vacuous (below
// 100 g); with point contacts a sharp-edged floor admits no finite bound.
TEST(HeadForceBoundTest, ShippedCircuitsStayWithinTheirBound) {
  const std::filesystem::path scenes = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes";
  for (const char* name : {"circuit_course.yaml", "circuit_room.yaml", "circuit_recorded.yaml"}) {
    const Scene scene = LoadScene(scenes / name);
    const std::vector<FullChairSample> run = SimulateCircuitScene(scene);
    double peak_speed = 0.0, peak_yaw_rate = 0.0;
    for (const FullChairSample& s : run) {
      peak_speed = std::max(peak_speed, std::abs(s.planar.v));
      peak_yaw_rate = std::max(peak_yaw_rate, std::abs(s.planar.yaw_rate));
    }
    const Vec3 r = scene.occupant.head_offset;
    const HeadForceBound bound = ComputeHeadForceBound(scene.chair, *scene.circuit, scene.load_kg, scene.pitch_torque, r,
                                                       peak_speed, peak_yaw_rate);
    ASSERT_TRUE(std::isfinite(bound.total)) << name;
    EXPECT_LT(bound.total, 100.0 * kG) << name;
    double peak = 0.0;
    for (std::size_t k = 1; k + 1 < run.size(); ++k) {
      if (run[k - 1].in_contact || run[k].in_contact || run[k + 1].in_contact) continue;
      peak = std::max(peak, HeadForceDeviation(run, k, r, scene.clock.dt()));
    }
    EXPECT_LT(peak, bound.total) << name;
    EXPECT_GT(peak, 0.0) << name;
  }
  Scene course = LoadScene(scenes / "circuit_course.yaml");
  course.circuit->layout.rolling_envelope = false;
  course.circuit->floor.features.push_back(BumpFeature(30.0, 31.0, -1.0, 1.0, 0.05, 0.0));  // a sharp step
  EXPECT_TRUE(std::isinf(ComputeHeadForceBound(course.chair, *course.circuit, course.load_kg, course.pitch_torque,
                                               course.occupant.head_offset, 1.0, 1.0).total));
}

}  // namespace
}  // namespace pwsim
