// Fault injection against the safety supervisor: every documented reaction happens within a
// bounded number of cycles, and the streamed positions never leave the workspace nor exceed
// the velocity, acceleration and jerk limits.
#include "hardware/safety_supervisor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

namespace pwsim::hw {
namespace {

/// Checks every output against the limits using finite differences, like a drive would see.
struct LimitChecker {
  SafetyConfig c;
  std::array<std::vector<double>, kMaxDriveAxes> p;
  int violations = 0;
  double worst_jerk_ratio = 0.0;

  void Add(const AxisValues& out) {
    for (std::size_t i = 0; i < static_cast<std::size_t>(c.axis_count); ++i) {
      auto& x = p[i];
      x.push_back(out[i]);
      const AxisLimits& l = c.axes[i];
      const double dt = c.dt;
      const std::size_t n = x.size();
      if (x[n - 1] > l.max + 1e-12 || x[n - 1] < l.min - 1e-12) ++violations;
      if (n >= 2 && std::abs(x[n - 1] - x[n - 2]) / dt > l.velocity * (1 + 1e-9)) ++violations;
      if (n >= 3) {
        const double a = (x[n - 1] - 2 * x[n - 2] + x[n - 3]) / (dt * dt);
        if (std::abs(a) > l.accel * (1 + 1e-6)) ++violations;
      }
      if (n >= 4) {
        const double a1 = (x[n - 1] - 2 * x[n - 2] + x[n - 3]) / (dt * dt);
        const double a0 = (x[n - 2] - 2 * x[n - 3] + x[n - 4]) / (dt * dt);
        const double j = std::abs(a1 - a0) / dt;
        worst_jerk_ratio = std::max(worst_jerk_ratio, j / l.jerk);
        if (j > l.jerk * (1 + 1e-6) + 1e-6 / (dt * dt * dt)) ++violations;
      }
    }
  }
};

struct Harness {
  SafetySupervisor sup;
  LimitChecker check{sup.config(), {}, 0, 0.0};
  std::int64_t cycle = 0;
  SafetyInputs in;

