#include "mca/washout.h"

#include "engine/input_error.h"
#include "mca/cue_analysis.h"
#include "tests/mca/actuator_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <limits>
#include <random>
#include <vector>

namespace pwsim::mca {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

HeadMotion Rest() { return HeadMotion{}; }

HeadMotion Surge(double a) {
  HeadMotion m;
  m.fs[0] = a;
  return m;
}

/// A smooth sagittal manoeuvre: accelerate, a bump in heave and pitch, brake.
HeadMotion Manoeuvre(double t) {
  HeadMotion m;
  m.fs[0] = 0.8 * (std::tanh(3.0 * (t - 1.0)) - std::tanh(3.0 * (t - 4.0))) * 0.5;
  m.fs[2] = kGravity + 3.0 * std::exp(-8.0 * (t - 2.5) * (t - 2.5)) * std::sin(12.0 * (t - 2.5));
  m.w[1] = -0.3 * std::exp(-4.0 * (t - 2.7) * (t - 2.7)) * std::sin(6.0 * (t - 2.7));
  m.w[0] = 0.05 * std::sin(0.7 * t);
  m.w[2] = 0.1 * std::sin(0.4 * t);
  return m;
}

// Tests that a vehicle at rest (fs = +g up, no rotation) leaves the platform exactly neutral.
TEST(WashoutTest, RestIsNeutralForever) {
  for (const PlatformSpec& platform : {MakePw4DofPlatform(), MakeCar2DofPlatform()}) {
    ClassicalWashout dut(DefaultWashoutParams(), platform, 1e-3);
    for (int k = 0; k < 20000; ++k) {
      const McaCommand& c = dut.Step(Rest());
      for (double v : c.pose) ASSERT_EQ(v, 0.0);
      ASSERT_EQ(c.tilt_pitch, 0.0);
    }
  }
}

// Tests tilt coordination for a sustained 1 m/s² surge: the tilt settles at asin(a/g), its
// rate never exceeds 3 deg/s, and the washed-out pitch is the tilt alone.
TEST(WashoutTest, SustainedSurgeTiltsToAsinAtLimitedRate) {
  for (double a : {0.5, 1.0}) {
    const double dt = 1e-3;
    ClassicalWashout dut(DefaultWashoutParams(), MakePw4DofPlatform(), dt);
    double prev_tilt = 0.0, max_rate = 0.0;
    McaCommand last;
    for (int k = 0; k < 60000; ++k) {
      last = dut.Step(Surge(a));
      max_rate = std::max(max_rate, std::abs(last.tilt_pitch - prev_tilt) / dt);
      prev_tilt = last.tilt_pitch;
    }
    EXPECT_NEAR(last.tilt_pitch, std::asin(a / kGravity), 0.1 * kDegToRad) << a;
    EXPECT_NEAR(last.pose[Index(Dof::kPitch)], last.tilt_pitch, 1e-6) << a;
    EXPECT_LE(max_rate, 3.0 * kDegToRad * (1.0 + 1e-9)) << a;
    if (a >= 1.0) {
      EXPECT_GT(max_rate, 2.9 * kDegToRad) << "the rate limit should be active";
    }
  }
}

// Tests roll tilt coordination for a sustained lateral specific force (a steady turn): the roll
// settles at asin(a_y/g) (left side up for a left turn's +y force), never turns faster than
// 3 deg/s, and the platform then delivers the turn's lateral specific force at the head
// (fs_y = g sin φ), the closed form of tilt coordination.
TEST(WashoutTest, SustainedSwayTiltsRollToAsinAtLimitedRate) {
  for (double a : {-0.6, 1.2}) {
    const double dt = 1e-3;
    const PlatformSpec platform = MakePw4DofPlatform();
    ClassicalWashout dut(DefaultWashoutParams(), platform, dt);
    HeadMotion turn;
    turn.fs[1] = a;
    double prev_tilt = 0.0, max_rate = 0.0;
    std::vector<DofArray> poses;
    for (int k = 0; k < 60000; ++k) {
      const McaCommand& c = dut.Step(turn);
      max_rate = std::max(max_rate, std::abs(c.tilt_roll - prev_tilt) / dt);
      prev_tilt = c.tilt_roll;
      if (k >= 59990) poses.push_back(c.pose);
    }
    const McaCommand& last = dut.command();
    EXPECT_NEAR(last.tilt_roll, std::asin(a / kGravity), 0.1 * kDegToRad) << a;
    EXPECT_NEAR(last.pose[Index(Dof::kRoll)], last.tilt_roll, 1e-6) << a;
    EXPECT_EQ(last.tilt_pitch, 0.0);
    EXPECT_LE(max_rate, 3.0 * kDegToRad * (1.0 + 1e-9)) << a;
    if (std::abs(a) >= 1.0) {
      EXPECT_GT(max_rate, 2.9 * kDegToRad) << "the rate limit should be active";
    }
    const std::vector<HeadMotion> felt = DeliveredHeadMotion(platform, poses, dt);
    EXPECT_NEAR(felt[5].fs[1], a, 0.02 * std::abs(a)) << a;
  }
}

// Tests the yaw washout against its closed form. A yaw rate ramped from 0 to r0 over T, then
// held (entering a steady turn), through s²/(s+ω)² and 1/s: the pose is
// Y(s) = r0/T (1 − e^{−sT}) / (s (s+ω)²), i.e. y(t) = r0/T (h(t) − h(t−T)) with
// h(t) = (1 − e^{−ωt} − ωt e^{−ωt}) / ω². The input is linear between ticks, so the exact FOH
// discretisation meets it to rounding; inside the limits the limiter passes it unchanged.
// The sustained turn washes out to neutral.
TEST(WashoutTest, YawWashoutMatchesClosedFormAndReturnsToNeutral) {
  const WashoutParams params = DefaultWashoutParams();
  const double w = params.rotation(Dof::kYaw).hp_omega;
  ASSERT_EQ(params.rotation(Dof::kYaw).hp_order, 2);
  ASSERT_EQ(params.rotation(Dof::kYaw).hp_zeta, 1.0);
  const double dt = 1e-3, r0 = 10.0 * kDegToRad, ramp = 1.0;
  auto h = [w](double t) { return t <= 0.0 ? 0.0 : (1.0 - std::exp(-w * t) - w * t * std::exp(-w * t)) / (w * w); };
  ClassicalWashout dut(params, MakePw4DofPlatform(), dt);
  double worst = 0.0, peak = 0.0;
  McaCommand c;
  for (int k = 1; k <= 40000; ++k) {
    const double t = k * dt;
    HeadMotion m;
    m.w[2] = r0 * std::min(t / ramp, 1.0);
    c = dut.Step(m);
    const double expected = r0 / ramp * (h(t) - h(t - ramp));
    worst = std::max(worst, std::abs(c.pose[Index(Dof::kYaw)] - expected));
    peak = std::max(peak, std::abs(expected));
    ASSERT_EQ(c.pose[Index(Dof::kPitch)], 0.0);
    ASSERT_EQ(c.pose[Index(Dof::kRoll)], 0.0);
  }
  EXPECT_GT(peak, 5.0 * kDegToRad);  // a real excursion, within the ±25° travel
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(c.pose[Index(Dof::kYaw)], 0.0, 1e-6);  // 40 s into the turn: washed out
}

// Tests that a specific-force step on the rail produces zero final displacement (3rd order).
TEST(WashoutTest, SurgeStepWashesOutOnTheRail) {
  ClassicalWashout dut(DefaultWashoutParams(), MakeCar2DofPlatform(), 1e-3);
  double peak = 0.0;
  McaCommand c;
  for (int k = 0; k < 60000; ++k) {
    c = dut.Step(Surge(1.0));
    peak = std::max(peak, std::abs(c.pose[Index(Dof::kSurge)]));
  }
  EXPECT_GT(peak, 0.05);
  EXPECT_NEAR(c.pose[Index(Dof::kSurge)], 0.0, 1e-4);
}

// Tests that the command stream does not depend on the step size: 250 Hz against 1 kHz. Without
// the tilt band (a threshold no rate reaches) to the filters' discretisation; with it (3 deg/s,
// binding on this manoeuvre's pitch), the band acts per tick and the streams differ by what its
// ticks of braking make: under 1 mm of heave (the legs it shares) and 0.15 deg of pitch.
TEST(WashoutTest, StepSizeIndependent) {
  const PlatformSpec platform = MakePw4DofPlatform();
  for (const double threshold : {100.0, 3.0 * kDegToRad}) {
    WashoutParams params = DefaultWashoutParams();
    params.tilt_rate_threshold = threshold;
    ClassicalWashout slow(params, platform, 4e-3);
    ClassicalWashout fast(params, platform, 1e-3);
    DofArray worst{};
    double worst_tilt = 0.0;
    for (int k = 1; k <= 2000; ++k) {
      const McaCommand& s = slow.Step(Manoeuvre(k * 4e-3));
      McaCommand f;
      for (int j = 1; j <= 4; ++j) f = fast.Step(Manoeuvre((4 * (k - 1) + j) * 1e-3));
      for (std::size_t i = 0; i < worst.size(); ++i) {
        worst[i] = std::max(worst[i], std::abs(s.pose[i] - f.pose[i]));
      }
      worst_tilt = std::max(worst_tilt, std::abs(s.tilt_pitch - f.tilt_pitch));
    }
    const bool band = threshold < 1.0;
    EXPECT_LT(worst[Index(Dof::kHeave)], band ? 1e-3 : 2e-4) << threshold;               // [m]
    EXPECT_LT(worst[Index(Dof::kPitch)], (band ? 0.15 : 0.05) * kDegToRad) << threshold;  // [rad]
    EXPECT_LT(worst[Index(Dof::kRoll)], 0.05 * kDegToRad) << threshold;
    EXPECT_LT(worst[Index(Dof::kYaw)], 0.05 * kDegToRad) << threshold;
    EXPECT_EQ(fast.limiter().stats().reduced > 0, band) << "the band binds on this manoeuvre";
    // the tilt channel's rate limiter differs by at most one slow tick of travel
    EXPECT_LT(worst_tilt, 3.0 * kDegToRad * 4e-3) << threshold;
  }
}

// Property test: random, extreme and non-finite inputs never take an actuator of any shipped
// platform (pw4dof's five, car2dof's two, stewart6dof's six) beyond its stroke, speed or
// acceleration, the platform never rotates beyond the tilt band, and the tilt channel never
// turns faster than 3 deg/s.
TEST(WashoutTest, NeverLeavesLimitsForAnyInput) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::bernoulli_distribution rare(0.002);
  const std::filesystem::path dir = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/platforms";
  for (const char* name : {"pw4dof", "car2dof", "stewart6dof"}) {
    const PlatformSpec platform = ReadPlatformFile(dir / (std::string(name) + ".yaml"));
    for (double dt : {1e-3, 4e-3}) {
      ClassicalWashout dut(DefaultWashoutParams(), platform, dt);
      double prev_pitch_tilt = 0.0, prev_roll_tilt = 0.0, prev_tilt_rate = 0.0;
      std::array<double, 2> follow{}, previous{}, held{};
      double fault_time = 0.0;
      const double hold_time = DefaultWashoutParams().fault.hold_time;
      std::vector<McaCommand> commands;
      const int ticks = static_cast<int>(40.0 / dt);
      commands.reserve(static_cast<std::size_t>(ticks));
      for (int k = 0; k < ticks; ++k) {
        HeadMotion m;
        const int regime = (k / 2000) % 5;
        for (std::size_t i = 0; i < 3; ++i) {
          const double scale = regime == 0 ? 2.0 : regime == 1 ? 50.0 : regime == 2 ? 1e9 : 5.0;
          m.fs[i] += scale * uniform(rng);
          m.w[i] = 0.1 * scale * uniform(rng);
        }
        if (regime == 3) {  // sustained extremes of either sign
          m.fs[0] = (k / 700) % 2 ? 30.0 : -30.0;
          m.fs[1] = (k / 900) % 2 ? 30.0 : -30.0;
        }
        if (regime == 4 || rare(rng)) {
          m.fs[static_cast<std::size_t>(k % 3)] = (k % 2) ? kNan : kInf;
        }
        const McaCommand& c = dut.Step(m);
        commands.push_back(c);
        // the tilt band from its definition (mca/mpc.h): the vehicle's roll and nose-up pitch
        // rates (during a fault the last finite ones for hold_s, then rest), ω_f changing by at
        // most the axis's brake acceleration per tick, the platform's rate per tick
        bool finite = true;
        for (std::size_t i = 0; i < 3; ++i) finite = finite && std::isfinite(m.fs[i]) && std::isfinite(m.w[i]);
        if (finite) {
          held = {m.w[0], -m.w[1]};
          fault_time = 0.0;
        } else {
          fault_time += dt;
        }
        const std::array<double, 2> vehicle = finite || fault_time <= hold_time * (1.0 + 1e-9) ? held : std::array<double, 2>{};
        for (std::size_t axis = 0; axis < 2; ++axis) {
          const Dof dof = axis == 0 ? Dof::kRoll : Dof::kPitch;
          if (!platform.Has(dof)) continue;
          const double brake = platform.limits(dof).brake_accel();
          follow[axis] = std::clamp(vehicle[axis], follow[axis] - brake * dt, follow[axis] + brake * dt);
          const double pose = c.pose[static_cast<std::size_t>(Index(dof))];
          const double r = (pose - previous[axis]) / dt;
          previous[axis] = pose;
          const double beyond = r - std::clamp(r, std::min(0.0, follow[axis]), std::max(0.0, follow[axis]));
          ASSERT_LE(std::abs(beyond), 3.0 * kDegToRad * (1.0 + 1e-9) + 1e-9) << name << " " << DofName(dof) << " " << k;
          ASSERT_NEAR(axis == 0 ? c.tilt_rate_roll : c.tilt_rate_pitch, beyond, 1e-6) << name << " " << k;
        }
        ASSERT_LE(std::abs(c.tilt_pitch - prev_pitch_tilt), 3.0 * kDegToRad * dt * (1.0 + 1e-9));
        ASSERT_LE(std::abs(c.tilt_roll - prev_roll_tilt), 3.0 * kDegToRad * dt * (1.0 + 1e-9));
        ASSERT_LE(std::abs(c.tilt_pitch), 10.0 * kDegToRad + 1e-12);
        // tilt acceleration limited too (10 deg/s²): no tangential jolt at the head
        const double tilt_rate = (c.tilt_pitch - prev_pitch_tilt) / dt;
        ASSERT_LE(std::abs(tilt_rate - prev_tilt_rate), 10.0 * kDegToRad * dt * (1.0 + 1e-6));
        prev_tilt_rate = tilt_rate;
        prev_pitch_tilt = c.tilt_pitch;
        prev_roll_tilt = c.tilt_roll;
      }
      test::ExpectActuatorsWithinLimits(platform, commands, dt, std::string(name) + " dt " + std::to_string(dt));
    }
  }
}

