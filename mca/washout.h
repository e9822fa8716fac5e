#pragma once
// Classical washout (Reid & Nahon structure) with tilt coordination, per axis:
//
//   surge/sway/heave:  f = fs_H - (0, 0, g)  → scale, clamp ±limit → H_hp(s) → 1/(s+λ)² → pose
//                      H_hp = s²/(s²+2ζωs+ω²) (order 2) or that · s/(s+ω_b) (order 3)
//   roll/pitch/yaw:    rate → scale, clamp ±limit → s/(s+ω) or s²/(s²+2ζωs+ω²) → 1/(s+λ) → pose
//   bank (roll, pitch):  the vehicle's attitude relative to gravity (HeadMotion::attitude)
//                      → 1 − H_hp(s) of that axis's rotation channel → clamped to ±max_angle →
//                      added to pose. With unit scale and no leak, rotation channel + bank
//                      = the attitude itself: a slope, a ramp or a banked road is presented as
//                      the real, sustained tilt it is, the rotation channel adding the onset.
//   tilt (pitch←surge, roll←sway): f_kin → scale → ω²/(s²+2ζωs+ω²) → asin(f/g), clamped to
//                      ±max_angle → rate limited to ±max_rate (default 3 deg/s) and acceleration
//                      limited to ±max_accel (the head sits above the pivot: a tilt acceleration
//                      θ̈ is felt as a tangential specific force h·θ̈) → added to pose;
//                      f_kin = fs − g·(sin θ, sin φ cos θ, ·) at the attitude (GravityAtAttitude):
//                      the part of the specific force that the bank does not already present
//                      (with the bank off, f_kin = fs: a slope is rendered by tilt, as before)
//
//   shape (roll, pitch):  the sum of the rotation channel, the bank and the tilt → a rate- and
//                      acceleration-limited follower (StepLimiter, mca/platform.h) with the
//                      platform file's axis box speed and acceleration (× shape.accel_scale) and
//                      the tilt band below as its rate window, stepped each tick from where the
//                      limiter left the platform (pose, rate) → the pose sent to the limiter, with
//                      its rate as the target's rate. A gap the limiter leaves (the tilt band's
//                      guard holds the rate at τ while the legs move heave) is then closed at the
//                      box's acceleration, not at the legs' (the limiter's own catch-up, Â_a).
//                      The head sits h = |head_from_pivot| from the pivot, so an angular
//                      acceleration θ̈ is felt as a tangential specific force h·θ̈: following a
//                      chair's pitch ringing (a few hundred deg/s²) up to what the legs can do
//                      (~1900 deg/s² on pw4dof) would push the head far harder than the chair did
//                      (a 300 deg/s² box keeps h·θ̈ ≤ 5 m/s² at h = 0.95 m). A target inside the
//                      box and the band (every slow motion) passes unchanged. Opt-in
//                      (shape.enabled, see ShapeParams).
//
// Then the pose goes through the platform limiter in actuator space (mca/actuator_limiter.h):
// every actuator inside its stroke, speed and acceleration, and the pitch and roll rates inside
// the tilt band B = [min(0, ω_f) − τ, max(0, ω_f) + τ] (ω_f the vehicle's own rate as the axis
// can follow it, τ = vestibular tilt-rate threshold, mca/mpc.h): the rotation beyond the
// vehicle's or against it — tilt coordination, the bank's approach and the rotation channel's
// return alike — is never faster than τ. The specific-force channels act on the head's
// specific force in head axes (no rotation into the inertial frame: the PW platform's tilts are
// small and the resulting coupling is second order); filters are exact FOH discretisations, so
// the behaviour does not depend on the step size.
//
// Faults: a non-finite input holds the last safe pose for fault.hold_time, then washes out to
// neutral at fault.return_speed_fraction of each axis's speed limit; filter states restart
// from rest, and when finite input returns the platform rejoins the washout output at the
// reduced speed before normal tracking resumes.
//
//   ClassicalWashout mca(DefaultWashoutParams(), MakePw4DofPlatform(), 1e-3);
//   const McaCommand& cmd = mca.Step(head_motion);   // one tick; no allocation

#include <array>
#include <cstdint>
#include <string>

#include "engine/yaml_reader.h"
#include "mca/actuator_limiter.h"
#include "mca/dof.h"
#include "mca/head_motion.h"
#include "mca/lti.h"
#include "mca/platform.h"

