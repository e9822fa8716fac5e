#pragma once
// The full-DoF power wheelchair: the planar motion (x, y, ψ; v, ω) of a non-holonomic
// differential-drive chair behind its controller, casters with swivel dynamics, load transfer
// per wheel, and the seed-000 vertical model (geometric model + lumped model) extended by roll,
// over a 2.5-D floor. The sagittal ChairSimulator (chair_simulator.h) stays the fast path of
// straight runs; this chair reproduces it bit for bit on a straight run (AdvanceAlong).
//
// Frames (docs/notation.md): W world (x along the start heading, y left, z up), V the chair
// at O_V (x forward, y left), ψ yaw (left positive), θ pitch nose-up, φ roll left side up.
//
// Planar dynamics. The drive wheels (left, right) sit at x_D in V, track b; they roll without
// slipping sideways, so the drive-axle midpoint D moves along V's x at v and O_V at
// (v, -ω x_D) in V. With the centre of mass at e = x_c - x_D ahead of D (Fierro & Lewis form):
//   m (v̇ - e ω²)            = F_L + F_R + Σ F_x,ext
//   (I_z + m e²) ω̇ + m e v ω = (F_R - F_L) b/2 + Σ M_z,ext(D)
//   ext: casters and anti-tip wheels (caster.h) at their contacts, rolling resistance of the
//        drive wheels -f_r N_i sgn(v_i), gravity along the floor m g_V,x and its yaw moment
//        about D, e m g_V,y (a cross-slope turns a chair whose mass is off its axle downhill).
// Drive wheel speeds v_L,R = v ∓ ω b/2 follow the controller's set-points (controller_profile.h)
// through each motor's speed loop with acceleration feed-forward and a torque limit:
//   F_i = clamp(m/2 (a*_i + k_v (v*_i - v_i) + k_I ∫(v*_i - v_i) dt), ±min(T_max / r_d, μ N_i))
// (k_v the speed-loop bandwidth, k_I = k_v²/4 its integral action, critically damped: the seed's
// hypothesis that the power module holds the programmed speed whatever the load, in steady
// state; the integral stops while the force is limited. In a transient a load such as caster
// drag still slows one wheel: the pull of a chair started with its casters across).
// Parking brakes: once the set-points are at rest (v* = ω* = 0 and not ramping) the power module
// brakes the drive wheels: F_L, F_R are the forces that stop v and ω within the step against
// every other force, each within the traction limit μ N_i (beyond it the chair slides and
// torque_limited is set); the loops' integrals are cleared.
// Integration: semi-implicit Euler (speeds from the forces at the step's start, then the pose
// at the midpoint heading), casters implicit in δ̇ (caster.h).
//
// Vertical model. Each wheel row i of the sagittal chair (front to rear) has a left and a right
// contact; Z_Oi is the mean of the two contact heights, and eq. (1)-(2) give Z_GM and θ_GM as in
// the sagittal model. Roll from the wheels' lateral spacing w_i:
//   φ_GM = Σ_i γ_i asin((Z_Oi,L - Z_Oi,R) / w_i)        (γ_i = α_i unless given)
// and the lumped model gains a roll axis beside heave and pitch (eq. 3):
//   J_x φ̈ + C_φ (φ̇ - φ̇_GM) + K_φ (φ - φ_GM) = Γ_φ,   Γ_φ = M d_CM (g sin φ + a_y)
//   J_x = J_x0 + d_CM² M,  Γ_θ as in the sagittal model (PitchTorqueParams).
// All three axes are discretised exactly (lumped_model.h) with Γ held over the step.
//
// Wheels over the floor. Each ground wheel of radius R (its row's sagittal wheel; the anti-tip
// wheels are points) meets the floor through its rolling envelope along its heading (floor_map.h,
// EnvelopeAt): a drive or fixed wheel along ψ, a caster along ψ - δ. Its tyre is a corner
// oscillator: the height u_i the GM reads follows the envelope h_i through a spring-damper of
// natural frequency ω_t = 2π / T_t and damping ratio ζ, written about its static deflection
// δ_s = g / ω_t² (e = h - u, ė = ḣ - u̇):
//   ü = max(ω_t² e + 2ζω_t ė, -g)   while e > -δ_s (the tyre pushes, never pulls),
//   ü = -g                          otherwise: the wheel has left the floor (airborne)
// so a corner follows the floor down no faster than g and lands again when it meets it
// (semi-implicit Euler; at rest e = ė = 0 and u = h exactly). T_t = 0: a rigid tyre, u = h.
// With rolling_envelope false both are off (point contacts, rigid tyres); AdvanceAlong always
// reads the floor at the points below the wheels, as the sagittal model does.
//
// Loads. Quasi-static, rigid chair on wheels whose suspension shares are k_i (α_i of the row by
// default, split evenly left/right): with F = M (g_V - a_V) applied at the centre of mass
// (x_c, 0, h = d_CM) the loads N_i = k_i (c_0 + c_1 x_i + c_2 y_i) satisfy
//   Σ N_i = -F_z,   Σ x_i N_i = x_c (-F_z) + h F_x,   Σ y_i N_i = h F_y.
// A load that reaches zero is reported (lift_off), never clipped; the centre of pressure
// (x_c + h F_x / (-F_z), h F_y / (-F_z)) outside the support polygon of the ground wheels
// (with the anti-tip wheels once it is behind the rearmost row) is a tip-over.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/caster.h"
#include "engine/chair.h"
#include "engine/chair_simulator.h"
#include "engine/controller_profile.h"
#include "engine/drive_profile.h"
#include "engine/floor_map.h"
#include "engine/geometric_model.h"
#include "engine/lumped_model.h"

