#pragma once
// independent_truth: a "real chair" for testing pwsim's identification and diagnosis that
// shares no code and no formulation with engine/ (used only by tests, benchmarks and scripts).
//
// Formulation (a rigid chassis on per-wheel suspensions, not the paper's GM + LM):
//   state: drive x, v; chassis altitude deviation z and pitch θ of O_V (from static
//   equilibrium on flat ground); per wheel optional unsprung mass (z_u, ż_u), Dahl friction
//   force F_d, cushion foam deflection d; optional occupant on a seat spring (z_o, ż_o).
//   Wheel i is attached at X_i = x + x_i cos θ, A_i = z + x_i sin θ. Its ground g_i is the
//   terrain under X_i (point contact) or the lowest centre height of a disc of radius R_i over
//   the terrain minus R_i (found by ternary search on each segment: the disc-top function is
//   concave per segment), minus the foam deflection d_i.
//   Suspension force on the chassis  S_i = F0_i + k_i δ_i + c_i δ̇_i + B_i(δ_i) + F_d,i,
//   δ_i = u_i - A_i (u_i the wheel: g_i, or z_u,i with a tyre; tyres are unilateral springs).
//     M_c z̈ = Σ (S_i - F0_i) + Q,   J_c θ̈ = cos θ [Σ (S_i - F0_i) x_i + Q x_s] + a_x Σ m h
//   with Q the occupant's seat force, F0_i the static preload (k-proportional share of the
//   weight), M_c = M_0 + (1-f) M_u, J_c = J_0 + d_CM² (M_0 + (1-f) M_u) (seed 000 eq. 4-5 when
//   f = 0). The drive x(t) follows a jerk-limited profile (accelerate, cruise over the
//   obstacle, decelerate). Integration: Dormand-Prince 5(4) with step-size control and dense
//   output (Boost.Odeint), tolerances 1e-9 abs / 1e-7 rel, steps ≤ 2 ms, sampled at the frame times.
//   Mocap: a marker at lever (r_x, r_z) in the chair frame measures x + r_x cos θ - r_z sin θ and
//   z + r_x sin θ + r_z cos θ; Gaussian noise on x, z, θ, or the coloured, drifting and
//   outlying noise of measurement_noise.h.
// Each effect has several physical laws (docs in TruthEffects); law_space.h draws them by seed.
// With every effect off and Σ k_i x_i = Σ c_i x_i = 0, the small-angle motion is the paper's
// model with α_i = k_i / Σk, a single front-rear slope, K_Z = Σk, K_θ = Σ k x², C likewise.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "tests/truth/measurement_noise.h"