  explicit Harness(SafetyConfig config = {}) : sup(config) {
    in.drives_ready = true;
    in.setpoint = AxisValues{};
  }
  AxisValues Step() {
    // The platform follows exactly (measured = last output).
    const auto out = sup.Step(cycle++, in);
    in.measured = out;
    if (sup.streaming()) check.Add(out);
    return out;
  }
  /// Runs cycles with setpoint(t); returns the cycle at which `pred` first holds, or -1.
  std::int64_t RunUntil(int max_cycles, const std::function<bool()>& pred,
                        const std::function<void(std::int64_t)>& before = nullptr) {
    for (int k = 0; k < max_cycles; ++k) {
      if (before) before(cycle);
      Step();
      if (pred()) return cycle - 1;
    }
    return -1;
  }
  void Cruise(int cycles) {
    for (int k = 0; k < cycles; ++k) {
      const double t = static_cast<double>(cycle) * sup.config().dt;
      in.setpoint = AxisValues{0.2 * std::sin(0.8 * t), 0.3 * std::sin(1.3 * t)};
      Step();
    }
  }
};

TEST(SafetySupervisor, DefaultConfigIsValid) {
  EXPECT_EQ(ValidateSafetyConfig(SafetyConfig{}), "");
  SafetyConfig bad;
  bad.axes[1].max = 0.7;  // beyond the hard end
  EXPECT_NE(ValidateSafetyConfig(bad).find("axis 2"), std::string::npos);
  SafetyConfig outside;
  outside.neutral[0] = 0.6;
  EXPECT_NE(ValidateSafetyConfig(outside).find("axis 1.neutral"), std::string::npos);
}

TEST(SafetySupervisor, PassesAFeasibleStreamThroughUnchanged) {
  Harness h;
  h.Step();
  ASSERT_EQ(h.sup.state(), SupervisorState::kRunning);
  for (int k = 0; k < 2000; ++k) {
    const double t = k * 0.004;
    const AxisValues sp{0.2 * (1 - std::cos(0.8 * t)) / 2, 0.3 * (1 - std::cos(1.3 * t)) / 2};
    h.in.setpoint = sp;
    const auto out = h.Step();
    EXPECT_EQ(out, sp) << k;
  }
  EXPECT_EQ(h.sup.counters().rate_limited, 0U);
  EXPECT_EQ(h.check.violations, 0);
}

TEST(SafetySupervisor, NonFiniteSetpointsAreRejectedAndHeld) {
  Harness h;
  h.Cruise(100);
  const auto before = h.sup.motion();
  h.in.setpoint = AxisValues{std::numeric_limits<double>::quiet_NaN(), 0.0};
  h.Step();
  h.in.setpoint = AxisValues{0.0, std::numeric_limits<double>::infinity()};
  h.Step();
  EXPECT_EQ(h.sup.counters().nonfinite, 2U);
  EXPECT_EQ(h.sup.state(), SupervisorState::kRunning);  // 2 <= stale_setpoint_cycles
  for (std::size_t i = 0; i < 2; ++i) EXPECT_TRUE(std::isfinite(h.sup.motion()[i].p));
  (void)before;
  EXPECT_EQ(h.check.violations, 0);
}

TEST(SafetySupervisor, OutOfWorkspaceSetpointsAreClampedAndStepsRateLimited) {
  Harness h;
  h.Cruise(10);
  h.in.setpoint = AxisValues{5.0, -9.0};  // far outside, a huge step
  for (int k = 0; k < 1000; ++k) h.Step();
  EXPECT_GT(h.sup.counters().clamped, 0U);
  EXPECT_GT(h.sup.counters().rate_limited, 0U);
  EXPECT_NEAR(h.sup.motion()[1].p, h.sup.config().axes[1].min, 1e-3);
  EXPECT_NEAR(h.sup.motion()[0].p, h.sup.config().axes[0].max, 1e-3);
  EXPECT_EQ(h.check.violations, 0);
}

struct FaultCase {
  const char* name;
  std::function<void(Harness&)> inject;
  SupervisorState reaction;
  int max_cycles;  ///< documented bound from injection to reaction
};

TEST(SafetySupervisor, EachFaultLeadsToItsReactionWithinBoundedCycles) {
  const std::vector<FaultCase> cases = {
      {"stale setpoint", [](Harness& h) { h.in.setpoint.reset(); }, SupervisorState::kSoftStop, 4},
      {"NaN stream", [](Harness& h) { h.in.setpoint = AxisValues{NAN, NAN}; },
       SupervisorState::kSoftStop, 4},
      {"heartbeat lost", [](Harness& h) { h.in.heartbeats_ok = false; }, SupervisorState::kSoftStop, 1},
      {"TPDO stale", [](Harness& h) { h.in.tpdos_fresh = false; }, SupervisorState::kSoftStop, 1},
      {"HMD stale", [](Harness& h) { h.in.hmd_ok = false; }, SupervisorState::kSoftStop, 1},
      {"stop request", [](Harness& h) { h.in.stop_requested = true; }, SupervisorState::kSoftStop, 1},
      {"drive quick stop", [](Harness& h) { h.in.drive_quick_stop = true; }, SupervisorState::kSoftStop, 1},
      {"drive restarted", [](Harness& h) { h.in.drive_restarted = true; }, SupervisorState::kSoftStop, 1},
      {"drive fault", [](Harness& h) { h.in.drive_fault = true; }, SupervisorState::kFault, 1},
      {"bus-off", [](Harness& h) { h.in.bus_off = true; }, SupervisorState::kFault, 1},
  };
  for (const FaultCase& fc : cases) {
    SCOPED_TRACE(fc.name);
    Harness h;
    h.Cruise(400);  // moving: 1.6 s into the motion
    ASSERT_EQ(h.sup.state(), SupervisorState::kRunning);
    const std::int64_t injected = h.cycle;
    const std::int64_t reacted =
        h.RunUntil(100, [&] { return h.sup.state() == fc.reaction; }, [&](std::int64_t) { fc.inject(h); });
    ASSERT_GE(reacted, 0) << SupervisorStateName(h.sup.state());
    EXPECT_LT(reacted - injected, fc.max_cycles);
    EXPECT_FALSE(h.sup.reason().empty());
    // The soft stop reaches neutral, at rest, within 10 s, and never breaks a limit.
    const std::int64_t rest = h.RunUntil(2500, [&] { return h.sup.parked_cycle() >= 0; },
                                         [&](std::int64_t) { fc.inject(h); });
    ASSERT_GE(rest, 0) << "did not come to rest: p=" << h.sup.motion()[1].p;
    EXPECT_NEAR(h.sup.motion()[0].p, 0.0, 1e-3);
    EXPECT_NEAR(h.sup.motion()[1].p, 0.0, 1e-3);
    EXPECT_EQ(h.check.violations, 0);
    if (fc.reaction == SupervisorState::kFault) {
      // Latched: clearing the cause does not resume.
      h.in = SafetyInputs{};
      h.in.drives_ready = true;
      h.in.setpoint = AxisValues{0.1, 0.1};
      for (int k = 0; k < 10; ++k) h.Step();
      EXPECT_EQ(h.sup.state(), SupervisorState::kFault);
      h.sup.Reset();
      h.Step();
      EXPECT_EQ(h.sup.state(), SupervisorState::kRunning);
    }
  }
}

TEST(SafetySupervisor, RandomHostileStreamsNeverBreakTheLimits) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    Harness h;
    AxisValues sp{};
    for (int k = 0; k < 1500; ++k) {
      const double r = u(rng);
      if (r > 0.95) {
        sp = {2.0 * u(rng), 2.0 * u(rng)};  // wild jumps, beyond the workspace
      } else if (r > 0.9) {
        sp = {0.5 * u(rng), 0.55 * u(rng)};
      } else {
        sp[0] += 0.01 * u(rng);
        sp[1] += 0.02 * u(rng);
      }
      h.in.setpoint = sp;
      h.Step();
    }
    EXPECT_EQ(h.check.violations, 0) << "trial " << trial;
    EXPECT_LE(h.check.worst_jerk_ratio, 1.0 + 1e-6);
    EXPECT_EQ(h.sup.state(), SupervisorState::kRunning);
  }
}

