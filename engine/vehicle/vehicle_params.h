#pragma once
// The parameters of a passenger car for the car simulator of seed 001 (one body with 5 DOF:
// longitudinal, lateral, yaw, roll, pitch; the complexity lies in the powertrain), and its file
// format `pwsim-vehicle/1` (assets/cars/*.yaml). Pure data; engine/vehicle/vehicle.h reads it.
//
// Frames and signs (docs/notation.md, ISO 8855): body frame V at the centre of gravity, x forward,
// y left, z up; yaw ψ positive turning left, roll φ positive left side up, pitch θ positive
// nose-up; road-wheel steer angle δ positive to the left.
//
// Gear ratio convention (one, stated): every ratio is input speed over output speed,
// i = ω_in / ω_out (> 1 for a reduction), so ω_engine = i_gear · i_final · ω_wheel when the
// clutch is locked. A file may state the other convention (`ratio_convention:
// output_over_input`); the reader converts (i = 1 / r) on load. Reverse is a negative ratio.
//
//   Vehicle car = ReadVehicleFile("assets/cars/midsize.yaml");

#include <filesystem>
#include <string>
#include <vector>

#include "engine/yaml_reader.h"

namespace pwsim::vehicle {

inline constexpr double kGravity = 9.80665;  ///< [m/s^2]
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kRpmToRadps = 2.0 * kPi / 60.0;

/// Chassis: rigid body on four wheels; roll and pitch on suspension springs.
struct ChassisParams {
  double mass{1450.0};            ///< m [kg] total
  double yaw_inertia{2400.0};     ///< I_z [kg m^2] about the CoG
  double roll_inertia{500.0};     ///< I_x [kg m^2] of the sprung mass about the roll axis
  double pitch_inertia{2100.0};   ///< I_y [kg m^2] of the sprung mass about the pitch axis
  double wheelbase{2.7};          ///< L [m]
  double cg_to_front{1.08};       ///< a [m] CoG to front axle (b = L - a)
  double cg_height{0.55};         ///< h [m] CoG above ground (load transfer)
  double track_front{1.55};       ///< t_f [m]
  double track_rear{1.55};        ///< t_r [m]
  double width{1.8};              ///< [m] body width (ISO 3888-1 lane widths, rendering)
  double roll_arm{0.45};          ///< h_φ [m] CoG above the roll axis
  double pitch_arm{0.45};         ///< h_θ [m] CoG above the pitch axis
  double roll_stiffness{9.0e4};   ///< K_φ [N m/rad]
  double roll_damping{6.0e3};     ///< C_φ [N m s/rad]
  double pitch_stiffness{1.5e5};  ///< K_θ [N m/rad]
  double pitch_damping{1.0e4};    ///< C_θ [N m s/rad]
  double roll_stiffness_front{0.55};  ///< λ_f [-] share of lateral load transfer on the front
  double drag_area{0.65};         ///< C_d A [m^2]
  double air_density{1.2};        ///< ρ [kg/m^3]