/// A speed cushion's pitch ringing under a heave bump, as the chair's head feels it: the chair
/// pitches nose-up by θ(t) (a 2 Hz ringing wavelet, ~500 deg/s² and ~40 deg/s at its peaks, the
/// speed cushion's order) about a point that heaves by z(t), the head `kChairHead` above it.
/// Specific force in head axes from the head's world path, differenced (the truth model: the
/// closed-form path, not the washout): f_W = p̈ + (0, 0, g), f_H = Ry(−θ)ᵀ f_W.
struct CushionRinging {
  static constexpr double kChairHead = 1.0;  ///< [m] head above the chair's rotation point
  static double Pitch(double t) {
    const double u = (t - 3.0) / 0.3;
    return 0.06 * std::exp(-u * u) * std::sin(12.0 * (t - 3.0));
  }
  static double Heave(double t) {
    const double u = (t - 3.1) / 0.15;
    return 0.05 * std::exp(-u * u);
  }
  static std::array<double, 2> HeadPosition(double t) {  // (x, z) in W, nose-up pitch tips it back
    return {-kChairHead * std::sin(Pitch(t)), Heave(t) + kChairHead * std::cos(Pitch(t))};
  }
  static HeadMotion At(double t) {
    constexpr double h = 1e-4;
    const std::array<double, 2> p0 = HeadPosition(t - h), p1 = HeadPosition(t), p2 = HeadPosition(t + h);
    const double ax = (p2[0] - 2.0 * p1[0] + p0[0]) / (h * h);
    const double az = (p2[1] - 2.0 * p1[1] + p0[1]) / (h * h) + kGravity;
    const double th = Pitch(t), c = std::cos(th), s = std::sin(th);
    HeadMotion m;
    m.fs = {c * ax + s * az, 0.0, -s * ax + c * az};
    m.w[1] = -(Pitch(t + h) - Pitch(t - h)) / (2.0 * h);  // y points left: nose-up is −w_y
    m.attitude = {0.0, th};
    return m;
  }
};