namespace pwsim {

inline constexpr double kStandardGravity = 9.80665;  ///< [m/s^2]
/// Ground contacts a full chair may have: two per sagittal row plus two anti-tip wheels.
inline constexpr int kMaxContacts = 2 * kMaxWheels + 2;

enum class DriveLayout { kRear, kMid, kFront };
enum class WheelRole { kDrive, kCaster, kFixed };
const char* DriveLayoutName(DriveLayout layout);

/// One sagittal row of the chair seen from above.
struct WheelRow {
  WheelRole role{WheelRole::kCaster};
  double half_track{0.25};  ///< w_i / 2 [m], contacts at y = ±half_track
  double roll_weight{0.0};  ///< γ_i [-] of φ_GM
  double load_share{0.0};   ///< k_i [-] suspension share of the row (both wheels)
};

/// Anti-tip wheels: a pair behind (or ahead of) the chair, clear of the floor at rest.
struct AntiTip {
  bool present{false};
  double x{-0.55};        ///< [m] in V
  double half_track{0.2}; ///< [m]
  double clearance{0.05}; ///< [m] above the floor at rest
};

/// The planar layout that, with a sagittal Chair (mass, inertia, d_CM, wheels, gm, lm), makes
/// the full chair. Rows are the chair's wheels, front to rear, same count.
struct PlanarLayout {
  DriveLayout layout{DriveLayout::kMid};
  std::vector<WheelRow> rows;
  AntiTip anti_tip;
  CasterParams caster;
  double cm_x{0.0};               ///< x_c [m] centre of mass along V's x from O_V
  double yaw_inertia{12.0};       ///< I_z0 [kg m^2] empty chair about its centre of mass
  double roll_inertia{6.0};       ///< J_x0 [kg m^2] empty chair about its centre of mass
  double k_roll{1.5e4};           ///< K_φ [N m/rad]
  double c_roll{700.0};           ///< C_φ [N m s/rad]
  double drive_radius{0.17};      ///< r_d [m]
  double max_motor_torque{40.0};  ///< T_max [N m] per drive wheel
  double speed_loop_gain{8.0};    ///< k_v [1/s]
  double rolling_resistance{0.015}; ///< f_r [-] of the drive wheels
  double friction{0.8};           ///< μ [-] tyre-floor friction of the drive wheels
  bool rolling_envelope{true};    ///< wheels of radius R and tyres (false: point contacts)
  double drive_tyre_period{0.15}; ///< T_t [s] of a drive wheel's tyre mode (0: rigid)
  double caster_tyre_period{0.07};///< T_t [s] of a caster's or fixed wheel's tyre mode (0: rigid)
  double tyre_damping{0.3};       ///< ζ [-] of the tyre modes
  ControllerProfile controller;
  /// Footprint for wall contacts: a rectangle in V [m].
  double footprint_front{0.55}, footprint_rear{-0.55}, footprint_half_width{0.33};
};

/// The layout of a chair built from its sagittal wheels: the row with x closest to `drive_x`
/// drives (the others are casters), tracks of `track` [m] for every row, γ_i = k_i = α_i.
/// @pre chair.gm set.
PlanarLayout DefaultPlanarLayout(const Chair& chair, double track = 0.56);

/// Reads a layout mapping for `chair`: {drive: rear|mid|front, rows: [{half_track_m, role,
/// roll_weight, load_share}] (one per wheel, optional), anti_tip: {x_m, half_track_m,
/// clearance_m}, caster: {trail_m, swivel_inertia_kgm2, ...}, cm_x_m, yaw_inertia_kgm2,
/// roll_inertia_kgm2, k_roll, c_roll, drive_radius_m, max_motor_torque_nm, speed_loop_gain,
/// rolling_resistance, friction, rolling_envelope, tyres: {drive_period_s, caster_period_s,
/// damping}, footprint_m: [front, rear, half_width], controller: {...}}.
/// @throws InputError.
PlanarLayout ParsePlanarLayout(YamlMap& map, const Chair& chair);

/// Roll torque Γ_φ = constant + gravity_lever (g sin φ) + per_lateral_accel a_y [N m].
struct RollTorqueParams {
  double constant{0.0};           ///< [N m]
  double gravity_lever{0.0};      ///< [kg m] M d_CM for the rigid load; 0 switches it off
  double per_lateral_accel{0.0};  ///< [kg m] M d_CM for the rigid load
};

/// The planar state of the chair.
struct PlanarState {
  double x{0.0}, y{0.0};   ///< p_WV [m]
  double yaw{0.0};         ///< ψ [rad], unwrapped
  double v{0.0};           ///< forward speed of D (and O_V) along V's x [m/s]
  double yaw_rate{0.0};    ///< ω [rad/s]
  bool operator==(const PlanarState&) const = default;
};

/// One ground contact (drive, caster or anti-tip wheel) at one tick.
struct WheelContact {
  double x{0.0}, y{0.0};          ///< contact point below the wheel's centre in W [m]
  double z{0.0};                  ///< u: the contact height through the tyre, read by the GM [m]
  double floor_z{0.0};            ///< h: the floor's rolling envelope under the wheel [m]
  bool airborne{false};           ///< the tyre has left the floor (it pushes no more)
  double load{0.0};               ///< N_i [N]; ≤ 0 with lift_off set (never clipped)
  bool lift_off{false};
  double force_x{0.0};            ///< longitudinal ground force on the wheel in V [N]
  double force_y{0.0};            ///< lateral ground force on the wheel in V [N]
};

/// Everything known about the full chair at one tick.
struct FullChairSample {
  std::int64_t tick{0};
  // --- planar ---
  PlanarState planar;
  double lateral_speed{0.0};   ///< O_V along V's y [m/s] (= -ω x_D)
  double a_x{0.0}, a_y{0.0};   ///< acceleration of O_V in V over the last step [m/s^2]
  double yaw_accel{0.0};       ///< ω̇ [rad/s^2]
  double distance{0.0};        ///< path length travelled by O_V [m]
  JoystickInput joystick;      ///< deflection applied over the last step
  ControllerState controller;  ///< set-points over the last step
  std::array<double, 2> drive_force{};  ///< F_L, F_R [N]
  std::array<double, 2> speed_error_integral{};  ///< ∫(v*_i - v_i) dt of the speed loops [m]
  bool torque_limited{false};  ///< a motor at its torque or traction limit
  // --- vertical (the sagittal model's quantities, per row, plus roll) ---
  Longitudinal drive;                       ///< (distance, v, a_x): the sagittal view
  std::array<double, kMaxWheels> z_O{};     ///< Z_Oi [m] row means, wheel_count() used
  GeometricOutput gm;                       ///< Z_GM, θ_GM
  double roll_gm{0.0};                      ///< φ_GM [rad]
  double z_gm_rate{0.0}, pitch_gm_rate{0.0}, roll_gm_rate{0.0};  ///< over the last step
  LumpedState lm;                           ///< Z_M, θ_M and rates
  double roll{0.0}, roll_rate{0.0};         ///< φ_M [rad], φ̇_M [rad/s]
  LumpedAcceleration lm_acc;                ///< Z̈_M, θ̈_M
  double roll_accel{0.0};                   ///< φ̈_M [rad/s^2]
  double pitch_torque{0.0}, roll_torque{0.0};  ///< Γ_θ, Γ_φ held over the last step [N m]
  // --- wheels ---
  int contact_count{0};  ///< contacts used: 2 per row, then 2 anti-tip wheels if present
  std::array<WheelContact, kMaxContacts> contacts{};  ///< row i: [2i] left, [2i+1] right
  std::array<CasterState, kMaxContacts> casters{};    ///< swivel state of caster contacts
  int lift_off_count{0};        ///< ground wheels with load ≤ 0 this tick
  double cop_x{0.0}, cop_y{0.0};///< centre of pressure in V [m]
  bool on_anti_tip{false};      ///< the anti-tip wheels carry load
  bool tip_over{false};         ///< centre of pressure outside the support polygon
  // --- circuit (filled by the circuit runner, circuit.h) ---
  bool in_contact{false};       ///< against a wall or obstacle this tick
  int contact_events{0};        ///< wall/obstacle contacts so far
  double last_contact_speed{0.0};  ///< approach speed of the latest contact [m/s]
  int gates_passed{0};          ///< route gates passed in order so far
};

/// A convex polygon (counter-clockwise) kept as its edges, each from vertex a along (dx, dy) to
/// the next vertex: (x, y) is inside or on it when dx (y - a_y) - dy (x - a_x) >= 0 for every edge.
struct ConvexPolygon {
  struct Edge {
    double ax{0.0}, ay{0.0}, dx{0.0}, dy{0.0};
  };
  std::array<Edge, kMaxContacts> edges{};
  int count{0};  ///< 0: no polygon (everything inside)

