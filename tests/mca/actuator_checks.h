#pragma once
// The tests' own check of a command stream against the actuators: positions by the mechanism's
// IK (Mechanism::Inverse, checked against closed forms in mechanism_test), rates and
// accelerations as their differences per tick, recomputed here (not mca::EvaluateActuators,
// which is under test itself).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mca/mechanism.h"
#include "mca/platform.h"
#include "mca/washout.h"

namespace pwsim::mca::test {

/// The worst use over a pose stream: distance beyond a stroke end [m | rad], and the largest
/// speed and acceleration as shares of their limits.
struct ActuatorUse {
  double beyond_stroke{0.0};
  double speed{0.0};
  double accel{0.0};
  bool ik_failed{false};
};

inline ActuatorUse MeasureActuatorUse(const Mechanism& m, const std::vector<DofArray>& poses, double dt) {
  ActuatorUse use;
  ActuatorVector q_prev = m.Neutral();
  ActuatorVector r_prev = ActuatorVector::Zero(m.actuator_count());
  for (const DofArray& pose : poses) {
    ActuatorVector q;
    if (!m.Inverse(pose, &q)) {
      use.ik_failed = true;
      continue;
    }
    for (int i = 0; i < m.actuator_count(); ++i) {
      const ActuatorLimits& lim = m.actuator(i).limits;
      use.beyond_stroke = std::max({use.beyond_stroke, q[i] - lim.max, lim.min - q[i]});
      const double r = (q[i] - q_prev[i]) / dt;
      use.speed = std::max(use.speed, std::abs(r) / lim.speed);
      use.accel = std::max(use.accel, std::abs(r - r_prev[i]) / dt / lim.accel);
      r_prev[i] = r;
    }
    q_prev = q;
  }
  return use;
}

inline std::vector<DofArray> Poses(const std::vector<McaCommand>& commands) {
  std::vector<DofArray> poses;
  poses.reserve(commands.size());
  for (const McaCommand& c : commands) poses.push_back(c.pose);
  return poses;
}

/// Every actuator inside its stroke, speed and acceleration over the stream (no slack), every
/// pose finite, and axes the mechanism does not move at 0.
inline void ExpectActuatorsWithinLimits(const PlatformSpec& platform, const std::vector<McaCommand>& commands,
                                        double dt, const std::string& what) {
  for (const McaCommand& c : commands) {
    for (Dof dof : kAllDofs) {
      const double v = c.pose[static_cast<std::size_t>(Index(dof))];
      ASSERT_TRUE(std::isfinite(v)) << what;
      if (!platform.mechanism.Moves(dof)) {
        ASSERT_EQ(v, 0.0) << what << " " << DofName(dof);
      }
    }
  }
  const ActuatorUse use = MeasureActuatorUse(platform.mechanism, Poses(commands), dt);
  EXPECT_FALSE(use.ik_failed) << what;
  // at or below the limits themselves: the limiter keeps 1e-9 of each free for rounding
  EXPECT_LE(use.beyond_stroke, 0.0) << what;
  EXPECT_LE(use.speed, 1.0) << what;
  EXPECT_LE(use.accel, 1.0) << what;
}

}  // namespace pwsim::mca::test
