#pragma once
// Extended chair model: the paper's geometric + lumped model (seed 000 eq. 1-5) with the
// physical effects it leaves out (measured-trials.md effect table), each switched on by its own
// parameters. Every effect is off at its default (zero) value, so the base model is the
// extended model with EffectParams{}.
//
// Driven like the paper's Fig. 6b: a trial's sampled x(t), linear between samples, on the
// internal grid t0 + k·step -> wheel contact heights -> (effects) -> GM -> LM -> Z and θ,
// interpolated linearly back to the sample times.
//
// Discretisation: the SAME as identification's (sysid/measured SimulateAxisOnGrid): each LM
// axis is propagated exactly (engine/lumped_model.h, matrix exponential) with the GM output
// on a first-order hold over the step. What an effect adds is either linear and exact too
// (a tyre mode: its own exact propagator on the ground height) or a force/torque evaluated
// at the start of the step and held over it (coupling, hardening, bump stops, friction, the
// inertial torque, the tyre's reaction). Dahl friction states relax exactly for the held
// deflection rate. With EffectParams{} the output is identification's base model bit for bit.
// Deterministic: same inputs, same bits.
//
//   PreparedTrial trial = PrepareTrial(chair, terrain, load_kg, t, x);
//   ExtendedParams params{.lm = *chair.lm};
//   params.fx.marker_lever_x = 0.1;
//   ModelOutput out = SimulateExtended(trial, params);

#include <array>
#include <span>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "engine/terrain.h"
#include "sysid/measured/measured_trial.h"