namespace pwsim::mca {

/// One specific-force channel (surge, sway or heave).
struct TranslationalParams {
  double scale{1.0};      ///< [-] gain on the specific-force deviation
  double limit{5.0};      ///< [m/s^2] clamp on the scaled input
  int hp_order{3};        ///< 2 or 3
  double hp_omega{2.0};   ///< ωn [rad/s] of the second-order high-pass
  double hp_zeta{1.0};    ///< ζ [-]
  double hp_break{0.5};   ///< ω_b [rad/s] of the first-order stage (order 3)
  double leak{0.0};       ///< λ [rad/s] of the double integrator 1/(s+λ)²
  bool operator==(const TranslationalParams&) const = default;
};

/// One angular-rate channel (roll, pitch or yaw).
struct RotationalParams {
  double scale{1.0};      ///< [-]
  double limit{1.0};      ///< [rad/s] clamp on the scaled rate
  int hp_order{2};        ///< 1 or 2
  double hp_omega{0.5};   ///< ω [rad/s]
  double hp_zeta{1.0};    ///< ζ [-] (order 2)
  double leak{0.0};       ///< λ [rad/s] of the integrator 1/(s+λ)
  bool operator==(const RotationalParams&) const = default;
};

/// Tilt coordination of one axis (pitch from surge, roll from sway).
struct TiltParams {
  bool enabled{true};
  double scale{1.0};                  ///< [-] on the specific force
  double lp_omega{2.0};               ///< ω [rad/s] of the second-order low-pass
  double lp_zeta{1.0};                ///< ζ [-]
  double max_rate{3.0 * kDegToRad};   ///< [rad/s], below the tilt-perception threshold
  /// [rad/s^2]; 10 deg/s² keeps h·θ̈ below 0.17 m/s² for a head up to 0.97 m above the pivot
  double max_accel{10.0 * kDegToRad};
  double max_angle{10.0 * kDegToRad}; ///< [rad]
  bool operator==(const TiltParams&) const = default;
};

/// The vehicle's sustained attitude presented as platform tilt (roll and pitch; see the header).
struct BankParams {
  bool enabled{true};
  double max_angle{10.0 * kDegToRad};  ///< [rad] per axis
  bool operator==(const BankParams&) const = default;
};

/// The roll and pitch shaping before the actuator limiter (see the header). Off by default: on
/// pw4dof it removes the limiter's catch-up spikes in surge at the head (speed cushion: 31.8 →
/// 7.0 m/s², the chair's own 10.2) but the pitch then waits at τ while the tilt band's guard
/// holds it (the legs moving heave), and the perceived-motion error rises (0.181 → 0.287);
/// docs/mca.md, "Pitch shaping".
struct ShapeParams {
  bool enabled{false};
  /// [-] on the platform file's box acceleration of roll and pitch (its speed is used as is)
  double accel_scale{1.0};
  bool operator==(const ShapeParams&) const = default;
};

struct FaultParams {
  double hold_time{0.5};               ///< [s] the last safe pose is held
  double return_speed_fraction{0.1};   ///< [-] of each axis's speed limit, while returning
  bool operator==(const FaultParams&) const = default;
};

struct WashoutParams {
  std::array<TranslationalParams, 3> translational{};  ///< surge, sway, heave
  std::array<RotationalParams, 3> rotational{};        ///< roll, pitch, yaw
  TiltParams tilt_pitch{};                             ///< pitch from surge specific force
  TiltParams tilt_roll{};                              ///< roll from sway specific force
  BankParams bank{};
  ShapeParams shape{};
  /// τ of the tilt band [rad/s]: not a scene key of its own, LoadMcaConfig sets it from
  /// mca.vestibular's tilt_rate_degps (one threshold for both algorithms)
  double tilt_rate_threshold{3.0 * kDegToRad};
  FaultParams fault{};
  bool operator==(const WashoutParams&) const = default;

