#pragma once
// Training metrics of a circuit run: the figures a therapist scores a power-wheelchair drive
// by, from the run's trace (one TrainingTick per engine tick, dt apart). Pure; no allocation
// beyond the result's.
//
//   completion time   t of the tick at which the last gate of the route is passed (all gates in
//                     order, circuit.h); none when the route was not completed.
//   route deviation   d_k = distance of O_V to the route polyline (the driver's path when the
//                     circuit has one, else start -> gate midpoints in order): mean, RMS, max.
//   contacts          wall/obstacle contacts begun during the run (count) and their approach
//                     speeds (mean, max) [m/s], time spent in contact.
//   clearance         c_k = the largest margin m with the footprint grown by m free of every wall
//                     and obstacle (circuit.h FootprintHit), found by bisection on [0, 2 m] to
//                     2 m / 2^12 ≈ 0.5 mm (0 in contact; ≥ 2 m reported as 2 m): min and when,
//                     and the time spent closer than 0.1 m.
//   joystick          a command begins when the deflection leaves the neutral zone
//                     (|f| ≤ 0.1 and |t| ≤ 0.1); a reversal is a sign change of f (or of t)
//                     between ±0.1 (the neutral zone in between ignored): counts of each.
//   head jerk         j_k = (p_k - 3 p_{k-h} + 3 p_{k-2h} - p_{k-3h}) / (h dt)³ of the head position
//                     (third backward difference over steps of h = round(50 ms / dt) ticks, at
//                     least 1: the jerk of the motion a person feels, below ~10 Hz, not the
//                     model's tick-to-tick chatter, which a 1 ms stencil amplifies by 10⁹),
//                     |j_k|: RMS, 95th percentile, max [m/s³].
//   near-tips         episodes (rising edges) on the anti-tip wheels; tip-overs: episodes with
//                     the centre of pressure outside the support polygon; lift-offs: episodes
//                     with a ground wheel unloaded (lift_off_count > 0), and their total time.

#include <array>
#include <optional>
#include <vector>

#include "engine/circuit.h"
#include "engine/full_chair.h"

namespace pwsim {

/// What the metrics need of one tick (a full sample is ~2 kB; a live drive keeps these).
struct TrainingTick {
  double t{0.0};                      ///< [s]
  double x{0.0}, y{0.0}, yaw{0.0};    ///< O_V in W [m, rad]
  double forward{0.0}, turn{0.0};     ///< joystick deflection applied [-1, 1]
  std::array<double, 3> head{};       ///< head (vestibular point) position in W [m]
  bool in_contact{false};
  int contact_events{0};
  double last_contact_speed{0.0};     ///< [m/s]
  int gates_passed{0};
  int lift_off_count{0};
  bool tip_over{false};
  bool on_anti_tip{false};
};

/// The tick of `sample` at time t [s] with the head at `head_W` (mca::PointOnBody of the pose).
TrainingTick TrainingTickOf(const FullChairSample& sample, double t, const std::array<double, 3>& head_W);

struct Stats {
  double mean{0.0}, rms{0.0}, max{0.0};
};

struct TrainingMetrics {
  double duration_s{0.0};
  int gates_passed{0}, gates_total{0};
  std::optional<double> completion_time_s;
  bool has_route{false};
  Stats route_deviation_m;
  int contacts{0};
  double contact_speed_mean_mps{0.0}, contact_speed_max_mps{0.0};
  double contact_time_s{0.0};
  double clearance_min_m{0.0};
  double clearance_min_t_s{0.0};
  double time_closer_than_0_1_m_s{0.0};
  int joystick_commands{0};
  int forward_reversals{0}, turn_reversals{0};
  double head_jerk_rms_mps3{0.0}, head_jerk_p95_mps3{0.0}, head_jerk_max_mps3{0.0};
  int near_tips{0}, tip_overs{0}, lift_offs{0};
  double lift_off_time_s{0.0};
};

inline constexpr double kJoystickNeutral = 0.1;   ///< neutral zone of |deflection| [-]
inline constexpr double kClearanceCap = 2.0;      ///< clearance search range [m]
inline constexpr double kCloseClearance = 0.1;    ///< "close" [m]
inline constexpr double kJerkStep = 0.05;         ///< stencil step of the head jerk [s]

/// The route the deviation is measured from (see above); fewer than 2 points: none.
std::vector<Point2> TrainingRoute(const CircuitSpec& circuit);

/// The clearance c of a chair at `pose` (see above) [m].
double Clearance(const CircuitSpec& circuit, const PlanarState& pose);

/// The metrics of a run. @pre dt > 0; trace non-empty.
TrainingMetrics ComputeTrainingMetrics(const CircuitSpec& circuit, const std::vector<TrainingTick>& trace, double dt);

}  // namespace pwsim