/// Peak |f_x| and |f_z − g| at the head over a trial.
std::array<double, 2> PeakHeadForce(const std::vector<HeadMotion>& motion) {
  std::array<double, 2> peak{};
  for (const HeadMotion& m : motion) {
    peak[0] = std::max(peak[0], std::abs(m.fs[0]));
    peak[1] = std::max(peak[1], std::abs(m.fs[2] - kGravity));
  }
  return peak;
}

// Tests that the washout does not turn a chair's fast pitch ringing into a larger push at the
// head than the chair gave: the platform's head specific force (the pose stream through
// DeliveredHeadMotion) stays within the vehicle's peak plus h·A per axis — h = |head_from_pivot|
// (0.951 m on pw4dof), A = the pitch box's 300 deg/s² that the shaping allows, so h·A = 4.98
// m/s², what the rotation's tangential term may add beyond the chair's own. Without the shaping
// (the default) the limiter catches up at the legs' acceleration (~1900 deg/s²) and the bound
// fails: the check can fail. Not checked: heave at the head, which the limiter's brake steps
// still push to the legs' ~10 m/s² when the tilt band's guard stops the pitch (docs/mca.md).
TEST(WashoutTest, PitchRingingGivesNoLargerSurgeAtTheHeadThanTheChair) {
  const double dt = 1e-3;
  const PlatformSpec platform = MakePw4DofPlatform();
  std::vector<HeadMotion> vehicle;
  for (int k = 0; k < 6000; ++k) vehicle.push_back(CushionRinging::At(k * dt));
  const std::array<double, 2> chair = PeakHeadForce(vehicle);
  ASSERT_GT(chair[0], 5.0);  // the input is the hard case: several m/s² at the chair's head
  const std::array<double, 3>& p = platform.head_from_pivot;
  const double h = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  const double margin = h * platform.limits(Dof::kPitch).accel;
  EXPECT_NEAR(margin, 0.951 * 300.0 * kDegToRad, 0.01);
  for (bool shaped : {true, false}) {
    WashoutParams params = DefaultWashoutParams();
    params.shape.enabled = shaped;
    ClassicalWashout dut(params, platform, dt);
    std::vector<DofArray> poses;
    std::vector<McaCommand> commands;
    for (const HeadMotion& m : vehicle) {
      commands.push_back(dut.Step(m));
      poses.push_back(commands.back().pose);
    }
    const std::array<double, 2> delivered = PeakHeadForce(DeliveredHeadMotion(platform, poses, dt));
    if (shaped) {
      EXPECT_LE(delivered[0], chair[0] + margin) << "surge at the head";
      test::ExpectActuatorsWithinLimits(platform, commands, dt, "shaped");
    } else {
      EXPECT_GT(delivered[0] - chair[0], margin)
          << "unshaped: the limiter's catch-up was expected to exceed the bound";
    }
  }
}

