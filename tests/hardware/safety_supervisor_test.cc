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
  std::array<std::vector<double>, 2> p;
  int violations = 0;
  double worst_jerk_ratio = 0.0;

  void Add(const std::array<double, 2>& out) {
    for (std::size_t i = 0; i < 2; ++i) {
      auto& x = p[i];
      x.push_back(out[i]);
      const AxisLimits& l = c.axes[i];
      const double dt = c.dt;
      const std::size_t n = x.size();
      if (std::abs(x[n - 1]) > l.workspace + 1e-12) ++violations;
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

  Harness() {
    in.drives_ready = true;
    in.setpoint = std::array<double, 2>{0.0, 0.0};
  }
  std::array<double, 2> Step() {
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
      in.setpoint = std::array<double, 2>{0.2 * std::sin(0.8 * t), 0.3 * std::sin(1.3 * t)};
      Step();
    }
  }
};

TEST(SafetySupervisor, DefaultConfigIsValid) {
  EXPECT_EQ(ValidateSafetyConfig(SafetyConfig{}), "");
  SafetyConfig bad;
  bad.axes[1].workspace = 0.7;
  EXPECT_NE(ValidateSafetyConfig(bad).find("rail.workspace"), std::string::npos);
}

TEST(SafetySupervisor, PassesAFeasibleStreamThroughUnchanged) {
  Harness h;
  h.Step();
  ASSERT_EQ(h.sup.state(), SupervisorState::kRunning);
  for (int k = 0; k < 2000; ++k) {
    const double t = k * 0.004;
    const std::array<double, 2> sp{0.2 * (1 - std::cos(0.8 * t)) / 2, 0.3 * (1 - std::cos(1.3 * t)) / 2};
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
  h.in.setpoint = std::array<double, 2>{std::numeric_limits<double>::quiet_NaN(), 0.0};
  h.Step();
  h.in.setpoint = std::array<double, 2>{0.0, std::numeric_limits<double>::infinity()};
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
  h.in.setpoint = std::array<double, 2>{5.0, -9.0};  // far outside, a huge step
  for (int k = 0; k < 1000; ++k) h.Step();
  EXPECT_GT(h.sup.counters().clamped, 0U);
  EXPECT_GT(h.sup.counters().rate_limited, 0U);
  EXPECT_NEAR(h.sup.motion()[1].p, -h.sup.config().axes[1].workspace, 1e-3);
  EXPECT_NEAR(h.sup.motion()[0].p, h.sup.config().axes[0].workspace, 1e-3);
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
      {"NaN stream", [](Harness& h) { h.in.setpoint = std::array<double, 2>{NAN, NAN}; },
       SupervisorState::kSoftStop, 4},
      {"heartbeat lost", [](Harness& h) { h.in.heartbeats_ok = false; }, SupervisorState::kSoftStop, 1},
      {"TPDO stale", [](Harness& h) { h.in.tpdos_fresh = false; }, SupervisorState::kSoftStop, 1},
      {"HMD stale", [](Harness& h) { h.in.hmd_ok = false; }, SupervisorState::kSoftStop, 1},
      {"stop request", [](Harness& h) { h.in.stop_requested = true; }, SupervisorState::kSoftStop, 1},
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
      h.in.setpoint = std::array<double, 2>{0.1, 0.1};
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
    std::array<double, 2> sp{0.0, 0.0};
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
  in.setpoint = std::array<double, 2>{0.3, 0.3};
  EXPECT_EQ(sup.Step(0, in), in.measured);
  EXPECT_EQ(sup.state(), SupervisorState::kIdle);
  in.drives_ready = true;
  const auto out = sup.Step(1, in);
  EXPECT_EQ(sup.state(), SupervisorState::kRunning);
  EXPECT_NEAR(out[1], 0.02, 1e-3);  // starts from the measured pose, rate-limited
}

}  // namespace
}  // namespace pwsim::hw