  /// From the vertices (counter-clockwise, as ConvexHull returns them).
  static ConvexPolygon FromVertices(const std::vector<std::array<double, 2>>& vertices);
  bool Contains(double x, double y) const {
    for (int k = 0; k < count; ++k) {
      const Edge& e = edges[k];
      if (e.dx * (y - e.ay) - e.dy * (x - e.ax) < 0.0) return false;
    }
    return true;
  }
};

/// The sagittal ChairSample view of a full-chair sample (same fields, same bits).
ChairSample SagittalView(const FullChairSample& sample);

class FullChairSimulator {
 public:
  /// @pre chair has gm and lm; layout.rows.size() == chair.wheel_count(); dt > 0.
  FullChairSimulator(const Chair& chair, const PlanarLayout& layout, const FloorMap& floor,
                     double load_kg, double dt, PitchTorqueParams pitch_torque = {},
                     RollTorqueParams roll_torque = {});

  /// Places the chair at rest at `pose` (v, ω ignored) in static equilibrium (tick 0), casters
  /// at `caster_angle` [rad].
  const FullChairSample& Start(const PlanarState& pose, double caster_angle = 0.0);
  /// Start for a straight run: at rest at `pose`, the sagittal view's drive = `drive` (its x the
  /// distance along the start heading that AdvanceAlong continues from).
  const FullChairSample& StartAlong(const PlanarState& pose, const Longitudinal& drive);
  /// Advances one tick with the joystick's deflection through the controller. No allocation.
  const FullChairSample& Advance(const JoystickInput& joystick);
  /// Advances one tick with the set-points given directly (a controller bypassed).
  const FullChairSample& AdvanceSetpoints(const ControllerState& setpoints);
  /// Advances one tick along the start heading with the longitudinal motion prescribed (the
  /// seed's servoed straight run: the power module holds the programmed speed exactly, ω = 0).
  /// On a floor uniform across y this reproduces ChairSimulator bit for bit.
  const FullChairSample& AdvanceAlong(const Longitudinal& drive);
  /// Replaces the planar state (the circuit runner's wall contact: pose kept, speeds zeroed),
  /// keeping everything else of the current sample.
  void OverridePlanar(const PlanarState& planar);
  /// The circuit runner's bookkeeping, copied into the sample (circuit.h).
  void SetCircuitStatus(bool in_contact, int contact_events, double last_contact_speed, int gates_passed);