// Tests the fault path: a non-finite input holds the last pose, then washes out to neutral;
// finite input afterwards rejoins the washout.
TEST(WashoutTest, NonFiniteInputHoldsThenWashesOut) {
  const double dt = 1e-3;
  const WashoutParams params = DefaultWashoutParams();
  ClassicalWashout dut(params, MakePw4DofPlatform(), dt);
  for (int k = 0; k < 3000; ++k) dut.Step(Manoeuvre(k * dt));  // platform away from neutral
  const McaCommand before = dut.command();
  HeadMotion bad = Manoeuvre(3.0);
  bad.w[1] = kNan;
  const McaCommand& first = dut.Step(bad);
  EXPECT_TRUE(first.fault);
  // held: within one tick of braking from the last safe pose
  for (Dof dof : kAllDofs) {
    const auto i = static_cast<std::size_t>(Index(dof));
    const DofLimits& l = dut.platform().dofs[i];
    if (!l.present) continue;
    EXPECT_NEAR(first.pose[i], before.pose[i], (std::abs(before.rate[i]) + l.accel * dt) * dt);
  }
  for (int k = 0; k < 60000; ++k) dut.Step(bad);
  for (double v : dut.command().pose) EXPECT_NEAR(v, 0.0, 1e-9);
  EXPECT_EQ(dut.state().fault_total, 60001);
  // recovery
  for (int k = 0; k < 20000; ++k) dut.Step(Rest());
  EXPECT_FALSE(dut.command().fault);
  EXPECT_FALSE(dut.state().recovering);
  for (double v : dut.command().pose) EXPECT_NEAR(v, 0.0, 1e-9);
}

