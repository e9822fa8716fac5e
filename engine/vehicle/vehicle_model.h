#pragma once
// The car of seed 001: one body with 5 DOF (longitudinal u, lateral v, yaw r; roll φ and pitch θ
// on suspension springs), four tyres (tyre.h), and a powertrain (engine map with idle control
// and stall, clutch with stick/slip switching, manual gearbox, final drive, open differential
// on the driven axle), brakes on all wheels, a steering rack.
//
// Chassis (body frame V at the CoG; x forward, y left), wheel i at (x_i, y_i), steer δ on the
// front wheels; F_i the tyre force in the wheel frame rotated to V by δ_i:
//   m (u̇ - v r) = Σ F_x,i - ½ ρ C_dA u|u|,   m (v̇ + u r) = Σ F_y,i,   I_z ṙ = Σ (x_i F_y,i - y_i F_x,i)
//   I_x φ̈ = m h_φ a_y + m g h_φ φ - K_φ φ - C_φ φ̇,   I_y θ̈ = m h_θ a_x + m g h_θ θ - K_θ θ - C_θ θ̇
// Normal loads, quasi-static with the previous step's a_x, a_y (roll moment split λ_f : 1-λ_f):
//   F_z,f = m (g b - a_x h)/L,  F_z,r = m (g a + a_x h)/L,  ΔF_z,f = m a_y h λ_f / t_f, ...
//   F_z,fl = F_z,f/2 - ΔF_z,f,  F_z,fr = F_z,f/2 + ΔF_z,f  (turning left loads the right wheels)
// Wheels:  J_w ω̇_i = T_drive,i - R_e F_x,i - (T_brake,i + f_r F_z,i R_e) sgn ω_i
//   (brake and rolling resistance are Coulomb torques, applied exactly: a wheel whose speed
//   would cross zero within the step stops at zero).
// Powertrain, i = i_gear i_final, ω_c = i (ω_l + ω_r)/2 the clutch's gearbox-side speed:
//   J_e ω̇_e = T_e - T_c;  each driven wheel gets T_drive = η' i T_c / 2  (η' = η when the
//   clutch drives the wheels, 1/η when the wheels drive the engine)
//   slipping: T_c = T_cap sgn(ω_e - ω_c);
//   locked:   ω_e = ω_c and T_c is the torque that keeps them equal,
//             T_c = (T_e/J_e + i ΣL/(2 J_w)) / (1/J_e + η' i²/(2 J_w)),
//             ΣL = Σ_driven (R_e F_x + T_res sgn ω); it unlocks when |T_c| > T_cap and locks
//             when the slip speed ω_e - ω_c changes sign in a step while |T_c| ≤ T_cap.
//
// Integration: fixed step, semi-implicit (symplectic) Euler: speeds first from the forces at
// the start of the step, then the poses from the new speeds; the body-frame velocity is
// rotated exactly by -r dt (the u r and v r terms), the tyre relaxation decay is implicit, and
// the Coulomb torques are exact. Deterministic: no clock, no randomness, no allocation.

#include <array>

#include "engine/vehicle/powertrain.h"
#include "engine/vehicle/tyre.h"
#include "engine/vehicle/vehicle_params.h"

namespace pwsim::vehicle {

inline constexpr int kWheels = 4;
enum WheelIndex : int { kFrontLeft = 0, kFrontRight = 1, kRearLeft = 2, kRearRight = 3 };

/// The driver's controls.
struct DriverInput {
  double throttle{0.0};  ///< accelerator travel [0, 1]
  double brake{0.0};     ///< brake pedal [0, 1] (fraction of full brake torque)
  double clutch{0.0};    ///< clutch pedal travel [0, 1]; 0 released (engaged), 1 pressed
  int gear{0};           ///< -1 reverse, 0 neutral, 1..n
  double steer{0.0};     ///< steering-wheel angle [rad], positive turns left
  bool starter{false};   ///< restarts a stalled engine when the clutch is open or in neutral
  bool operator==(const DriverInput&) const = default;
};

struct VehicleState {
  double x{0.0}, y{0.0}, yaw{0.0};     ///< p_WV [m], ψ [rad] of the CoG in W
  double u{0.0}, v{0.0}, r{0.0};       ///< body-frame velocity [m/s], yaw rate [rad/s]
  double roll{0.0}, roll_rate{0.0};    ///< φ [rad], φ̇ [rad/s]
  double pitch{0.0}, pitch_rate{0.0};  ///< θ [rad] nose-up, θ̇ [rad/s]
  std::array<double, kWheels> omega{};          ///< wheel spin [rad/s]
  std::array<TyreSlipState, kWheels> slip{};    ///< lagged slips
  double engine_speed{0.0};            ///< ω_e [rad/s]
  bool engine_running{true};
  bool clutch_locked{false};
  IdleControllerState idle;
  double ax{0.0}, ay{0.0};             ///< body-frame CoG acceleration of the last step [m/s^2]
  double yaw_accel{0.0};               ///< ṙ of the last step [rad/s^2]
  bool operator==(const VehicleState&) const = default;
};

/// What happened during one step (forces and torques at its start), for outputs and checks.
struct StepInfo {
  double road_wheel_angle{0.0};          ///< δ [rad]
  double throttle{0.0};                  ///< θ_eff after idle control and fuel cut
  double engine_torque{0.0};             ///< T_e [N m] (friction when stalled)
  double clutch_torque{0.0};             ///< T_c [N m]
  double clutch_capacity{0.0};           ///< T_cap [N m]
  double gearbox_ratio{0.0};             ///< i = i_gear i_final (0 in neutral)
  double drag_force{0.0};                ///< [N] along -x
  std::array<double, kWheels> fz{};      ///< [N]
  std::array<TyreForce, kWheels> force{};///< wheel frame [N]
  std::array<double, kWheels> vcx{}, vcy{};  ///< contact velocity, wheel frame [m/s]
  std::array<double, kWheels> drive_torque{};  ///< [N m] from the differential
  std::array<double, kWheels> resist_torque{}; ///< [N m] brake + rolling resistance magnitude
};

/// A car at rest at the origin heading along +x, engine idling, neutral.
VehicleState InitialState(const Vehicle& car);

/// One step of `dt` seconds. `info` (optional) receives the step's forces.
VehicleState StepVehicle(const Vehicle& car, const VehicleState& state, const DriverInput& input,
                         double dt, StepInfo* info = nullptr);

/// Wheel positions (x_i, y_i) in V [m].
std::array<std::array<double, 2>, kWheels> WheelPositions(const Vehicle& car);

/// Static normal loads [N] (front, rear per wheel).
std::array<double, 2> StaticWheelLoads(const Vehicle& car);

/// Kinetic energy: translation, yaw, wheel spin and engine [J] (roll/pitch excluded).
double KineticEnergy(const Vehicle& car, const VehicleState& state);

/// Vehicle speed over ground [m/s].
inline double Speed(const VehicleState& s) { return std::hypot(s.u, s.v); }
inline double EngineRpm(const VehicleState& s) { return s.engine_speed / kRpmToRadps; }

}  // namespace pwsim::vehicle