  const TranslationalParams& translation(Dof dof) const;
  const RotationalParams& rotation(Dof dof) const;
  /// Empty when valid, else which field is wrong and why.
  std::string Validate() const;
};

/// The defaults documented in docs/mca.md (tuned for the PW platform and the speed cushion).
WashoutParams DefaultWashoutParams();
/// Reads an `mca:` mapping over `base`: every axis and every field optional.
/// @throws InputError (file, line, field, expected).
WashoutParams ParseWashoutParams(YamlMap& map, const WashoutParams& base);

/// Continuous transfer function from the channel input to the pose of one axis (for tests
/// and OMCT comparisons): scale · H_hp(s) · integrator.
ContinuousSystem ChannelSystem(const WashoutParams& params, Dof dof);

/// One tick of output: the platform command stream and the visual channel's tilt.
struct McaCommand {
  DofArray pose{};     ///< setpoint per axis [m | rad]; 0 for axes the platform lacks
  DofArray rate{};     ///< its rate over the last tick [m/s | rad/s]
  DofArray accel{};    ///< its acceleration [m/s^2 | rad/s^2]
  DofArray desired{};  ///< washout + bank + tilt, roll and pitch shaped, before the limiter
  double tilt_pitch{0.0};  ///< [rad] tilt-coordination part of the pitch (not to be seen)
  double tilt_roll{0.0};   ///< [rad] tilt-coordination part of the roll (not to be seen)
  /// [rad] the sustained attitude of the vehicle presented (a slope, a ramp, a banked road: a
  /// real tilt, shown by the visuals too), part of the pose's pitch and roll
  double bank_pitch{0.0};
  double bank_roll{0.0};
  /// [rad/s] the tilt-coordination rates, the platform's rotation beyond the vehicle's own or
  /// against it (TiltCoordinationRate, mca/actuator_limiter.h), held below the tilt-rate
  /// threshold by the limiter's tilt band. The false-cue count of the tilt rate
  /// (EvaluateConsistency) reads these.
  double tilt_rate_pitch{0.0};
  double tilt_rate_roll{0.0};
  bool fault{false};       ///< this tick's input was not finite
  bool operator==(const McaCommand&) const = default;
};

/// Everything the next tick needs (copyable, comparable).
struct WashoutState {
  std::array<FilterState, kDofCount> channel{};
  std::array<FilterState, 2> tilt_lp{};   ///< pitch, roll
  std::array<LimiterState, 2> tilt{};     ///< rate/acceleration-limited tilt (pitch, roll)
  std::array<double, 2> tilt_target{};    ///< asin(low-passed force / g) of the last tick
  std::array<FilterState, 2> bank{};      ///< bank filters (pitch, roll)
  std::array<double, 2> follow_rate{};    ///< ω_f of the tilt band (roll, pitch) [rad/s]
  std::array<LimiterState, 2> shape{};    ///< the shaped roll and pitch of the last tick (roll, pitch)
  std::array<double, 2> shape_target{};   ///< their targets of the last tick (roll, pitch)
  HeadMotion held{};                      ///< the last finite input (ω_f during a fault)
  DofArray desired_prev{};
  DofArray hold_pose{};
  std::array<double, 2> tilt_hold{};      ///< tilt angles held during a fault's hold time
  std::int64_t fault_ticks{0};    ///< consecutive faulted ticks (0 = healthy)
  bool recovering{false};
  std::int64_t fault_total{0};    ///< faulted ticks since Reset
  bool operator==(const WashoutState&) const = default;
};

class ClassicalWashout {
 public:
  /// @pre params.Validate() and platform.Validate() are empty; dt > 0.
  ClassicalWashout(const WashoutParams& params, const PlatformSpec& platform, double dt);

  /// Back to neutral at rest.
  void Reset();
  /// Advances one tick with the head motion of this tick. No allocation.
  const McaCommand& Step(const HeadMotion& input);

  const WashoutState& state() const { return state_; }
  const McaCommand& command() const { return command_; }
  const WashoutParams& params() const { return params_; }
  const PlatformSpec& platform() const { return platform_; }
  /// The limiter in actuator space: actuator positions, rates, accelerations of the command.
  const ActuatorLimiter& limiter() const { return limiter_; }
  double dt() const { return dt_; }

 private:
  void StepHealthy(const HeadMotion& input);
  void StepFaulted();
  void TiltStep(int axis, double target);
  void Follow(const HeadMotion& vehicle);
  /// Roll and pitch of `desired` through the shaping (feed_forward false: a held target).
  void Shape(DofArray* desired, bool feed_forward);
  void Limit(const DofArray& desired, double speed_fraction);

  WashoutParams params_;
  PlatformSpec platform_;
  double dt_;
  double inv_dt_;
  std::array<DiscreteSystem, kDofCount> channel_{};
  std::array<DiscreteSystem, 2> tilt_lp_{};
  std::array<double, 2> tilt_sin_max_{};
  std::array<DofLimits, 2> tilt_limits_{};
  std::array<DiscreteSystem, 2> bank_{};   ///< 1 − H_hp of pitch, roll
  std::array<double, 2> band_accel_{};     ///< A of roll, pitch: ω_f's rate of change [rad/s²]
  std::array<DofLimits, 2> shape_limits_{};  ///< roll, pitch: box speed and accel, no travel
  std::int64_t hold_ticks_{0};
  ActuatorLimiter limiter_;
  WashoutState state_;
  McaCommand command_;
};

}  // namespace pwsim::mca
