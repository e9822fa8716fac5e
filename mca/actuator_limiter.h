#pragma once
// The platform limiter in actuator space: every tick, the next pose x_k+1 of the platform top
// (P relative to B, mca/mechanism.h) such that every actuator of the mechanism stays inside its
// stroke, speed and acceleration, whatever the target, and such that the pose rate of an axis
// given a rate window (the tilt band on roll and pitch, mca/mpc.h) stays inside that window.
// The cueing (mca/washout.h, mca/mpc.h) gives a target pose and its rate; this unit alone decides
// what the drives get. The axis boxes of the platform file play no part, except a stage's
// sustained-acceleration budget (DofLimits::steady_accel), which actuators do not carry.
//
// Actuator signals are differences of the positions the drives get, q_k = IK(x_k):
//   rate r_k = (q_k − q_k−1)/dt,   acceleration (r_k − r_k−1)/dt.
// Limits of actuator i: q_i ∈ [min_i, max_i], |r_i| ≤ v_i, |r_i,k − r_i,k−1| ≤ a_i dt, each held
// with a headroom of 1e-9 of the limit (1e-9 of the half-stroke at each end), so that the same
// figures recomputed from the poses elsewhere (another IK's rounding, differenced again: a few
// 1e-12 relative) still come out at or below the limit itself.
//
// Groups. A rail or rotary stage that no leg depends on drives its axis alone: it is limited by
// StepLimiter (mca/platform.h) on its stroke (asymmetric strokes about their centre), speed and
// acceleration, with its axis's rate window — the 1-D proof there. The legs, and any stage a leg
// length depends on, form the coupled group on their axes G (pw4dof: four legs on heave, roll,
// pitch; stewart6dof: six legs on all six axes); for them:
//
// Brake. From a state (x_k, x_k−1) with actuator rates r, the brake step scales the pose rate:
//   T = max_i |r_i| / ā_i   (ā_i = (1 − m) a_i, m = accel_margin),
//   x_k+1 = x_k + λ (x_k − x_k−1),   λ = 1 − dt/T if T > dt, else 0.
// Every actuator rate shrinks by about the same factor λ, so the slowest-braking actuator
// decelerates at ā and the others slower; the margin m absorbs what the kinematics' curvature
// adds (q̈ = J ẍ + ẋᵀ ∂²q/∂x² ẋ). The brake sequence of a state is the sequence of brake steps
// from it until the actuators are at rest (T = 0).
// Invariant S: the brake sequence of the current state keeps every actuator inside its stroke,
// speed and acceleration, and at each of its states (and the current one) every window axis t
// satisfies the guard  T ≤ dt  or  |ẋ_t| ≤ c_t  or  e_t T ≤ |ẋ_t|  (RateGuard: c_t the core every
// window contains, e_t the fastest its edges move). Each tick the limiter takes the largest
// s ∈ [0, 1] (tried: 1, then bisection) for which the pose rate  b + s (c − b)  — b the brake
// step's, c the candidate's (below) — gives a next state that meets this tick's limits and
// windows and satisfies S, the brake sequence simulated exactly (the same floating-point
// function as the step itself). s = 0 is always accepted, without a check:
//   (i)  the brake step is the first step of the brake sequence S vouched for: it meets every
//        actuator limit, and the next state's brake sequence is that sequence's tail, so S holds;
//   (ii) the window: for ẋ_t ≥ 0 (ẋ_t ≤ 0 is the mirror image) in the last window [L, U], the
//        brake rate λ ẋ_t lies in [0, ẋ_t]; 0 is in every window; if ẋ_t ≤ c_t then λ ẋ_t ≤ c_t ≤ U';
//        else the guard gives ẋ_t − λ ẋ_t = ẋ_t dt/T ≥ e_t dt, and U' ≥ U − e_t dt ≥ λ ẋ_t.
// From rest (S holds trivially) S holds on every tick by induction, and with it every actuator
// limit and every window; no argument about the kinematics' curvature is needed, as S is
// checked, not assumed. The cost is bounded: a brake sequence lasts at most max_i v_i/ā_i (plus
// rounding), 47 ticks at 1 kHz on pw4dof's legs, and the bisection tries at most 12 values.
//
// Candidate. Per axis of G the rate StepLimiter would take without limits: the target's rate
// plus the gap closed as fast as braking at Â_a allows, Â_a = min_i ā_i/|J_ia| at neutral (the
// axis alone); clamped to the window and to speed_fraction·V̂_a (V̂_a = min_i v_i/|J_ia|); its
// change from the current rate scaled so that the linearised actuator accelerations J Δẋ/dt stay
// within a_i. When the target is inside every limit the candidate is the target (dead-beat)
// and s = 1.
//
//   ActuatorLimiter limiter(platform, 1e-3, guards);
//   limiter.Step(target, target_rate, windows, 1.0);   // limiter.pose(), .position() ...