TEST(SafetySupervisor, IdleHoldsMeasuredUntilDrivesAreReady) {
  SafetySupervisor sup;
  SafetyInputs in;
  in.measured = {0.01, 0.02};
  in.setpoint = AxisValues{0.3, 0.3};
  EXPECT_EQ(sup.Step(0, in), in.measured);
  EXPECT_EQ(sup.state(), SupervisorState::kIdle);
  in.drives_ready = true;
  const auto out = sup.Step(1, in);
  EXPECT_EQ(sup.state(), SupervisorState::kRunning);
  EXPECT_NEAR(out[1], 0.02, 1e-3);  // starts from the measured pose, rate-limited
}

/// Five axes of different ranges and limits (legs and a stage), neutral off zero.
SafetyConfig FiveAxes() {
  SafetyConfig c;
  c.axis_count = 5;
  for (std::size_t i = 0; i < 5; ++i) {
    const double n = 0.4 + 0.01 * static_cast<double>(i);
    c.axes[i] = {n - 0.1, n + 0.1, n - 0.12, n + 0.12, 0.3 + 0.05 * static_cast<double>(i), 3.0, 30.0};
    c.soft_stop[i] = c.axes[i];
    c.soft_stop[i].velocity = 0.06 + 0.01 * static_cast<double>(i);
    c.soft_stop[i].accel = 0.3 + 0.1 * static_cast<double>(i);
    c.soft_stop[i].jerk = 3.0 - 0.2 * static_cast<double>(i);
    c.neutral[i] = n;
  }
  return c;
}