namespace pwsim::effects {

/// The discrete members of the families whose laws differ by more than a value
/// (effect_catalog.h, EffectFamily): each is chosen by the fit among its family's members,
/// never fitted continuously, and kept apart from the fitted values below.
enum class CushionLoad { kPerWheel, kWholeChair };  ///< W = α_i M g, or W = M g
enum class StopSides { kCompression, kBoth, kRebound };  ///< where the bump stops act
/// The chassis' kinematics, a member of the whole model rather than of one family:
///  - kSmallAngle (the paper's, identification's; the default): wheel i, at x_i in the chassis
///    frame, touches the ground at x + x_i, its anchor at Z + x_i θ; the LM's pitch spring and
///    damper act on θ - θ_GM and θ̇ - θ̇_GM.
///  - kExact: the rigid chassis pitched by θ. Wheel i touches the ground at x + x_i cos θ, its
///    anchor sits at Z + x_i sin θ and its vertical force acts at the lever x_i cos θ. The GM's
///    θ_GM (eq. 2: the asin of the contacts' chords) is the angle at which the anchors meet the
///    contacts, sin θ = sin θ_GM; springs k_i on the anchors give the torque
///    -cos θ Σ k_i x_i² (sin θ - sin θ_GM), so the LM's pitch torque becomes
///      Γ = -cos θ [K_θ (sin θ - sin θ_GM) + C_θ (cos θ θ̇ - cos θ_GM θ̇_GM)]
///    (the anchor's rate is Ż + x_i cos θ θ̇). Its difference from the small-angle torque,
///    O(θ³), is held over the step like the other held forces (Heun), the contact heights are
///    taken at x + x_i cos θ with θ predicted to the step's end, and the tyres' reactions split
///    K_θ (sin θ - sin θ_GM) + C_θ (cos θ θ̇ - cos θ_GM θ̇_GM) over the wheels (Σ x_i R_i).
///    Heave, the coupling and the hardening terms stay as they are. On a ramp of slope s a
///    chassis whose β sum to 1 rests at θ = atan s (exact) instead of asin s (contacts at x_i).
///    About a pitch θ the small-angle pitch stiffness is off by sin²θ: 3.9 % at 0.2 rad.
enum class Kinematics { kSmallAngle, kExact };
/// The suspension friction's law (EffectParams, suspension_friction): Dahl's (a state relaxing
/// over a presliding deflection) or smooth Coulomb (a function of the deflection rate).
enum class FrictionLaw { kDahl, kSmoothCoulomb };
/// The tyres' law (EffectParams, tyre_compliance): an unsprung mass on each tyre, or a massless
/// spring-damper in series with the suspension.
enum class TyreLaw { kUnsprung, kMassless };
struct EffectMembers {
  CushionLoad cushion_load{CushionLoad::kPerWheel};
  TyreLaw tyre{TyreLaw::kUnsprung};
  StopSides stops{StopSides::kCompression};
  FrictionLaw friction{FrictionLaw::kDahl};
  Kinematics kinematics{Kinematics::kSmallAngle};
};

/// Effect parameters; each group is one effect id of the spec's table. Zero = effect absent.
struct EffectParams {
  EffectMembers member;  ///< the discrete member of each family (the fitted values follow)
  // wheel_radius: each wheel centre rides the rolling-disc envelope of the ground.
  double caster_radius{0.0};  ///< [m] radius of every caster wheel (0 = point contact)
  double drive_radius{0.0};   ///< [m] radius of every non-caster wheel
  // tyre_compliance: per wheel an unsprung mass m_u on a tyre of stiffness k_t = 1/c_t and
  // damping ratio ζ under its own suspension spring, ω² = k_t / m_u; its height z_u is the GM's
  // input:
  //   z̈_u = ω² (h - z_u) + 2ζω (ḣ - ż_u) + ω² c_t R_i        (R_i / m_u = ω² c_t R_i)
  //   R_i = a_i F + p_i Γ - k_i d_i - c_i ḋ_i
  // (deviations from static equilibrium): the LM's suspension force F and torque Γ split over
  // the wheels by the suspension plane (a_i, p_i: coefficients of the s-weighted least-squares
  // plane through the wheel heights, so Σ R_i = F and Σ x_i R_i = Γ), plus the wheel's own
  // spring k_i = s_i K_Z on its height d_i off that plane (the hop mode at √((k_t + k_i)/m_u);
  // the chassis does not feel d_i), and its own damper s_i C_Z on ḋ_i (held over the step, so
  // capped where s_i C_Z Δt / m_u would pass 1: beyond 2 it is unstable). The suspension shares
  // s_i: the GM was identified on ground heights, through each tyre in series with its spring,
  // so s keeps the series pairs 1/(1/k_i + c_t,i) = λ α_i at the GM's shares α (Σ k_i = K_Z),
  // and the GM acting on the unsprung heights is the identified one shifted by the s-plane minus
  // the α-plane. c_t = 0 drops the reaction (a stiff tyre under a heavy wheel: a unit-DC-gain
  // filter of the ground, s = α). The tyre pushes but never pulls: when its total force (static
  // s_i M g + m_u g plus the deviation) would fall below zero the wheel leaves the ground for
  // that step (ballistic, R_i and g; at c_t = 0 it still cannot follow the ground down faster
  // than g).
  // member.tyre == kMassless: no unsprung mass. Each wheel's hub u_i sits between a tyre of
  // stiffness k_t = 1/c_t with damper τ_t k_t (wheels with c_t = 0 are rigid, u = h) and its
  // suspension, and the forces balance:
  //   k_t (h - u) + τ_t k_t (ḣ - u̇) + R_i = 0,
  // where R_i (as above) depends on every hub's rate through the suspension's dampers: on the
  // GM's rates (C_Z, C_θ and the coupling, through the GM's linear weights) and on each wheel's
  // own damper on its rate off the plane. Written (τ_t K_t + D) u̇ = K_t (h - u) + τ_t K_t ḣ + R(u̇ = 0)
  // and likewise R's dependence on u as a stiffness S, the hubs advance by a linearly implicit
  // trapezoidal step, u' = u + Δt (τ_t K_t + D + Δt S / 2)^-1 b(u), stable for any τ_t ≥ 0 (the
  // chassis' state held over the step). The periods and ζ are not used; the tyres never leave
  // the ground.
  double caster_tyre_period{0.0};      ///< [s] 2π/ω of the caster tyre (0 = rigid)
  double drive_tyre_period{0.0};       ///< [s] 2π/ω of the drive tyre (0 = rigid)
  double tyre_damping{0.5};            ///< ζ [-] of the tyre modes
  double caster_tyre_compliance{0.0};  ///< c_t [m/N] per caster (0 = reaction neglected)
  double drive_tyre_compliance{0.0};   ///< c_t [m/N] per drive wheel
  double tyre_time_constant{0.005};    ///< τ_t [s] of the massless tyres' dampers
  // The casters behind O_V (x_i < 0: anti-tip or rear casters, often smaller wheels on other
  // tyres than the front ones) have the compliance ρ c_t of the front casters' c_t
  // (TyreCompliances).
  double rear_caster_compliance_ratio{1.0};  ///< ρ [-]
  // cushion_compliance: the obstacle height falls with the load on it, W = the static wheel
  // load α_i M g (per wheel) or the whole chair's weight M g (member.cushion_load), by a power
  // law the data choose:
  // h_eff = h max(0, g - c (W / 1 kN)^p), g the unloaded height relative to the terrain file.
  double cushion_loss_per_kn{0.0};  ///< c [-] fraction of obstacle height lost at W = 1 kN
  double cushion_height_gain{1.0};  ///< g [-]
  double cushion_exponent{1.0};     ///< p [-] (1: linear yield)
  // ... and θ_GM scaled by q: where the base model's β were identified on these trials (free,
  // unlike the α, which sum to 1: sysid/identify IdentifyOptions::rigid_heave), they already
  // carry the yield every wheel shares; q rescales them (θ_GM is linear in the β), so that the
  // yield is not counted twice in pitch.
  double cushion_pitch_gain{1.0};   ///< q [-]
  // heave_pitch_coupling: off-diagonal K, C as a fraction of sqrt(K_Z K_θ), sqrt(C_Z C_θ).
  double stiffness_coupling{0.0};  ///< [-] in (-1, 1)
  double damping_coupling{0.0};    ///< [-] in (-1, 1)
  // nonlinear_stiffness: K δ (1 + κ (δ/δ_ref)²), δ_ref = kHeaveRef, kPitchRef.
  double heave_hardening{0.0};  ///< κ_Z [-]
  double pitch_hardening{0.0};  ///< κ_θ [-]
  // ... and per-wheel bump stops (progressive): wheel i adds
  //   F_i = b K_Z α_i max(0, c_i - g)² / δ_ref,  c_i = Z_Oi - (Z + x_i sin θ) its compression,
  // at x_i (member.stops == kCompression); with rebound stops as well (kBoth) it also adds
  // -b K_Z α_i max(0, -c_i - g)² / δ_ref in extension, pulling the chassis back down; kRebound:
  // that rebound force alone (the family's three members, each fitted, the best kept).
  double bump_gain{0.0};      ///< b [-]
  double bump_gap{0.0};       ///< g [m] compression (and extension) before a stop engages
  // suspension_friction: dry friction in each wheel's suspension, Dahl's law on the wheel's
  // deflection r_i = Z + x_i θ - Z_Oi (the chassis over the wheel relative to its contact):
  //   dF_i/dt = (ṙ_i / δ_p) (F_c,i sgn ṙ_i - F_i)·sgn ṙ_i,  i.e. presliding stiffness F_c/δ_p,
  // F_i resisting ṙ_i (Coulomb as δ_p -> 0); ΣF_i acts on heave, Σ x_i F_i on pitch.
  // member.friction == kSmoothCoulomb: instead a function of the rate alone,
  //   F_i = F_c,i tanh(ṙ_i / v_s)
  // (Coulomb as v_s -> 0; below v_s a viscous F_c/v_s: a creep rather than Dahl's presliding
  // spring), held over the step from the previous step's mean rate; v_s is kept above
  // n F_c,i Δt (1/M + x_i²/I_θ) (n wheels) so that the held law stays stable.
  double caster_friction{0.0};    ///< F_c [N] per caster
  double drive_friction{0.0};     ///< F_c [N] per drive wheel
  double friction_presliding{5e-4};  ///< δ_p [m] (Dahl)
  double friction_smooth_rate{5e-3};  ///< v_s [m/s] (smooth Coulomb)
  // inertial_pitch: Γ_θ = (M_0 h + M_u h_u) a_x (nose-up when accelerating for h > 0): the
  // chair's and the occupant's centres of mass at their own heights above the contact line.
  double cm_lever{0.0};       ///< h [m], empty chair
  double load_cm_lever{0.0};  ///< h_u [m], occupant or dummy
  // marker_offset: the tracked origin sits at lever (r_x, r_z) in the chair frame, so
  // x_measured = x + r_x cos θ - r_z sin θ and Z_measured = Z + r_x sin θ + r_z (cos θ - 1): the
  // model places its wheels at x = x_measured - r_x cos θ + r_z sin θ (θ its own pitch state).
  double marker_lever_x{0.0};  ///< r_x [m], forward
  double marker_lever_z{0.0};  ///< r_z [m], up
};

inline constexpr double kHeaveRef = 0.01;          ///< [m] δ_ref of the heave hardening
inline constexpr double kPitchRef = 0.01;          ///< [rad] δ_ref of the pitch hardening
inline constexpr double kGravity = 9.81;           ///< [m/s^2]

struct ExtendedParams {
  LumpedParams lm;  ///< K, C of eq. (3) (re-identified together with the effect)
  EffectParams fx;
};

/// One trial ready to simulate: the chair (with gm), terrain, load and the sampled x(t).
struct PreparedTrial {
  Chair chair;
  Terrain terrain;
  double load_kg{0.0};
  std::vector<double> t;      ///< [s] sample times, strictly increasing
  std::vector<double> x;      ///< [m] O_V along the path at t
  std::vector<double> accel;  ///< [m/s^2] smoothed longitudinal acceleration at t
  std::vector<bool> is_caster;  ///< per wheel
  double step{1e-3};            ///< [s] internal grid step (identification's SimulationOptions::dt)