#include <array>
#include <cstdint>
#include <vector>

#include "mca/dof.h"
#include "mca/mechanism.h"
#include "mca/platform.h"

namespace pwsim::mca {

/// What a rate window of one axis promises [m/s | rad/s]: it always contains [−core, core],
/// and its edges move by at most edge_accel·dt per tick (the tilt band: core τ, edge_accel the
/// axis's brake acceleration, mca/mpc.h). The default: no window on this axis.
struct RateGuard {
  double core{kUnlimited};
  double edge_accel{0.0};
};

// The tilt band (the proof that it holds is in mca/mpc.h): ω_f, the vehicle's own rate on roll
// (w_x) or nose-up pitch (−w_y) as a platform braking at A can follow it,
//   ω_f,k = clamp(ω_veh,k, ω_f,k−1 − A dt, ω_f,k−1 + A dt),
// and the window B = [min(0, ω_f) − τ, max(0, ω_f) + τ] for the platform's rate (RateGuard{τ, A}).

/// ω_f: the vehicle's rate `vehicle_rate` as a platform braking at `brake_accel` can follow it,
/// one tick `dt` after `follow_rate`.
double StepFollowRate(double follow_rate, double vehicle_rate, double brake_accel, double dt);
/// The tilt band B = [min(0, ω_f) − τ, max(0, ω_f) + τ] for the platform's rate.
RateWindow TiltBand(double follow_rate, double threshold);
/// The tilt-coordination rate of a platform rate, the rotation beyond the vehicle's or against
/// it: r − clamp(r, min(0, ω_f), max(0, ω_f)).
double TiltCoordinationRate(double platform_rate, double follow_rate);

/// The tilt band's guards: on roll and pitch (where the platform has them), core τ = `threshold`,
/// edges moving at the axis's brake acceleration (its box's brake_accel()), the rate ω_f follows at.
std::array<RateGuard, kDofCount> TiltGuards(const PlatformSpec& platform, double threshold);

/// Counters of the limiter's work.
struct ActuatorLimiterStats {
  std::int64_t ticks{0};
  std::int64_t reduced{0};   ///< coupled-group ticks that took less than the candidate (s < 1)
  std::int64_t braked{0};    ///< of those, ticks that took the brake step (s = 0)
  std::int64_t simulated{0}; ///< brake steps simulated (the cost)
};

class ActuatorLimiter {
 public:
  /// @pre platform.mechanism valid (Mechanism::Validate empty) with at least one actuator; dt > 0;
  /// accel_margin in [0, 1).
  ActuatorLimiter(const PlatformSpec& platform, double dt, std::array<RateGuard, kDofCount> guards = {},
                  double accel_margin = 0.05);

  /// Neutral pose at rest.
  void Reset();
  /// One tick towards `target` moving at `target_rate` (axes the mechanism does not move are
  /// ignored and stay 0). `windows`: per axis, the rate window for this tick, each within its
  /// RateGuard's promise (RateWindow{} = none). `speed_fraction` in (0, 1] slows the approach
  /// (a soft limit: braking from a faster rate takes its time). No allocation.
  void Step(const DofArray& target, const DofArray& target_rate, const std::array<RateWindow, kDofCount>& windows,
            double speed_fraction = 1.0);

