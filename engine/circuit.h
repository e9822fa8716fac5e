#pragma once
// Circuits: the full-DoF chair driven by a joystick through a room or circuit (pwsim-scene/1,
// `circuit:` section; docs/circuits.md). Walls, obstacles, the floor height map, a route of
// gates, where the joystick comes from (a time table, a recorded CSV, or a closed-loop driver
// that follows a path at a speed), and the runner that steps the chair tick by tick.
//
// Contacts. The chair's footprint is a rectangle in V; a tick whose new pose would overlap a
// wall (a segment with thickness) or an obstacle (circle or oriented box) is not taken as it
// was. With n the contact's normal (out of the wall, toward the footprint's centre; round a
// wall's end or a circle from the nearest point; a box's face) and u O_V's velocity over the
// tick, u_n = u·n < 0 toward the wall and u_t = u·t along it, the wall takes u_n (an inelastic
// impact) and, by Coulomb friction μ_w (wall_friction), μ_w |u_n| from |u_t|:
//   u_t' = sgn(u_t) max(0, |u_t| − μ_w |u_n|),
// so a chair driven into a wall at an angle of incidence α (from the normal) slides along it
// when tan α > μ_w and stops otherwise. Sliding, O_V moves by u_t' dt along the wall at the
// heading it had (its tyres scrubbing sideways: the wall's push beats their grip; ω = 0) while
// its drive wheels keep their speed v (they slip): pushed on at v it slides at
// v (sin α − μ_w cos α); stopped (or when the slid pose would overlap something), the pose
// stays and v, ω become 0. A contact is
// counted once when it begins, with its approach speed |u_n|, and lasts until the chair is
// kContactReleaseGap clear again (pushing on at the wall is one contact). The chair never
// passes through: a tick moves it by at most v_max dt (2.4 mm at 2.4 m/s, 1 kHz), far less than
// any wall's thickness (>= 0.02 m, validated).
//
// Gates. A gate is a segment from its left post to its right post; it is passed when O_V's
// path over one tick crosses it. Gates count in order: `gates_passed` is the number passed.
//
// Closed-loop driver (pure pursuit on the joystick). At the path point a look-ahead L ahead of
// the nearest point, with α the bearing of that point in V:
//   κ = 2 sin α / L,   v_ref = min(v_path, √(a_dec s_left)) · clamp(cos α, 0.2, 1)
//   shaped f = (v_ref + k_s (v_ref - v)) / v_fwd,   shaped t = κ max(v, v_ref/2) / (ω_max(v_ref) G_t)
// and the deflections are the controller's shaping inverted (deadband and curve), clamped to
// [0, 1] forward and [-1, 1] turn: the driver knows the chair it drives. At the path's end the
// joystick is released.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/controller_profile.h"
#include "engine/floor_map.h"
#include "engine/full_chair.h"
#include "engine/yaml_reader.h"

namespace pwsim {

struct Point2 {
  double x{0.0}, y{0.0};  ///< [m] in W
};

struct Wall {
  Point2 from, to;          ///< centreline [m]
  double thickness{0.1};    ///< [m] >= 0.02
  std::string name;
};

struct Obstacle {
  enum class Shape { kCircle, kBox };
  Shape shape{Shape::kCircle};
  Point2 centre;            ///< [m]
  double radius{0.2};       ///< circle [m]
  double half_length{0.2};  ///< box, along its yaw [m]
  double half_width{0.2};   ///< box, across [m]
  double yaw{0.0};          ///< box [rad]
  double height{0.8};       ///< [m] (rendering)
  std::string name;
};

struct Gate {
  std::string name;
  Point2 left, right;       ///< posts [m]
};

/// Where the joystick comes from.
struct JoystickSource {
  enum class Kind { kTable, kRecorded, kDriver };
  Kind kind{Kind::kTable};
  // kTable and kRecorded: knots (t, f, t_turn), rising t; linear between, held at the ends.
  std::vector<double> t, forward, turn;
  bool hold{false};                       ///< stepwise instead of linear
  std::filesystem::path recorded_file;    ///< kRecorded
  // kDriver
  std::vector<Point2> path;               ///< polyline to follow [m]
  double speed{0.8};                      ///< v_path [m/s]
  double lookahead{0.6};                  ///< L [m]
  double speed_gain{1.0};                 ///< k_s [-]
  double end_time{0.0};                   ///< last knot time (tables) [s]