  const FullChairSample& sample() const { return sample_; }
  int wheel_count() const { return gm_.wheel_count(); }
  double dt() const { return lumped_.dt; }
  const PlanarLayout& layout() const { return layout_; }
  double mass() const { return mass_; }         ///< M [kg]
  double cm_height() const { return cm_height_; }  ///< d_CM [m]
  double drive_x() const { return drive_x_; }   ///< x_D [m]
  double track() const { return track_; }       ///< b [m]

 private:
  void Vertical(double pitch_torque, double roll_torque);
  /// Z_GM, θ_GM (eq. 1-2) and φ_GM of the contacts' heights into geometry_, geometry_roll_;
  /// kept from the last evaluation while the heights are the same bits (level ground).
  void UpdateGeometry();
  void Loads(double a_x, double a_y);
  /// How ContactsAt sets the contact heights u.
  enum class TyreUpdate {
    kRest,  ///< u = h, at rest (Start): envelope and tyres on
    kStep,  ///< one tick of the tyres (Advance)
    kPoint, ///< point contacts, u = h (AdvanceAlong: the sagittal model)
    kKeep,  ///< u kept (a pose overridden within a tick)
  };
  void ContactsAt(const PlanarState& pose, TyreUpdate update);
  /// Caster c's contact point in V (body_x_, body_y_) from its cos δ, sin δ.
  void PlaceCasterContact(int c);
  void Equilibrium();
  double PitchTorqueNow() const;
  double RollTorqueNow() const;