  const DofArray& pose() const { return pose_; }
  const DofArray& rate() const { return rate_; }     ///< (x_k − x_k−1)/dt
  const DofArray& accel() const { return accel_; }   ///< rate difference / dt
  const ActuatorVector& position() const { return q_; }
  const ActuatorVector& actuator_rate() const { return q_rate_; }
  const ActuatorVector& actuator_accel() const { return q_accel_; }
  const ActuatorLimiterStats& stats() const { return stats_; }
  const Mechanism& mechanism() const { return mechanism_; }
  /// Â_a, V̂_a of the header (coupled axes; 0 elsewhere).
  double axis_accel(Dof dof) const { return axis_accel_[static_cast<std::size_t>(Index(dof))]; }
  double axis_speed(Dof dof) const { return axis_speed_[static_cast<std::size_t>(Index(dof))]; }

  /// The actuators of the coupled group (legs and the stages they depend on), in order.
  const std::vector<int>& coupled_actuators() const { return coupled_; }
  /// Whether `dof` is an axis of the coupled group (else an independent stage drives it, or nothing).
  bool coupled(Dof dof) const { return coupled_axes_[static_cast<std::size_t>(Index(dof))]; }
  /// The 1-D limits of the independent stage driving `dof` (travel = half its stroke, about
  /// `centre`; the box's sustained budget) — false when no independent stage drives it.
  bool StageLimits(Dof dof, DofLimits* limits, double* centre) const;
  /// max over the coupled actuators of v_i / ā_i [s]: how long the brake step takes at most.
  double longest_brake() const { return longest_brake_; }

  /// Leg lengths and stage positions of the coupled group at `pose` (the group's entries of q;
  /// the others untouched): Mechanism::Inverse with the rotations formed once. false when a leg
  /// has no length. No allocation.
  bool CoupledPositions(const DofArray& pose, ActuatorVector* q) const;

 private:
  struct Stage {
    int actuator{0};
    Dof dof{Dof::kSurge};
    DofLimits limits;        ///< travel = half the stroke, about `centre`
    double centre{0.0};
  };
  /// Checks the coupled next state x' = x + rho·dt (this tick's limits, windows unless null,
  /// guards and the brake sequence, invariant S); writes the pose and positions on success.
  bool CoupledFeasible(const DofArray& rho, const std::array<RateWindow, kDofCount>* windows, DofArray* next_pose,
                       ActuatorVector* next_q);
  /// The brake step from (x_now, x_prev) with positions (q_now, q_prev): x_next and T.
  void BrakeStep(const DofArray& x_now, const DofArray& x_prev, const ActuatorVector& q_now,
                 const ActuatorVector& q_prev, DofArray* x_next, double* brake_time) const;
  /// This tick's actuator limits from (q_prev, q_now) to q_next, and the guards at (x_next, x_now).
  bool TickWithinLimits(const DofArray& x_now, const DofArray& x_next, const ActuatorVector& q_prev,
                        const ActuatorVector& q_now, const ActuatorVector& q_next) const;
  double BrakeTime(const ActuatorVector& q_now, const ActuatorVector& q_prev) const;

  Mechanism mechanism_;
  std::vector<Actuator> actuators_;     ///< the mechanism's, at hand for the per-tick loops
  double dt_;
  std::array<RateGuard, kDofCount> guards_;
  std::vector<Stage> stages_;           ///< the independent stages
  std::vector<int> coupled_;            ///< actuators of the coupled group
  DofMask coupled_axes_{};
  std::array<double, kDofCount> axis_accel_{}, axis_speed_{};
  std::vector<double> brake_accel_;     ///< ā_i per actuator
  int max_brake_ticks_{0};
  double longest_brake_{0.0};
  // the rotations' structure, for CoupledPositions
  double pivot_height_{0.0};
  DofMask stage_axes_{};
  DofMask coupled_or_leg_axes_{};      ///< the axes the coupled group's positions depend on
  bool coupled_stage_axes_any_{false};  ///< a stage in the coupled group (the legs' floor moves)
  // state
  DofArray pose_{}, pose_prev_{}, rate_{}, accel_{};
  ActuatorVector q_, q_prev_, q_rate_, q_accel_;
  std::array<LimiterState, kDofCount> stage_state_{};
  ActuatorLimiterStats stats_;
  // scratch
  ActuatorJacobian jacobian_;
  ActuatorVector sim_q_[3];
};

}  // namespace pwsim::mca