  /// Table deflection at time t [s] (kTable, kRecorded).
  JoystickInput At(double time) const;
};

/// Pure-pursuit driver state (kDriver).
struct DriverState {
  std::size_t segment{0};   ///< nearest path segment so far (never goes back)
  double progress{0.0};     ///< [m] along the path
  bool finished{false};     ///< reached the path's end: joystick released
};

/// The driver's deflection for the chair's current sample. No allocation.
JoystickInput DriveAlongPath(const JoystickSource& source, const ControllerProfile& profile,
                             DriverState& state, const FullChairSample& sample);

struct CircuitSpec {
  double duration{20.0};              ///< [s]
  PlanarState start;                  ///< pose at t = 0 (speeds 0)
  double start_caster_angle{0.0};     ///< δ_0 [rad] of every caster
  PlanarLayout layout;
  RollTorqueParams roll_torque;
  FloorMap floor;
  std::vector<Wall> walls;
  std::vector<Obstacle> obstacles;
  std::vector<Gate> gates;
  JoystickSource joystick;
  double wall_friction{0.4};          ///< μ_w [-] between the chair's footprint and walls, obstacles
};

/// Reads the `circuit:` section of a scene for `chair` carrying `load_kg`. Overlapping walls,
/// a route whose gate or driver path crosses a wall, a floor with holes or NaN, a joystick file
/// with NaN or deflections outside [-1, 1], a profile with negative accelerations: errors naming
/// file, line, field and what was expected. @throws InputError.
CircuitSpec ParseCircuit(YamlMap& map, const Chair& chair, double load_kg);

/// Reads a recorded joystick CSV: header `t_s,forward,turn` (any order), rising t_s, every
/// deflection finite and in [-1, 1]. @throws InputError naming file, line and column.
JoystickSource ReadRecordedJoystick(const std::filesystem::path& file);

/// Does the footprint of a chair at `pose` (layout's rectangle grown by `margin` [m] on every
/// side) overlap a wall or obstacle? Returns the index of the first one hit (walls first, then
/// obstacles offset by walls.size()), or -1.
int FootprintHit(const CircuitSpec& circuit, const PlanarState& pose, double margin = 0.0);

/// The unit normal of the contact with wall or obstacle `hit` (FootprintHit's index) of a chair
/// at `pose`: out of the thing hit, toward the footprint's centre (header, Contacts).
Point2 ContactNormal(const CircuitSpec& circuit, int hit, const PlanarState& pose);

/// Distance from p to the segment a-b [m] (to a when a = b).
double PointSegmentDistance(Point2 p, Point2 a, Point2 b);

/// A contact ends when the chair is this far clear of everything it touched [m].
inline constexpr double kContactReleaseGap = 0.01;

/// Plausibility bound on the occupant's head specific force over a circuit: how far
/// f_H = R_HWᵀ (a_H − g_W) may depart from its rest value (0, 0, g) given the floor, the chair
/// and the speeds driven. Derived link by link, each a worst case within two stated
/// assumptions: (a) floor edges meet one wheel row at a time (rows further apart than a climb,
/// √(2Rh − h²)), and (b) an edge is a step of the contact's vertical speed (the disc's first
/// touch) that then decays along the arc, so each linear link passes it with the peak of its
/// step response (its overshoot), not its L1 norm:
///  1. wheel speed over the floor v_w = v_peak + ω_peak ρ (ρ: the farthest contact from D);
///  2. the steepest envelope under a wheel of radius R: for a bump of height h tapered over r,
///     S = min(h / r, tan β), tan β = √(2Rh − h²) / (R − h) the slope at which the disc first
///     touches the edge (∞ for h >= R: a wall, or for a point contact on a sharp step); a
///     plane's grade plus its taper's rise over r; a profile's or grid's steepest piece; bumps
///     taken one at a time (summed where they overlap), planes, profile and grid added;
///  3. the contact's vertical speed through the tyre, V = max(N_t v_w S, √(2 g h_max)), N_t the
///     tyre's rate overshoot, the second term a free fall off the highest bump where
///     v_w² / R > g;
///  4. the GM's rates with one row on an edge: Ż_GM <= α_i V_i, θ̇_GM <= Σ_j β_ij V_i / (Δx_ij cos),
///     φ̇_GM <= |γ_i| V_i / (w_i cos) (cos of the steepest asin argument, G + h_max / Δx), the
///     largest row;
///  5. each LM axis (J, C, K) with step peaks: accel <= (max |ẍ| per unit step of ẏ) rate
///     (C/J at the step), rate <= overshoot × rate; its torque deviation ΔΓ likewise
///     (1/J at the step); ΔΓ_θ = |per_accel| a_x, ΔΓ_φ = M d (a_y + g sin φ_floor);
///  6. the planar motion: a_x <= μ g + g G + (f_c + f_r) g + |e| ω², a_y <= v ω + |x_D| ω̇,
///     ω̇ <= μ M g b / I_D (both drive wheels at their grip, opposite);
///  7. the head at r = |p_VH| (its horizontal part r_h): |a_H| <= |a_O| + |Z̈_M|
///     + r (|φ̈| + |θ̈| + φ̇² + θ̇² + ω²) + r_h ω̇, plus the tilt's share of gravity
///     g (φ_max + θ_max), the tilts from the floor (bump height over track and wheelbase, grade)
///     times the axes' overshoot.
/// A wall contact is a rigid impact (the normal speed lost within a tick, an impulse): the bound
/// holds away from wall contacts, whose approach speeds are reported on their own.
struct HeadForceBound {
  double wheel_speed{0.0};                    ///< v_w [m/s]
  std::vector<double> envelope_slope;         ///< S per wheel row [-]
  std::vector<double> contact_rate;           ///< V per wheel row [m/s]
  double gm_z_rate{0.0}, gm_pitch_rate{0.0}, gm_roll_rate{0.0};  ///< [m/s], [rad/s]
  double heave_accel{0.0};                    ///< |Z̈_M| [m/s²]
  double pitch_accel{0.0}, roll_accel{0.0};   ///< [rad/s²]
  double pitch_rate{0.0}, roll_rate{0.0};     ///< [rad/s]
  double planar_accel{0.0};                   ///< |a_O| in the plane [m/s²]
  double yaw_accel{0.0};                      ///< ω̇ [rad/s²]
  double tilt{0.0};                           ///< φ_max + θ_max [rad]
  double total{0.0};                          ///< bound on |f_H − (0, 0, g)| [m/s²]
};

/// The bound for `circuit` driven with the chair at most at `peak_speed` [m/s] and
/// `peak_yaw_rate` [rad/s] (a run's own peaks, or the controller's maxima). Infinite where a
/// floor feature is a step at least as high as a wheel's radius, or a sharp step taken by a
/// point contact (rolling_envelope false).
HeadForceBound ComputeHeadForceBound(const Chair& chair, const CircuitSpec& circuit, double load_kg,
                                     PitchTorqueParams pitch_torque, const std::array<double, 3>& head_offset,
                                     double peak_speed, double peak_yaw_rate);

/// Runs one circuit on the clock: sample 0 is the start, then one sample per tick.
class CircuitRunner {
 public:
  CircuitRunner(const Chair& chair, const CircuitSpec& circuit, double load_kg, double dt,
                PitchTorqueParams pitch_torque = {});
  const FullChairSample& Start();
  /// One tick at time t = tick · dt (the joystick sampled at the tick's start).
  const FullChairSample& Advance(double time);
  /// One tick with the joystick given from outside (a live drive: `pwsim drive`); walls,
  /// contacts and gates as in Advance. No allocation.
  const FullChairSample& AdvanceWith(const JoystickInput& joystick);
  const FullChairSample& sample() const { return simulator_.sample(); }
  const FullChairSimulator& simulator() const { return simulator_; }

 private:
  const CircuitSpec& circuit_;
  FullChairSimulator simulator_;
  DriverState driver_;
  bool in_contact_{false};
  int contact_events_{0};
  double last_contact_speed_{0.0};
  int gates_passed_{0};
};

}  // namespace pwsim