  double cg_to_rear() const { return wheelbase - cg_to_front; }
};

/// Tyre (all four alike): combined-slip magic formula, relaxation lengths.
struct TyreParams {
  double radius{0.31};            ///< R_e [m] effective rolling radius
  double wheel_inertia{1.2};      ///< J_w [kg m^2] wheel + tyre + brake disc spin inertia
  double mu_x{1.0};               ///< μ_x [-] peak longitudinal friction (D_x = μ_x F_z)
  double mu_y{0.95};              ///< μ_y [-] peak lateral friction
  double shape_x{1.65};           ///< C_x [-] magic-formula shape factor, longitudinal
  double shape_y{1.3};            ///< C_y [-]
  double curvature_x{0.0};        ///< E_x [-] (< 1)
  double curvature_y{-1.0};       ///< E_y [-] (< 1)
  double slip_stiffness{20.0};    ///< C_κ / F_z [1] longitudinal slip stiffness per unit load
  /// Cornering stiffness C_α(F_z) = c1 sin(2 atan(F_z / c2)) [N/rad] (degressive in load).
  double cornering_c1{8.0e4};     ///< c1 [N/rad]
  double cornering_c2{5.0e3};     ///< c2 [N]
  double relax_x{0.15};           ///< σ_κ [m] longitudinal relaxation length
  double relax_y{0.45};           ///< σ_α [m] lateral relaxation length
  double low_speed{1.0};          ///< v_low [m/s] slip speed floor (no division by 0)
  double low_speed_damping{4.0e3};///< c_low [N s/m] contact damping below v_low (faded out)
  double carcass_damping_time{0.004};  ///< τ_x [s] longitudinal carcass damping (force at κ' + τ_x κ̇')
  double rolling_resistance{0.012};  ///< f_r [-] rolling resistance coefficient
};

/// One engine torque curve point.
struct TorquePoint {
  double rpm{0.0};
  double full_load{0.0};       ///< [N m] wide-open throttle
  double closed_throttle{0.0}; ///< [N m] throttle closed (≤ 0: friction and pumping)
};

struct EngineParams {
  std::vector<TorquePoint> map;   ///< rising rpm, first at 0 rpm
  double inertia{0.2};            ///< J_e [kg m^2] crank + flywheel
  double idle_rpm{800.0};         ///< idle controller set point
  double stall_rpm{350.0};        ///< below this a running engine stalls
  double max_rpm{6500.0};         ///< fuel cut (rev limiter) above
  double idle_gain{0.004};        ///< k_p [1/rpm] idle throttle per rpm below idle
  double idle_integral_gain{0.01};///< k_i [1/(rpm s)]
  double idle_max_throttle{0.35}; ///< [-] authority of the idle controller
};

struct ClutchParams {
  double max_torque{380.0};       ///< T_c,max [N m] capacity with the pedal released
  double engaged_pedal{0.15};     ///< pedal travel [0..1] at or below which the capacity is full
  double free_pedal{0.7};         ///< pedal travel at or above which the clutch transmits none
};

struct GearboxParams {
  std::vector<double> ratios{3.6, 2.1, 1.4, 1.05, 0.82};  ///< i_1..i_n [-] ω_in/ω_out
  double reverse{-3.5};           ///< i_R [-] (negative)
  double final_drive{3.9};        ///< i_f [-]
  double efficiency{0.93};        ///< η [-] driveline efficiency (power engine → wheels)
  bool front_drive{true};         ///< driven axle: true = front, false = rear
};

struct BrakeParams {
  double max_torque_front{2200.0};  ///< [N m] per front wheel at full pedal
  double max_torque_rear{1000.0};   ///< [N m] per rear wheel at full pedal
};

struct SteeringParams {
  double ratio{15.0};             ///< steering-wheel angle / road-wheel angle [-]
  double max_wheel_angle{0.6};    ///< [rad] road-wheel angle limit
};

struct Vehicle {
  std::string name{"car"};
  std::string description;
  ChassisParams chassis;
  TyreParams tyre;
  EngineParams engine;
  ClutchParams clutch;
  GearboxParams gearbox;
  BrakeParams brakes;
  SteeringParams steering;

  int gear_count() const { return static_cast<int>(gearbox.ratios.size()); }
  /// Gearbox ratio of `gear` (-1 reverse, 0 neutral → 0, 1..n forward).
  double GearRatio(int gear) const;
};

/// A mid-size front-drive saloon (~1.45 t, 2.0 l petrol, 5 speeds), as assets/cars/midsize.yaml.
Vehicle MakeMidsizeCar();

/// Empty when consistent, else which field is wrong and why.
std::string Validate(const Vehicle& car);

/// Reads the vehicle fields (everything but `format`) from an open mapping.
Vehicle ParseVehicle(YamlMap& map);
/// Reads a `pwsim-vehicle/1` file. @throws InputError.
Vehicle ReadVehicleFile(const std::filesystem::path& file);

}  // namespace pwsim::vehicle