  /// Optional precomputed inputs on the grid of `cache_step` (CacheInputs): x and a_x on the
  /// grid, per wheel the point-contact ground height, and the point-contact GM output (Z, θ).
  /// Used only while cache_step == step.
  double cache_step{0.0};
  std::vector<double> x_grid;       ///< [m]
  std::vector<double> accel_grid;   ///< [m/s^2]
  std::vector<double> wheel_cache;  ///< [grid point][wheel] height
  std::vector<double> gm_cache;     ///< [grid point][z, pitch]
};

/// Fills the input caches of `trial` for its current step (speeds up repeated simulations,
/// e.g. in fits; the results are bit-identical to uncached runs).
void CacheInputs(PreparedTrial& trial);

/// Builds a PreparedTrial; `accel` is estimated from x by a local quadratic fit over
/// ±`accel_window` s unless given (same size as t). @pre chair.gm set, t strictly increasing.
PreparedTrial PrepareTrial(const Chair& chair, const Terrain& terrain, double load_kg,
                           std::vector<double> t, std::vector<double> x,
                           std::vector<double> accel = {}, double accel_window = 0.15);

/// Longitudinal acceleration of x(t): at each sample the curvature 2 c₂ of the least-squares
/// quadratic x ≈ c₀ + c₁τ + c₂τ² over the samples within ±`window` s (0 where fewer than five).
std::vector<double> EstimateAcceleration(const std::vector<double>& t, const std::vector<double>& x,
                                         double window = 0.15);

/// Casters: wheels named "*caster*" or clearly smaller than the largest wheel.
std::vector<bool> CasterWheels(const Chair& chair);

/// One value per wheel (the first `wheels` used).
using WheelArray = std::array<double, kMaxWheels>;

/// Each wheel's tyre compliance c_t [m/N]: the drive wheels' c_t; the casters' c_t, and ρ c_t
/// (EffectParams::rear_caster_compliance_ratio) for the casters behind O_V where there are
/// casters in front of it too (with casters on one side only, ρ would only rescale c_t).
WheelArray TyreCompliances(const EffectParams& fx, const PreparedTrial& trial);

/// Weighted least-squares plane through the wheel heights u_i at x_i, weights w_i:
/// [Σw Σwx; Σwx Σwx²] [Z; θ] = [Σ w u; Σ w x u], written Z = Σ z_i u_i, θ = Σ pitch_i u_i. The
/// same coefficients split a force F and torque Γ on the plane over the wheels,
/// R_i = z_i F + pitch_i Γ (Σ R_i = F, Σ x_i R_i = Γ). All zero when the weights do not fix a
/// plane (fewer than two weighted positions).
struct WheelPlane {
  WheelArray z{}, pitch{};
};
WheelPlane WeightedPlane(const WheelArray& w, const WheelArray& x, int wheels);

/// The extended model's output: pwsim::ModelOutput (sysid/measured/measured_trial.h) with the
/// GM output filled in.
using pwsim::ModelOutput;

/// Simulates the extended model at the trial's sample times (starts in static equilibrium).
ModelOutput SimulateExtended(const PreparedTrial& trial, const ExtendedParams& params);

/// Wheel-centre height minus R over a piecewise-linear ground (rolling-disc envelope) and its
/// x-derivative; R = 0 gives the ground itself.
struct EnvelopePoint {
  double height{0.0};  ///< [m]
  double slope{0.0};   ///< [-]
};
EnvelopePoint RollingDiscEnvelope(const Terrain& terrain, double x, double radius);

/// A trial as the diagnosis sees it: what was driven, on what, and what was measured.
struct TrialRecord {
  std::string name;
  Chair chair;  ///< with gm (lm used as the starting point of fits when present)
  Terrain terrain;
  double load_kg{0.0};
  double speed{0.0};          ///< [m/s] nominal (programmed or peak measured) speed
  std::vector<double> t;      ///< [s]
  std::vector<double> x;      ///< [m] measured O_V along the path
  std::vector<double> z;      ///< [m] measured altitude (any constant offset)
  std::vector<double> pitch;  ///< [rad] measured pitch (any constant offset)
  /// chair.gm was identified from these trials (diagnose::RecordsFromMeasured), not given: the
  /// diagnosis may identify it again once it knows where the marker sits.
  bool gm_from_trials{false};
};

/// Static wheel load W_i = α_i M g [N] (α as load share; used by cushion_compliance).
std::vector<double> StaticWheelLoads(const Chair& chair, double load_kg);

/// cushion_compliance's effective / nominal obstacle height under each wheel of `chair` (with
/// gm) at `load_kg`: max(0, g - c (W / 1 kN)^p), W the wheel's static load or the whole chair's
/// weight (fx.member.cushion_load); 1 for every wheel without the effect.
std::vector<double> CushionHeightFactors(const Chair& chair, double load_kg, const EffectParams& fx);

}  // namespace pwsim::effects
