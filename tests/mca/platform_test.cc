#include "mca/platform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/input_error.h"

namespace pwsim::mca {
namespace {

const std::filesystem::path kPlatforms = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/platforms";

// Tests that the platform files hold the seed figures (car) and the built-in defaults (PW).
TEST(PlatformTest, FilesMatchBuiltIns) {
  const PlatformSpec car = ReadPlatformFile(kPlatforms / "car2dof.yaml");
  const PlatformSpec car_builtin = MakeCar2DofPlatform();
  EXPECT_EQ(car.name, "car2dof");
  for (Dof dof : kAllDofs) {
    EXPECT_EQ(car.Has(dof), car_builtin.Has(dof)) << DofName(dof);
    if (!car.Has(dof)) continue;
    EXPECT_NEAR(car.limits(dof).speed, car_builtin.limits(dof).speed, 1e-12);
    EXPECT_NEAR(car.limits(dof).accel, car_builtin.limits(dof).accel, 1e-9);
    EXPECT_NEAR(car.limits(dof).steady_accel, car_builtin.limits(dof).steady_accel, 1e-9);
  }
  EXPECT_DOUBLE_EQ(car.limits(Dof::kSurge).travel, 0.6);
  EXPECT_DOUBLE_EQ(car.limits(Dof::kSurge).speed, 2.45);
  EXPECT_NEAR(car.limits(Dof::kSurge).accel, 1.224 * kGravity, 1e-9);
  EXPECT_NEAR(car.limits(Dof::kSurge).steady_accel, 0.408 * kGravity, 1e-9);
  EXPECT_TRUE(std::isinf(car.limits(Dof::kYaw).travel));
  EXPECT_NEAR(car.limits(Dof::kYaw).speed, 29.075 * kDegToRad, 1e-12);
  EXPECT_NEAR(car.limits(Dof::kYaw).accel, 58.151 * kDegToRad, 1e-12);

  const PlatformSpec pw = ReadPlatformFile(kPlatforms / "pw4dof.yaml");
  const PlatformSpec pw_builtin = MakePw4DofPlatform();
  EXPECT_EQ(pw.dofs, pw_builtin.dofs);
  EXPECT_EQ(pw.head_from_pivot, pw_builtin.head_from_pivot);
  EXPECT_TRUE(pw.Has(Dof::kHeave) && pw.Has(Dof::kPitch) && pw.Has(Dof::kRoll) && pw.Has(Dof::kYaw));
  EXPECT_FALSE(pw.Has(Dof::kSurge) || pw.Has(Dof::kSway));
}

// Tests that an unknown key and an out-of-range value name file, line and field.
TEST(PlatformTest, StrictParsing) {
  const std::string text =
      "format: pwsim-platform/1\nname: x\ndofs:\n  heave: {travel_m: 0.1, speed_mps: 1, accel_mps2: 5, jerk: 3}\n";
  const YamlDocument doc = LoadYamlString(text, "inline.yaml");
  YamlMap root(doc.root, doc.file, "");
  try {
    root.String("format");
    ParsePlatform(root);
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.line(), 4);
    EXPECT_NE(std::string(error.what()).find("jerk"), std::string::npos) << error.what();
  }
  const std::string negative =
      "name: x\ndofs:\n  pitch: {travel_deg: -3, speed_degps: 1, accel_degps2: 5}\n";
  const YamlDocument doc2 = LoadYamlString(negative, "inline.yaml");
  YamlMap root2(doc2.root, doc2.file, "");
  EXPECT_THROW(ParsePlatform(root2), InputError);
}

// Tests that the limiter follows a feasible target exactly (dead-beat).
TEST(PlatformTest, LimiterIsTransparentInsideLimits) {
  const DofLimits limits{.present = true, .travel = 0.1, .speed = 0.5, .accel = 10.0};
  const double dt = 1e-3;
  LimiterState state;
  double prev = 0.0;
  for (int k = 1; k <= 3000; ++k) {
    const double target = 0.05 * (1.0 - std::cos(2.0 * k * dt));  // starts at rest
    state = StepLimiter(limits, state, target, (target - prev) / dt, limits.speed, dt);
    prev = target;
    ASSERT_NEAR(state.pose, target, 1e-12);
  }
}

// Tests that random and extreme targets never push pose, rate or acceleration past the limits.
TEST(PlatformTest, LimiterNeverExceedsLimits) {
  std::mt19937_64 rng(20240601);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const DofLimits rail = MakeCar2DofPlatform().limits(Dof::kSurge);
  const DofLimits heave = MakePw4DofPlatform().limits(Dof::kHeave);
  for (const DofLimits& limits : {rail, heave}) {
    for (double dt : {1e-3, 4e-3, 2e-2}) {
      LimiterState state;
      for (int k = 0; k < 200000; ++k) {
        double target = 0.0;
        switch ((k / 500) % 4) {
          case 0: target = 10.0 * uniform(rng); break;                    // wild noise
          case 1: target = (k / 50) % 2 ? 1e6 : -1e6; break;              // extreme steps
          case 2: target = limits.travel * std::sin(0.05 * k); break;     // at the edge
          default: target = std::nan(""); break;                          // non-finite
        }
        const double cap = (k / 3000) % 2 ? limits.speed : 0.1 * limits.speed;
        const LimiterState next = StepLimiter(limits, state, target, 1e3 * uniform(rng), cap, dt);
        ASSERT_LE(std::abs(next.pose), limits.travel) << k;
        ASSERT_LE(std::abs(next.rate), limits.speed * (1.0 + 1e-9)) << k;
        ASSERT_LE(std::abs(next.accel), limits.accel * (1.0 + 1e-6)) << k;
        if (std::isfinite(limits.steady_accel)) {  // the peak budget is never overdrawn
          const double excess = limits.accel - limits.steady_accel;
          ASSERT_LE(next.heat, excess * (limits.peak_time + dt) * (1.0 + 1e-9)) << k;
        }
        state = next;
      }
    }
  }
}

// Tests the rate window (RateWindow, the MPC's tilt band): wild targets while the window
// [lo, hi] ∋ [−τ, τ] wanders with each edge moving at most brake_accel()·dt per tick (jumps
// of exactly that size, random walks, long holds) — on pw4dof's pitch and on the car's rail with
// its peak budget, at three step sizes. The rate stays in the window on every tick (floating
// point aside) and every limit holds; a window edge jumping by more is then, by design, not
// guaranteed: the acceleration limit wins (checked on one jump).
TEST(PlatformTest, LimiterKeepsAMovingRateWindow) {
  std::mt19937_64 rng(20261125);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const DofLimits pitch = MakePw4DofPlatform().limits(Dof::kPitch);
  const DofLimits rail = MakeCar2DofPlatform().limits(Dof::kSurge);
  for (const DofLimits& limits : {pitch, rail}) {
    const double tau = 0.05 * limits.speed;
    for (double dt : {1e-3, 4e-3, 1e-2}) {
      const double step = limits.brake_accel() * dt;
      LimiterState state;
      double centre = 0.0;  // the window is [min(0, c) − τ, max(0, c) + τ]
      for (int k = 0; k < 100000; ++k) {
        switch ((k / 700) % 3) {
          case 0: centre += step * (uniform(rng) > 0.0 ? 1.0 : -1.0); break;  // full-size moves
          case 1: centre += step * uniform(rng); break;
          default: break;  // held
        }
        centre = std::clamp(centre, -limits.speed, limits.speed);
        const RateWindow window{std::min(0.0, centre) - tau, std::max(0.0, centre) + tau};
        const double target = (k / 300) % 2 ? 10.0 * uniform(rng) : limits.travel * std::sin(0.01 * k);
        const LimiterState next = StepLimiter(limits, state, target, 1e3 * uniform(rng), window, dt);
        ASSERT_GE(next.rate, window.lo - 1e-9) << k << " dt " << dt;
        ASSERT_LE(next.rate, window.hi + 1e-9) << k << " dt " << dt;
        ASSERT_LE(std::abs(next.pose), limits.travel) << k;
        ASSERT_LE(std::abs(next.rate), limits.speed * (1.0 + 1e-9)) << k;
        ASSERT_LE(std::abs(next.accel), limits.accel * (1.0 + 1e-6)) << k;
        state = next;
      }
    }
  }
  // beyond the premise: from 10 deg/s, a window collapsing to [±τ] in one tick is left at the
  // nearest rate the acceleration limit allows
  LimiterState moving;
  moving.rate = 10.0 * kDegToRad;
  const double tau = 3.0 * kDegToRad, dt = 1e-3;
  const LimiterState next = StepLimiter(pitch, moving, 0.0, 0.0, RateWindow{-tau, tau}, dt);
  EXPECT_NEAR(next.rate, moving.rate - pitch.accel * dt, 1e-9);
}

// Tests the stopping bound: braking from StoppableSpeed(d) at `brake` stays within d.
TEST(PlatformTest, StoppableSpeedStops) {
  for (double d : {1e-6, 0.01, 0.3, 0.6}) {
    const double dt = 1e-3, brake = 4.0;
    double v = StoppableSpeed(d, brake, dt);
    double travelled = 0.0;
    while (v > 0.0) {
      travelled += v * dt;
      v -= brake * dt;
    }
    EXPECT_LE(travelled, d * (1.0 + 1e-12)) << d;
  }
}

// Tests the seed-001 figures on the car platform: the rail reaches 2.45 m/s at 1.224 g and
// stops inside ±0.6 m; the turntable reaches 29.075 deg/s in 0.5 s at 58.151 deg/s², and after
// the peak time only the 3.971 deg/s² steady acceleration is left.
TEST(PlatformTest, CarPlatformFigures) {
  const PlatformSpec car = MakeCar2DofPlatform();
  const double dt = 1e-3;
  const DofLimits& rail = car.limits(Dof::kSurge);
  LimiterState s;
  double peak_rate = 0.0, peak_pose = 0.0;
  for (int k = 0; k < 3000; ++k) {
    s = StepLimiter(rail, s, 100.0, 0.0, rail.speed, dt);  // far beyond the end of the rail
    peak_rate = std::max(peak_rate, s.rate);
    peak_pose = std::max(peak_pose, s.pose);
  }
  EXPECT_LE(peak_pose, 0.6);
  EXPECT_NEAR(s.pose, 0.6, 1e-3);  // parked at the end, not beyond
  EXPECT_LE(peak_rate, 2.45 * (1.0 + 1e-12));
  // braking is planned at the steady 0.408 g: at most sqrt(0.6 / (1/(2·12) + 1/(2·4))) m/s
  EXPECT_GT(peak_rate, 1.85);

  const DofLimits& yaw = car.limits(Dof::kYaw);
  LimiterState y;
  int ticks_to_speed = -1;
  for (int k = 1; k <= 4000; ++k) {
    y = StepLimiter(yaw, y, 1e3, yaw.speed, yaw.speed, dt);
    if (ticks_to_speed < 0 && y.rate >= yaw.speed * (1.0 - 1e-9)) ticks_to_speed = k;
  }
  EXPECT_NEAR(ticks_to_speed * dt, 29.075 / 58.151, 2e-3);
  // reversing back and forth spends the peak budget: then only the steady acceleration is left
  bool steady_seen = false;
  for (int k = 0; k < 6000; ++k) {
    const double target = (k / 600) % 2 ? 1e3 : -1e3;
    y = StepLimiter(yaw, y, target, 0.0, yaw.speed, dt);
    if (std::abs(std::abs(y.accel) - 3.971 * kDegToRad) < 1e-9) steady_seen = true;
    ASSERT_LE(std::abs(y.accel), yaw.accel * (1.0 + 1e-9));
  }
  EXPECT_TRUE(steady_seen);
}

}  // namespace
}  // namespace pwsim::mca