// Tests bit-identical repeat runs, and that Reset() restores the initial behaviour.
TEST(WashoutTest, RepeatRunsAreBitIdentical) {
  auto run = [](ClassicalWashout& dut) {
    std::vector<McaCommand> out;
    for (int k = 0; k < 8000; ++k) {
      HeadMotion m = Manoeuvre(k * 1e-3);
      if (k == 4000) m.fs[0] = kNan;
      out.push_back(dut.Step(m));
    }
    return out;
  };
  ClassicalWashout a(DefaultWashoutParams(), MakePw4DofPlatform(), 1e-3);
  ClassicalWashout b(DefaultWashoutParams(), MakePw4DofPlatform(), 1e-3);
  const std::vector<McaCommand> ra = run(a);
  const std::vector<McaCommand> rb = run(b);
  EXPECT_TRUE(ra == rb);
  EXPECT_EQ(a.state(), b.state());
  a.Reset();
  EXPECT_TRUE(run(a) == ra);
}

// Tests the channel transfer function: pose/input = scale · HP · integrators.
TEST(WashoutTest, ChannelSystemClosedForm) {
  WashoutParams params = DefaultWashoutParams();
  params.translational[Index(Dof::kHeave)].leak = 0.05;
  const TranslationalParams& h = params.translation(Dof::kHeave);
  const ContinuousSystem dut = ChannelSystem(params, Dof::kHeave);
  const RotationalParams& r = params.rotation(Dof::kPitch);
  const ContinuousSystem pitch = ChannelSystem(params, Dof::kPitch);
  for (double w : {0.1, 1.0, 6.31}) {
    const std::complex<double> s(0.0, w);
    const auto hp2 = s * s / (s * s + 2.0 * h.hp_zeta * h.hp_omega * s + h.hp_omega * h.hp_omega);
    const auto expected = h.scale * hp2 * s / (s + h.hp_break) / ((s + h.leak) * (s + h.leak));
    EXPECT_NEAR(std::abs(dut.Response(w) - expected), 0.0, 1e-9 * std::abs(expected));
    const auto rot = r.scale * s * s / (s * s + 2.0 * r.hp_zeta * r.hp_omega * s + r.hp_omega * r.hp_omega) / s;
    EXPECT_NEAR(std::abs(pitch.Response(w) - rot), 0.0, 1e-9 * std::abs(rot));
  }
}

