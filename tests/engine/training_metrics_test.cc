#include "engine/training_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pwsim {
namespace {

/// A circuit with a footprint of [-0.5, 0.5] x [-0.3, 0.3] in V and nothing else.
CircuitSpec EmptyCircuit() {
  CircuitSpec c;
  c.layout.footprint_front = 0.5;
  c.layout.footprint_rear = -0.5;
  c.layout.footprint_half_width = 0.3;
  return c;
}

// Tests the clearance against distances worked out by hand: a wall whose face is at x = 1.9
// (centreline 2, 0.2 thick) and a circle of radius 0.5; the footprint's front edge, then its
// side (turned by 90°), then its left edge facing the circle.
TEST(TrainingMetricsTest, ClearanceIsTheGapBetweenFootprintAndTheNearestWallOrObstacle) {
  CircuitSpec c = EmptyCircuit();
  c.walls.push_back({{2.0, -5.0}, {2.0, 5.0}, 0.2, "wall"});
  // front edge at 1.5: 0.4 to the wall's face
  EXPECT_NEAR(Clearance(c, {1.0, 0.0, 0.0, 0.0, 0.0}), 0.4, 2.0 / 4096);
  EXPECT_LE(Clearance(c, {1.0, 0.0, 0.0, 0.0, 0.0}), 0.4);  // never more than the true gap
  // turned left by 90°: the right side (half width 0.3) faces the wall, at 1.3
  EXPECT_NEAR(Clearance(c, {1.0, 0.0, std::acos(-1.0) / 2, 0.0, 0.0}), 0.6, 2.0 / 4096);
  EXPECT_EQ(Clearance(c, {1.5, 0.0, 0.0, 0.0, 0.0}), 0.0);            // overlapping: 0
  EXPECT_EQ(Clearance(c, {-3.0, 0.0, 0.0, 0.0, 0.0}), kClearanceCap);  // 4.4 m away: the cap
  Obstacle post;
  post.centre = {-3.0, 1.5};
  post.radius = 0.5;
  c.obstacles.push_back(post);
  // left edge at y = 0.3, the post's rim at 1.0: 0.7 (the wall is 4.4 m away)
  EXPECT_NEAR(Clearance(c, {-3.0, 0.0, 0.0, 0.0, 0.0}), 0.7, 2.0 / 4096);
}

// Tests every metric on a six-tick trace worked out by hand (dt = 0.1 s).
TEST(TrainingMetricsTest, SixTickTraceGivesTheHandComputedFigures) {
  CircuitSpec c = EmptyCircuit();  // no walls: clearance is the cap but where in contact
  c.gates.push_back({"g1", {2.0, 1.0}, {2.0, -1.0}});  // midpoint (2, 0)
  c.gates.push_back({"g2", {1.0, 2.0}, {3.0, 2.0}});   // midpoint (2, 2)
  const std::vector<Point2> route = TrainingRoute(c);  // start (0, 0) -> (2, 0) -> (2, 2)
  ASSERT_EQ(route.size(), 3u);
  EXPECT_EQ(route[1].x, 2.0);
  EXPECT_EQ(route[2].y, 2.0);

  const double dt = 0.1;
  const double xs[] = {0.0, 1.0, 2.0, 2.3, 2.0, 1.9};
  const double ys[] = {0.1, -0.2, 0.0, 1.0, 2.0, 2.5};
  const double forward[] = {0.0, 0.5, 0.05, -0.5, -0.6, 0.3};
  const double turn[] = {0.0, 0.0, 0.0, 0.0, 0.2, -0.2};
  const bool in_contact[] = {false, true, true, false, true, false};
  const int events[] = {0, 1, 1, 1, 2, 2};
  const double contact_speed[] = {0.0, 0.5, 0.5, 0.5, 0.3, 0.3};
  const int gates[] = {0, 0, 1, 1, 2, 2};
  const int lifted[] = {0, 1, 1, 0, 1, 0};
  const bool anti_tip[] = {false, false, true, true, false, true};
  const bool tip[] = {false, false, false, true, false, false};
  std::vector<TrainingTick> trace;
  for (int k = 0; k < 6; ++k) {
    TrainingTick t;
    t.t = k * dt;
    t.x = xs[k];
    t.y = ys[k];
    t.forward = forward[k];
    t.turn = turn[k];
    t.head = {t.t * t.t * t.t, 0.0, 2.0 * t.t * t.t};  // x = t³: jerk 6; z = 2 t²: jerk 0
    t.in_contact = in_contact[k];
    t.contact_events = events[k];
    t.last_contact_speed = contact_speed[k];
    t.gates_passed = gates[k];
    t.lift_off_count = lifted[k];
    t.on_anti_tip = anti_tip[k];
    t.tip_over = tip[k];
    trace.push_back(t);
  }
  const TrainingMetrics m = ComputeTrainingMetrics(c, trace, dt);
  EXPECT_DOUBLE_EQ(m.duration_s, 0.5);
  EXPECT_EQ(m.gates_passed, 2);
  EXPECT_EQ(m.gates_total, 2);
  ASSERT_TRUE(m.completion_time_s.has_value());
  EXPECT_DOUBLE_EQ(*m.completion_time_s, 0.4);
  // distances to the route: 0.1, 0.2, 0, 0.3, 0, |(1.9, 2.5) - (2, 2)| = √0.26
  const double d[] = {0.1, 0.2, 0.0, 0.3, 0.0, std::sqrt(0.26)};
  double sum = 0.0, sq = 0.0;
  for (double v : d) {
    sum += v;
    sq += v * v;
  }
  EXPECT_TRUE(m.has_route);
  EXPECT_NEAR(m.route_deviation_m.mean, sum / 6, 1e-12);
  EXPECT_NEAR(m.route_deviation_m.rms, std::sqrt(sq / 6), 1e-12);
  EXPECT_NEAR(m.route_deviation_m.max, std::sqrt(0.26), 1e-12);
  EXPECT_EQ(m.contacts, 2);
  EXPECT_DOUBLE_EQ(m.contact_speed_mean_mps, 0.4);
  EXPECT_DOUBLE_EQ(m.contact_speed_max_mps, 0.5);
  EXPECT_NEAR(m.contact_time_s, 0.3, 1e-12);
  EXPECT_EQ(m.clearance_min_m, 0.0);
  EXPECT_DOUBLE_EQ(m.clearance_min_t_s, 0.1);  // the first tick in contact
  EXPECT_NEAR(m.time_closer_than_0_1_m_s, 0.3, 1e-12);
  // neutral, out (1), back to neutral (|0.05| ≤ 0.1), out (2), held, held
  EXPECT_EQ(m.joystick_commands, 2);
  // forward: + then - (1) then + (2), the neutral tick in between ignored; turn: + then - (1)
  EXPECT_EQ(m.forward_reversals, 2);
  EXPECT_EQ(m.turn_reversals, 1);
  // x = t³ has the third difference 6 (h dt)³ exactly (up to rounding; h = 1 at dt = 0.1 s);
  // z = 2 t² none
  EXPECT_NEAR(m.head_jerk_rms_mps3, 6.0, 1e-9);
  EXPECT_NEAR(m.head_jerk_p95_mps3, 6.0, 1e-9);
  EXPECT_NEAR(m.head_jerk_max_mps3, 6.0, 1e-9);
  EXPECT_EQ(m.near_tips, 2);
  EXPECT_EQ(m.tip_overs, 1);
  EXPECT_EQ(m.lift_offs, 2);
  EXPECT_NEAR(m.lift_off_time_s, 0.3, 1e-12);
}

// Tests the head jerk's 50 ms stencil at 1 kHz: a cubic's jerk exactly, a 1 kHz ripple of
// ±1 µm on it (whose 1 ms third difference would be 8e-6 / 1e-9 = 8000 m/s³) barely.
TEST(TrainingMetricsTest, HeadJerkIsTakenOver50MsSteps) {
  const CircuitSpec c = EmptyCircuit();
  const double dt = 1e-3;
  std::vector<TrainingTick> trace(1001);
  for (std::size_t k = 0; k < trace.size(); ++k) {
    const double t = static_cast<double>(k) * dt;
    trace[k].t = t;
    trace[k].head = {0.5 * t * t * t, 0.0, 0.0};  // jerk 3 m/s³
  }
  TrainingMetrics m = ComputeTrainingMetrics(c, trace, dt);
  EXPECT_NEAR(m.head_jerk_rms_mps3, 3.0, 1e-6);
  EXPECT_NEAR(m.head_jerk_max_mps3, 3.0, 1e-6);
  for (std::size_t k = 0; k < trace.size(); ++k) trace[k].head[0] += (k % 2 == 0 ? 1e-6 : -1e-6);
  m = ComputeTrainingMetrics(c, trace, dt);
  // steps of 50 ticks keep the ripple's parity: it cancels in the stencil (1 - 3 + 3 - 1 = 0)
  EXPECT_NEAR(m.head_jerk_max_mps3, 3.0, 1e-3);
}

// Tests that a run that misses a gate is not completed, and that a circuit without gates or a
// driver path has no route.
TEST(TrainingMetricsTest, IncompleteRunsAndCircuitsWithoutARoute) {
  CircuitSpec c = EmptyCircuit();
  std::vector<TrainingTick> trace(3);
  for (int k = 0; k < 3; ++k) trace[static_cast<std::size_t>(k)].t = k * 0.01;
  TrainingMetrics m = ComputeTrainingMetrics(c, trace, 0.01);
  EXPECT_FALSE(m.has_route);
  EXPECT_FALSE(m.completion_time_s.has_value());
  EXPECT_EQ(m.head_jerk_max_mps3, 0.0);  // fewer than 4 ticks: no jerk
  c.gates.push_back({"g", {1.0, 1.0}, {1.0, -1.0}});
  m = ComputeTrainingMetrics(c, trace, 0.01);
  EXPECT_TRUE(m.has_route);
  EXPECT_FALSE(m.completion_time_s.has_value());
  EXPECT_EQ(m.gates_passed, 0);
}

}  // namespace
}  // namespace pwsim