  // --- parameters ---
  const FloorMap& floor_;
  PlanarLayout layout_;
  GeometricModel gm_;
  DiscreteLumpedModel lumped_;
  AxisPropagator roll_axis_;
  AxisParams roll_params_;
  PitchTorqueParams pitch_torque_;
  RollTorqueParams roll_torque_;

  // --- derived once by the constructor (constant per chair: nothing of it is recomputed per tick) ---
  double mass_{0.0}, cm_height_{0.0}, drive_x_{0.0}, track_{0.0};
  double yaw_inertia_D_{0.0};  ///< I_z + m e² [kg m^2]
  double cm_ahead_{0.0};       ///< e = x_c - x_D [m]
  int rows_{0};
  int drive_row_{0};
  int ground_contacts_{0};     ///< 2 per row (the anti-tip pair follows)
  double front_x_{0.0}, rear_x_{0.0};  ///< first and last rows' x [m]
  std::array<double, kMaxContacts> rest_x_{}, rest_y_{};  ///< contact at rest in V [m]
  std::array<WheelRole, kMaxContacts> contact_role_{};
  std::array<double, kMaxContacts> share_{};              ///< k_i per contact
  std::array<double, kMaxContacts> load_c0_{}, load_cx_{}, load_cy_{};
  /// The ground contacts that are not driven (casters and fixed wheels), in contact order.
  std::array<int, kMaxContacts> undriven_{};
  int undriven_count_{0};
  /// Per contact: a caster's pivot x in V, x_p = x_rest + t [m] (the contact at rest otherwise).
  std::array<double, kMaxContacts> pivot_x_{};
  /// Per contact: x_p - x_D, the pivot's (or fixed wheel's) lever about D along x [m].
  std::array<double, kMaxContacts> lever_x_{};
  std::array<double, kMaxContacts> radius_{};       ///< R per contact (0: a point) [m]
  std::array<double, kMaxContacts> tyre_omega2_{};  ///< ω_t² per contact (0: rigid) [1/s²]
  std::array<double, kMaxContacts> tyre_2zw_{};     ///< 2ζω_t per contact [1/s]
  std::array<double, kMaxContacts> tyre_static_{};  ///< δ_s = g / ω_t² per contact [m]
  std::array<double, kMaxWheels> roll_weight_{};
  std::array<double, kMaxWheels> inv_row_track_{};  ///< 1 / (2 half_track_i)
  ConvexPolygon support_;            ///< support polygon of the ground wheels in V
  ConvexPolygon support_anti_tip_;   ///< with the anti-tip wheels
  CasterStepConstants caster_constants_;
  double inv_mass_{0.0}, inv_yaw_inertia_D_{0.0}, inv_dt_{0.0}, inv_roll_inertia_{0.0};
  double inv_track_{0.0}, inv_wheelbase_{0.0};
  double motor_force_limit_{0.0};  ///< max motor torque / drive radius [N]
  double half_mass_{0.0};          ///< M / 2 [kg], each drive wheel's share of the body
  double integral_gain_{0.0};      ///< k_v² / 4 [1/s²] of the speed loops