// Tests strict parsing of an mca mapping: per-axis values, degrees converted, unknown keys fail.
TEST(WashoutTest, ParsesPerAxisParameters) {
  const YamlDocument doc = LoadYamlString(
      "heave: {scale: 0.5, hp_omega_radps: 4}\npitch: {limit_degps: 30, hp_order: 1}\n"
      "tilt_pitch: {max_rate_degps: 2, max_angle_deg: 6}\nfault: {hold_s: 1}\n"
      "shape: {enabled: true, accel_scale: 2}\n",
      "mca.yaml");
  YamlMap map(doc.root, doc.file, "mca");
  const WashoutParams p = ParseWashoutParams(map, DefaultWashoutParams());
  map.Finish();
  EXPECT_DOUBLE_EQ(p.translation(Dof::kHeave).scale, 0.5);
  EXPECT_DOUBLE_EQ(p.translation(Dof::kHeave).hp_omega, 4.0);
  EXPECT_NEAR(p.rotation(Dof::kPitch).limit, 30.0 * kDegToRad, 1e-15);
  EXPECT_EQ(p.rotation(Dof::kPitch).hp_order, 1);
  EXPECT_NEAR(p.tilt_pitch.max_rate, 2.0 * kDegToRad, 1e-15);
  EXPECT_DOUBLE_EQ(p.fault.hold_time, 1.0);
  EXPECT_TRUE(p.shape.enabled);
  EXPECT_DOUBLE_EQ(p.shape.accel_scale, 2.0);
  EXPECT_EQ(p.translation(Dof::kSurge), DefaultWashoutParams().translation(Dof::kSurge));

  const YamlDocument bad = LoadYamlString("heave: {hp_omega: 4}\n", "mca.yaml");
  YamlMap bad_map(bad.root, bad.file, "mca");
  EXPECT_THROW(ParseWashoutParams(bad_map, DefaultWashoutParams()), InputError);
  const YamlDocument bad_shape = LoadYamlString("shape: {accel_scale: 0}\n", "mca.yaml");
  YamlMap bad_shape_map(bad_shape.root, bad_shape.file, "mca");
  EXPECT_THROW(ParseWashoutParams(bad_shape_map, DefaultWashoutParams()), InputError);
}

}  // namespace
}  // namespace pwsim::mca