namespace pwsim::truth {

struct TruthWheel {
  std::string name;
  double x_m{0.0};       ///< along the forward axis from O_V
  double radius_m{0.1};  ///< nominal radius written to chair.yaml
  double k_npm{2e4};     ///< suspension stiffness
  double c_nspm{1e3};    ///< suspension damping
  bool caster{false};
};

struct TruthChair {
  std::string name{"indep"};
  double mass_kg{53.0};       ///< M_0
  double inertia_kgm2{9.9};   ///< J_0
  double cm_height_m{0.43};   ///< d_CM
  std::vector<TruthWheel> wheels;  ///< front to rear
};

/// The physical effects, each in a form of its own (none is the candidate's formula).
struct TruthEffects {
  // wheel_radius: wheels roll as discs of contact_radius_scale × nominal radius.
  double contact_radius_scale{0.0};
  // tyre_compliance, law 1: unsprung wheels on unilateral tyre springs.
  double caster_tyre_hz{0.0}, drive_tyre_hz{0.0};  ///< wheel-hop frequency on the tyre (0 = rigid)
  double tyre_zeta{0.1};
  double caster_unsprung_kg{3.0}, drive_unsprung_kg{8.0};
  // tyre_compliance, law 2: a massless tyre spring k_t = ratio × k_i with damper c_t = τ_t k_t in
  // series with the suspension; the hub u follows from the force balance
  //   k_t (g - u) + c_t (ġ - u̇) = k δ + c δ̇ + B(δ) + F_d,   δ = u - A.
  // Not combined with rate-dependent friction (the balance would be implicit).
  double caster_tyre_ratio{0.0}, drive_tyre_ratio{0.0};  ///< k_t / k_i (0 = rigid)
  bool tyre_massless{false};
  double tyre_tau_s{0.005};
  // cushion_compliance: foam deflection d → D(F) = H y(F), y = a (F / F_ref)^p ≤ 0.8, relaxing with tau.
  double cushion_yield{0.0};     ///< a [-] at F = F_ref
  double cushion_exponent{1.0};  ///< p
  bool cushion_whole_chair{false};  ///< F = whole-chair weight (static) instead of the wheel's dynamic force
  bool cushion_proportional{false};  ///< y = a whatever the load: the foam yields a fixed share of its height
  double cushion_ref_n{500.0};
  double cushion_tau_s{0.015};
  // heave_pitch_coupling: front springs × (1 + e), rear × (1 - e) (dampers too when damper_asym).
  double stiffness_asymmetry{0.0};
  bool damper_asymmetry{true};
  // nonlinear_stiffness: bump stops beyond gap: k b (δ - g)² / g (compression; both ways if symmetric).
  double bump_gain{0.0};
  double bump_gap_m{0.004};
  bool bump_symmetric{false};
  bool bump_rebound_only{false};  ///< stops in rebound (δ < -g) only
  // suspension_friction: a friction force of Coulomb level F_c = dahl_force_n in the law
  //   Dahl (per wheel):    Ḟ = σ δ̇ (1 - sgn(δ̇) F / F_c), σ = F_c / presliding deflection;
  //   smooth Coulomb:      F = F_c tanh(δ̇ / v_s);
  //   Stribeck/breakaway:  F = (F_c + (F_s - F_c) exp(-(δ̇ / v_St)²)) tanh(δ̇ / v_s);
  // per wheel (on δ̇_i) or at chair level (force -F(ż) on heave, torque -L F(L θ̇) on pitch,
  // L the largest wheel lever), plus a viscous share c_v δ̇ per wheel.
  enum class FrictionLaw { kDahl, kSmoothCoulomb, kStribeck };
  FrictionLaw friction_law{FrictionLaw::kDahl};
  double dahl_force_n{0.0};
  double dahl_presliding_m{5e-4};
  bool friction_chair_level{false};
  double friction_smooth_mps{0.005};      ///< v_s
  double friction_breakaway_ratio{1.0};   ///< F_s / F_c
  double friction_stribeck_mps{0.01};     ///< v_St
  double friction_viscous_nspm{0.0};      ///< c_v
  // inertial_pitch: pitch torque a_x (M_chassis h_c + M_u h_u).
  double chassis_cm_height_m{0.0}, load_cm_height_m{0.0};
  // marker_offset: lever of the tracked origin in the chair frame.
  double marker_x_m{0.0}, marker_z_m{0.0};
  // Outside the catalogue: the occupant sits on a seat spring (share f of M_u).
  double occupant_share{0.0};
  double seat_hz{4.0}, seat_zeta{0.25}, seat_x_m{0.0};
  // Wheels may leave the ground (suspension force clipped at 0). Off by default: the paper's
  // model keeps every wheel on the ground, and a light chair on a tall cushion would otherwise
  // unload its mid wheel (a further effect outside the catalogue).
  bool unilateral_contact{false};
};

struct Obstacle {
  std::vector<double> x_m, z_m;  ///< piecewise-linear profile (z = 0 outside)
  double HeightAt(double x) const;
};

struct DriveProfile {
  double speed_mps{1.0};
  double accel_mps2{0.8};
  double jerk_time_s{0.25};  ///< accel ramps up/down over this time
  double still_s{0.5};
  double cruise_until_m{8.0};  ///< O_V position where deceleration starts
};

struct TruthTrialConfig {
  TruthChair chair;
  TruthEffects effects;
  Obstacle terrain;
  DriveProfile drive;
  double load_kg{0.0};
  double rate_hz{100.0};
  double noise_x_m{3e-4}, noise_z_m{3e-4}, noise_pitch_rad{5e-4};  ///< white σ when noise.white_only
  MeasurementNoise noise;  ///< white_only (default): the σ above; otherwise this model
  double z_offset_m{0.4};  ///< altitude of the lab's origin at rest
  std::uint64_t seed{1};
  /// Chassis kinematics linearised as the paper's model has them (cos θ -> 1, sin θ -> θ for
  /// the wheels' positions, the suspension anchors and the moment arms). Off: exact rigid-body
  /// geometry, which departs from the linear model only when the chair pitches far.
  bool small_angle{false};
};

struct TruthTrial {
  std::vector<double> t, x, z, pitch;  ///< what the mocap measured (noise, marker lever)
  std::vector<double> true_x, true_z, true_pitch;  ///< O_V itself, noise-free
};

TruthTrial SimulateTruthTrial(const TruthTrialConfig& config);

/// The paper's 3-contact chair perturbed at random (seeded): Σk x = Σc x = 0, K_θ 4-7 kN m/rad.
TruthChair RandomTruthChair(std::mt19937_64& rng);
/// A speed cushion of random height (5-8 cm), ramps (0.25-0.35 m) and top (1.2-1.8 m) at x ≈ 4 m.
Obstacle RandomCushion(std::mt19937_64& rng);

/// Effect names understood by EffectsFor: the spec's ids plus "occupant_seat" (outside the
/// catalogue). `form` picks one physical variant of the family (any integer; wraps around).
std::vector<std::string> TruthEffectNames();
/// Adds effect `name` at `strength` (1 = moderate) in variant `form` to `fx`. @throws
/// std::invalid_argument for an unknown name.
void AddEffect(const std::string& name, double strength, int form, const TruthChair& chair,
               TruthEffects& fx);

struct TruthSetConfig {
  std::vector<std::string> effects;  ///< empty: no effect
  double strength{1.0};
  int form{0};
  std::vector<double> speeds{0.5, 0.9, 1.3, 1.7};
  std::vector<double> loads{0.0, 50.0, 100.0};
  std::uint64_t seed{1};
  double rate_hz{100.0};
  bool small_angle{false};  ///< TruthTrialConfig::small_angle for every trial
  /// Draw each effect's law, parameters and strength and the noise model from the law space by
  /// `seed` (law_space.h) instead of AddEffect's variant `form` at `strength` (both ignored).
  bool draw_laws{false};
  std::string noise_kind;  ///< with draw_laws: force the noise kind (NoiseKinds()); empty: drawn
};

struct TruthSet {
  TruthChair chair;
  TruthEffects effects;
  Obstacle terrain;
  std::vector<std::string> names;  ///< trial folder names
  std::vector<TruthTrialConfig> configs;
  std::vector<TruthTrial> trials;
  std::vector<std::string> laws;  ///< with draw_laws: each effect's law and parameters, and the noise
  MeasurementNoise noise;
};

TruthSet SimulateTruthSet(const TruthSetConfig& config);

/// Writes one folder per trial under `dir` in measured-trials.md's format (trial.yaml,
/// chair.yaml without gm/lm, terrain.yaml, mocap.csv) and the truth beside the set:
/// `<dir>.truth.yaml` (never inside a trial folder).
void WriteTruthSet(const TruthSet& set, const std::filesystem::path& dir);

}  // namespace pwsim::truth