// From rest, the soft stop moves every axis along the same normalised profile: the positions stay
// on the straight line from where the stop began to neutral (legs of a parallel platform stay close
// to a consistent pose), every axis arrives together (overshooting neutral by the same small
// fraction), and each keeps its own comfort limits.
TEST(SafetySupervisor, TheSoftStopMovesEveryAxisAlongOneStraightLineToNeutral) {
  Harness h(FiveAxes());
  const SafetyConfig& c = h.sup.config();
  const AxisValues start{0.47, 0.35, 0.43, 0.48, 0.36};
  AxisValues neutral_gap{};
  for (std::size_t i = 0; i < 5; ++i) neutral_gap[i] = start[i] - c.neutral[i];
  h.in.measured = start;
  h.in.setpoint = start;
  for (int k = 0; k < 5; ++k) h.Step();  // running, at rest where the platform is
  ASSERT_EQ(h.sup.state(), SupervisorState::kRunning);
  ASSERT_EQ(h.sup.motion()[0].p, start[0]);
  h.in.stop_requested = true;
  double worst = 0.0, worst_end = 0.0, u_min = 1.0;
  std::int64_t parked = -1;
  for (int k = 0; k < 5000 && parked < 0; ++k) {
    const AxisValues out = h.Step();
    const double u0 = (out[0] - c.neutral[0]) / neutral_gap[0];  // the common progress
    u_min = std::min(u_min, u0);
    for (std::size_t i = 1; i < 5; ++i) {
      const double off = std::abs((out[i] - c.neutral[i]) / neutral_gap[i] - u0);
      // until the axes reach neutral (a 1 % margin); crossing it, an axis within the park
      // tolerance stops taking part in the plan and the small overshoot settles on its own
      if (u0 > 0.01) worst = std::max(worst, off);
      worst_end = std::max(worst_end, off);
    }
    for (std::size_t i = 0; i < 5; ++i) {
      const auto& x = h.check.p[i];
      const std::size_t n = x.size();
      if (n >= 2) {
        ASSERT_LE(std::abs(x[n - 1] - x[n - 2]) / c.dt, c.soft_stop[i].velocity * (1 + 1e-9)) << i;
      }
    }
    if (h.sup.state() == SupervisorState::kParked) parked = k;
  }
  ASSERT_GE(parked, 0);
  EXPECT_LT(worst, 1e-9) << "the axes left the straight line to neutral";
  EXPECT_LT(worst_end, 0.01);
  EXPECT_GE(u_min, -0.03) << "the jerk-limited tracking overshoots neutral by a little, not more";
  EXPECT_EQ(h.check.violations, 0);
}

// Drives that stop following (a restart, a quick stop walked back): the supervisor follows the
// measured positions at rest, never parks on its own trajectory, and once the drives are enabled
// again ramps from where they are: no jump, and the stop to neutral from there.
TEST(SafetySupervisor, WhileTheDrivesAreNotEnabledItFollowsTheMeasuredPositionsThenRampsFromThem) {
  Harness h;
  h.Cruise(400);
  ASSERT_EQ(h.sup.state(), SupervisorState::kRunning);
  h.in.drives_enabled = false;
  const AxisValues elsewhere{-0.1, 0.2};  // where the restarted drives report themselves
  for (int k = 0; k < 50; ++k) {
    const AxisValues out = h.sup.Step(h.cycle++, SafetyInputs{h.in.setpoint, elsewhere, false, false});
    EXPECT_EQ(out[0], elsewhere[0]);
    EXPECT_EQ(out[1], elsewhere[1]);
    EXPECT_TRUE(h.sup.holding());
  }
  EXPECT_EQ(h.sup.state(), SupervisorState::kSoftStop);
  EXPECT_EQ(h.sup.reason(), "drive not operation enabled");
  EXPECT_EQ(h.sup.parked_cycle(), -1);
  EXPECT_GE(h.sup.counters().held, 50U);
  // enabled again: from `elsewhere` at rest, under the comfort limits, to neutral
  h.in.drives_enabled = true;
  h.in.measured = elsewhere;
  h.check = LimitChecker{h.sup.config(), {}, 0, 0.0};
  h.check.Add(elsewhere);
  h.check.Add(elsewhere);
  h.check.Add(elsewhere);
  const AxisValues first = h.Step();
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_LE(std::abs(first[i] - elsewhere[i]), h.sup.config().axes[i].jerk * std::pow(h.sup.config().dt, 3) * 1.01);
  ASSERT_GE(h.RunUntil(5000, [&] { return h.sup.state() == SupervisorState::kParked; }), 0);
  EXPECT_NEAR(h.sup.motion()[1].p, 0.0, 1e-3);
  EXPECT_EQ(h.check.violations, 0);
}

}  // namespace
}  // namespace pwsim::hw
