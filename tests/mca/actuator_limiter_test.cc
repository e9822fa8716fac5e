// The limiter in actuator space (mca/actuator_limiter.h): every actuator's stroke, speed and
// acceleration recomputed here from the poses by Mechanism::Inverse (the mechanism's own IK,
// not the limiter's), on fuzzed targets for the three shipped platforms; rate windows that move
// within their promise always hold; transparency inside the limits; the car's stages are the
// 1-D limiter bit for bit.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>

#include "mca/actuator_limiter.h"
#include "mca/platform.h"
#include "tests/mca/actuator_checks.h"

namespace pwsim::mca {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

PlatformSpec Shipped(const char* name) {
  return ReadPlatformFile(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/platforms" / (std::string(name) + ".yaml"));
}

// Tests that the coupled group's fast positions equal Mechanism::Inverse.
TEST(ActuatorLimiterTest, CoupledPositionsAreTheMechanismsInverse) {
  for (const char* name : {"pw4dof", "stewart6dof"}) {
    const PlatformSpec p = Shipped(name);
    const ActuatorLimiter limiter(p, 1e-3);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 200; ++k) {
      DofArray pose{};
      for (Dof dof : kAllDofs) {
        if (p.mechanism.Moves(dof)) pose[static_cast<std::size_t>(Index(dof))] = u(rng) * (IsRotational(dof) ? 0.2 : 0.05);
      }
      ActuatorVector a = p.mechanism.Neutral(), b;
      ASSERT_TRUE(limiter.CoupledPositions(pose, &a));
      ASSERT_TRUE(p.mechanism.Inverse(pose, &b));
      for (int i = 0; i < b.size(); ++i) {
        if (p.mechanism.actuator(i).kind == ActuatorKind::kLeg) {
          EXPECT_NEAR(a[i], b[i], 1e-14) << name << " " << i;
        }
      }
    }
  }
}

// Tests fuzzed targets (random poses far outside the workspace held for random times, one-tick
// impulses, slow sweeps, NaN) on pw4dof, car2dof and stewart6dof at 1 kHz and 100 Hz: no
// actuator ever leaves its stroke or exceeds its speed or acceleration (recomputed from the
// poses with the mechanism's IK; floating point only), and the limiter is not idle (the limits
// are reached).
TEST(ActuatorLimiterTest, FuzzedTargetsNeverBeyondAnActuatorLimit) {
  for (const char* name : {"pw4dof", "car2dof", "stewart6dof"}) {
    const PlatformSpec p = Shipped(name);
    for (const double dt : {1e-3, 1e-2}) {
      ActuatorLimiter limiter(p, dt);
      std::mt19937 rng(11);
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      std::uniform_int_distribution<int> hold(1, static_cast<int>(0.5 / dt)), kind(0, 9);
      std::vector<DofArray> poses;
      const int ticks = static_cast<int>(6.0 / dt);
      while (static_cast<int>(poses.size()) < ticks) {
        const int k = kind(rng);
        DofArray target{}, rate{};
        for (Dof dof : kAllDofs) {
          const double span = IsRotational(dof) ? 0.6 : 0.3;  // [rad | m]: far beyond every stroke
          target[static_cast<std::size_t>(Index(dof))] = (k < 9 ? u(rng) : 0.0) * span;
        }
        if (k == 9) target[static_cast<std::size_t>(Index(Dof::kPitch))] = kNan;
        const int n = k == 8 ? 1 : hold(rng);
        for (int t = 0; t < n && static_cast<int>(poses.size()) < ticks; ++t) {
          if (k == 7) {  // a sweep the target's rate announces
            for (double& r : rate) r = 0.3;
            for (double& x : target) x += 0.3 * dt;
          }
          limiter.Step(target, rate, {});
          poses.push_back(limiter.pose());
        }
      }
      const test::ActuatorUse use = test::MeasureActuatorUse(p.mechanism, poses, dt);
      const std::string what = std::string(name) + " dt " + std::to_string(dt);
      EXPECT_LE(use.beyond_stroke, 0.0) << what;
      EXPECT_LE(use.speed, 1.0) << what;
      EXPECT_LE(use.accel, 1.0) << what;
      EXPECT_GT(use.speed, 0.5) << what << ": the fuzz reaches the limits";
    }
  }
}

// Tests the rate windows: on the pitch and roll of pw4dof's and stewart6dof's legs a window
// [min(0, w) − τ, max(0, w) + τ] whose w moves by at most the promised edge acceleration per
// tick (a random walk that hits its bound often), with random targets: the pose rate is never
// outside the window.
TEST(ActuatorLimiterTest, MovingRateWindowsAlwaysHold) {
  const double tau = 3.0 * kDegToRad, edge = 300.0 * kDegToRad;
  for (const char* name : {"pw4dof", "stewart6dof"}) {
    const PlatformSpec p = Shipped(name);
    for (const double dt : {1e-3, 1e-2}) {
      std::array<RateGuard, kDofCount> guards{};
      guards[Index(Dof::kRoll)] = guards[Index(Dof::kPitch)] = RateGuard{tau, edge};
      ActuatorLimiter limiter(p, dt, guards);
      std::mt19937 rng(3);
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      std::array<double, 2> w{};
      DofArray target{};
      for (int k = 0; k < static_cast<int>(8.0 / dt); ++k) {
        if (k % static_cast<int>(0.2 / dt) == 0) {
          for (double& x : target) x = 0.3 * u(rng);
        }
        std::array<RateWindow, kDofCount> windows{};
        for (std::size_t a = 0; a < 2; ++a) {
          w[a] = std::clamp(w[a] + 2.0 * edge * dt * u(rng), w[a] - edge * dt, w[a] + edge * dt);
          w[a] = std::clamp(w[a], -0.6, 0.6);
          windows[a == 0 ? Index(Dof::kRoll) : Index(Dof::kPitch)] = {std::min(0.0, w[a]) - tau, std::max(0.0, w[a]) + tau};
        }
        limiter.Step(target, DofArray{}, windows);
        for (Dof dof : {Dof::kRoll, Dof::kPitch}) {
          const RateWindow& win = windows[Index(dof)];
          const double r = limiter.rate()[Index(dof)];
          ASSERT_GE(r, win.lo - 1e-12) << name << " " << DofName(dof) << " tick " << k;
          ASSERT_LE(r, win.hi + 1e-12) << name << " " << DofName(dof) << " tick " << k;
        }
      }
      EXPECT_GT(limiter.stats().reduced, 0) << name;
    }
  }
}

// Tests transparency: slow motion well inside every limit, its rate the difference per tick as
// the cueing gives it, is followed exactly (dead-beat).
TEST(ActuatorLimiterTest, InsideTheLimitsTheTargetIsFollowedExactly) {
  for (const char* name : {"pw4dof", "stewart6dof"}) {
    const PlatformSpec p = Shipped(name);
    ActuatorLimiter limiter(p, 1e-3);
    DofArray last{};
    for (int k = 1; k <= 4000; ++k) {
      DofArray target{}, rate{};
      for (Dof dof : kAllDofs) {
        if (!p.mechanism.Moves(dof)) continue;
        const double a = IsRotational(dof) ? 0.02 : 0.01;
        const double w = 1.0 + 0.3 * Index(dof);
        target[static_cast<std::size_t>(Index(dof))] = a * std::sin(w * k * 1e-3) * std::sin(w * k * 1e-3);
      }
      for (std::size_t d = 0; d < kDofCount; ++d) rate[d] = (target[d] - last[d]) / 1e-3;  // as the cueing gives it
      last = target;
      limiter.Step(target, rate, {});
      for (std::size_t d = 0; d < kDofCount; ++d) ASSERT_NEAR(limiter.pose()[d], target[d], 1e-12) << name << " " << k;
    }
    EXPECT_EQ(limiter.stats().reduced, 0) << name;
  }
}

// Tests that the car's rail and turntable (independent stages) are exactly the 1-D limiter on
// their actuators' limits less the 1e-9 headroom (the car's file: the same as its axis boxes).
TEST(ActuatorLimiterTest, IndependentStagesAreTheOneAxisLimiter) {
  const PlatformSpec p = Shipped("car2dof");
  ActuatorLimiter limiter(p, 1e-3);
  std::array<DofLimits, kDofCount> limits = p.dofs;
  for (DofLimits& l : limits) {
    l.travel *= 1.0 - 1e-9;
    l.speed *= 1.0 - 1e-9;
    l.accel *= 1.0 - 1e-9;
  }
  std::array<LimiterState, kDofCount> axis{};
  for (int k = 0; k < 5000; ++k) {
    DofArray target{};
    target[Index(Dof::kSurge)] = k < 2500 ? 2.0 : -0.3;
    target[Index(Dof::kYaw)] = std::sin(k * 1e-3);
    limiter.Step(target, DofArray{}, {});
    for (Dof dof : {Dof::kSurge, Dof::kYaw}) {
      const auto d = static_cast<std::size_t>(Index(dof));
      axis[d] = StepLimiter(limits[d], axis[d], target[d], 0.0, RateWindow{}, 1e-3);
      ASSERT_EQ(limiter.pose()[d], axis[d].pose) << DofName(dof) << " " << k;
    }
  }
}

}  // namespace
}  // namespace pwsim::mca
