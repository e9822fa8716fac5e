#include "engine/training_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/check.h"

namespace pwsim {

TrainingTick TrainingTickOf(const FullChairSample& s, double t, const std::array<double, 3>& head_W) {
  TrainingTick k;
  k.t = t;
  k.x = s.planar.x;
  k.y = s.planar.y;
  k.yaw = s.planar.yaw;
  k.forward = s.joystick.forward;
  k.turn = s.joystick.turn;
  k.head = head_W;
  k.in_contact = s.in_contact;
  k.contact_events = s.contact_events;
  k.last_contact_speed = s.last_contact_speed;
  k.gates_passed = s.gates_passed;
  k.lift_off_count = s.lift_off_count;
  k.tip_over = s.tip_over;
  k.on_anti_tip = s.on_anti_tip;
  return k;
}

std::vector<Point2> TrainingRoute(const CircuitSpec& circuit) {
  if (circuit.joystick.kind == JoystickSource::Kind::kDriver && circuit.joystick.path.size() >= 2)
    return circuit.joystick.path;
  std::vector<Point2> route{{circuit.start.x, circuit.start.y}};
  for (const Gate& g : circuit.gates) route.push_back({0.5 * (g.left.x + g.right.x), 0.5 * (g.left.y + g.right.y)});
  if (route.size() < 2) route.clear();
  return route;
}

double Clearance(const CircuitSpec& circuit, const PlanarState& pose) {
  if (FootprintHit(circuit, pose) >= 0) return 0.0;
  if (FootprintHit(circuit, pose, kClearanceCap) < 0) return kClearanceCap;
  double free = 0.0, hit = kClearanceCap;  // invariant: margin `free` clear, `hit` touches
  for (int i = 0; i < 12; ++i) {
    const double mid = 0.5 * (free + hit);
    (FootprintHit(circuit, pose, mid) < 0 ? free : hit) = mid;
  }
  return free;
}

namespace {

double RouteDistance(const std::vector<Point2>& route, Point2 p) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < route.size(); ++i) d = std::min(d, PointSegmentDistance(p, route[i], route[i + 1]));
  return d;
}

/// Sign of a deflection outside the neutral zone (0 inside).
int Side(double deflection) { return deflection > kJoystickNeutral ? 1 : deflection < -kJoystickNeutral ? -1 : 0; }

}  // namespace

TrainingMetrics ComputeTrainingMetrics(const CircuitSpec& circuit, const std::vector<TrainingTick>& trace, double dt) {
  PWSIM_DEMAND(dt > 0.0 && !trace.empty());
  TrainingMetrics m;
  const TrainingTick& first = trace.front();
  const TrainingTick& last = trace.back();
  m.duration_s = last.t - first.t;
  m.gates_total = static_cast<int>(circuit.gates.size());
  m.gates_passed = last.gates_passed;

  const std::vector<Point2> route = TrainingRoute(circuit);
  m.has_route = !route.empty();
  double deviation_sum = 0.0, deviation_sq = 0.0;
  double speed_sum = 0.0;
  int events = first.contact_events;
  double clearance_min = std::numeric_limits<double>::infinity();
  int forward_side = Side(first.forward), turn_side = Side(first.turn);
  bool neutral = forward_side == 0 && turn_side == 0;
  bool anti_tip_before = first.on_anti_tip, tip_before = first.tip_over, lifted_before = first.lift_off_count > 0;
  const auto h = static_cast<std::size_t>(std::max(1L, std::lround(kJerkStep / dt)));
  const double step3 = std::pow(static_cast<double>(h) * dt, 3);
  std::vector<double> jerk;
  jerk.reserve(trace.size());
  for (std::size_t k = 0; k < trace.size(); ++k) {
    const TrainingTick& s = trace[k];
    if (!m.completion_time_s && m.gates_total > 0 && s.gates_passed >= m.gates_total) m.completion_time_s = s.t;
    if (m.has_route) {
      const double d = RouteDistance(route, {s.x, s.y});
      deviation_sum += d;
      deviation_sq += d * d;
      m.route_deviation_m.max = std::max(m.route_deviation_m.max, d);
    }
    if (s.contact_events > events) {
      m.contacts += s.contact_events - events;
      speed_sum += s.last_contact_speed;
      m.contact_speed_max_mps = std::max(m.contact_speed_max_mps, s.last_contact_speed);
      events = s.contact_events;
    }
    if (s.in_contact) m.contact_time_s += dt;
    const double c = s.in_contact ? 0.0 : Clearance(circuit, {s.x, s.y, s.yaw, 0.0, 0.0});
    if (c < clearance_min) {
      clearance_min = c;
      m.clearance_min_t_s = s.t;
    }
    if (c < kCloseClearance) m.time_closer_than_0_1_m_s += dt;
    // joystick
    const int f = Side(s.forward), t = Side(s.turn);
    if (f != 0 && forward_side != 0 && f != forward_side) ++m.forward_reversals;
    if (t != 0 && turn_side != 0 && t != turn_side) ++m.turn_reversals;
    if (f != 0) forward_side = f;
    if (t != 0) turn_side = t;
    const bool now_neutral = std::abs(s.forward) <= kJoystickNeutral && std::abs(s.turn) <= kJoystickNeutral;
    if (neutral && !now_neutral) ++m.joystick_commands;
    neutral = now_neutral;
    // head jerk
    if (k >= 3 * h) {
      double sq = 0.0;
      for (std::size_t i = 0; i < 3; ++i) {
        const double j =
            (s.head[i] - 3.0 * trace[k - h].head[i] + 3.0 * trace[k - 2 * h].head[i] - trace[k - 3 * h].head[i]) / step3;
        sq += j * j;
      }
      jerk.push_back(std::sqrt(sq));
    }
    // tips and lift-offs
    m.near_tips += s.on_anti_tip && !anti_tip_before ? 1 : 0;
    m.tip_overs += s.tip_over && !tip_before ? 1 : 0;
    const bool lifted = s.lift_off_count > 0;
    m.lift_offs += lifted && !lifted_before ? 1 : 0;
    if (lifted) m.lift_off_time_s += dt;
    anti_tip_before = s.on_anti_tip;
    tip_before = s.tip_over;
    lifted_before = lifted;
  }
  const auto n = static_cast<double>(trace.size());
  if (m.has_route) {
    m.route_deviation_m.mean = deviation_sum / n;
    m.route_deviation_m.rms = std::sqrt(deviation_sq / n);
  }
  if (m.contacts > 0) m.contact_speed_mean_mps = speed_sum / m.contacts;
  m.clearance_min_m = clearance_min;
  if (!jerk.empty()) {
    double sq = 0.0;
    for (double j : jerk) sq += j * j;
    m.head_jerk_rms_mps3 = std::sqrt(sq / static_cast<double>(jerk.size()));
    m.head_jerk_max_mps3 = *std::max_element(jerk.begin(), jerk.end());
    // 95th percentile: the value at rank ceil(0.95 n) (nearest rank)
    const auto rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(jerk.size()))) - 1;
    std::nth_element(jerk.begin(), jerk.begin() + static_cast<std::ptrdiff_t>(rank), jerk.end());
    m.head_jerk_p95_mps3 = jerk[rank];
  }
  return m;
}

}  // namespace pwsim