  // --- state carried from tick to tick besides the sample ---
  double along_x0_{0.0}, along_y0_{0.0}, along_c_{1.0}, along_s_{0.0};  ///< AdvanceAlong line
  double yaw_cos_{1.0}, yaw_sin_{0.0};  ///< cos ψ, sin ψ carried with the yaw (small_rotation.h)
  // inclination of the floor under the chair: tan from the contacts, cos and sin from the tan
  double floor_tan_pitch_{0.0}, floor_tan_roll_{0.0};
  double floor_cos_pitch_{1.0}, floor_sin_pitch_{0.0}, floor_cos_roll_{1.0}, floor_sin_roll_{0.0};
  std::array<double, kMaxContacts> caster_cos_{}, caster_sin_{};  ///< of each caster's δ
  std::array<double, kMaxContacts> tyre_rate_{};  ///< u̇ per contact [m/s]
  std::array<double, kMaxContacts> floor_z_before_{};  ///< h at the last tick [m]
  /// Each contact point in V [m]: at rest, or a caster's p_rest + t (1 - cos δ, -sin δ).
  std::array<double, kMaxContacts> body_x_{}, body_y_{};

  // --- caches (results kept to spare a lookup; any value gives the same bits) ---
  std::array<FloorHint, kMaxContacts> floor_hints_{};  ///< each contact's floor lookup hint
  JoystickInput target_joystick_;  ///< the deflection target_ was computed for
  std::array<double, kMaxContacts> geometry_z_{};  ///< contact heights geometry_ is from [m]
  GeometricOutput geometry_;       ///< gm_.Evaluate of their row means
  double geometry_roll_{0.0};      ///< φ_GM of them [rad]
  bool geometry_valid_{false};
  ControllerState target_;         ///< ControllerTarget(layout_.controller, target_joystick_)

  FullChairSample sample_;
};

}  // namespace pwsim
