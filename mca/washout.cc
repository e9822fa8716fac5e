#include "mca/washout.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

constexpr std::array<Dof, 3> kTranslations{Dof::kSurge, Dof::kSway, Dof::kHeave};
constexpr std::array<Dof, 3> kRotations{Dof::kRoll, Dof::kPitch, Dof::kYaw};
constexpr double kRejoinTolerance = 1e-6;  ///< [m | rad] recovery ends when this close

std::size_t At(Dof dof) { return static_cast<std::size_t>(Index(dof)); }

bool Finite(const HeadMotion& m) {
  for (double v : m.fs) {
    if (!std::isfinite(v)) return false;
  }
  for (double v : m.w) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

/// The tilt target asin(f/g), clamped to ±max_angle (s_max = sin(max_angle)).
double TiltTarget(double s_max, double force_lp) {
  return std::asin(std::clamp(force_lp / kGravity, -s_max, s_max));
}

/// The tilt angle as an axis of its own: travel max_angle, speed max_rate, accel max_accel.
DofLimits TiltLimits(const TiltParams& p) {
  return {.present = true, .travel = p.max_angle, .speed = p.max_rate, .accel = p.max_accel};
}

/// 1 − H(s): the complement of a filter (same states, output negated, feed-through 1 − D).
ContinuousSystem Complement(const ContinuousSystem& h) {
  ContinuousSystem c = h;
  for (double& v : c.c) v = -v;
  c.d = 1.0 - h.d;
  return c;
}

/// The rotation channel's high-pass of one axis (unit scale, no integrator).
ContinuousSystem RotationHighPass(const RotationalParams& p) {
  return p.hp_order == 1 ? HighPass1(p.hp_omega) : HighPass2(p.hp_omega, p.hp_zeta);
}

void ParseTranslational(YamlMap& m, TranslationalParams& p) {
  p.scale = m.NumberOr("scale", p.scale, Range::Closed(0.0, 10.0));
  p.limit = m.NumberOr("limit_mps2", p.limit, Range::Positive(100.0, "m/s^2"));
  p.hp_order = m.IntegerOr("hp_order", p.hp_order, 2, 3);
  p.hp_omega = m.NumberOr("hp_omega_radps", p.hp_omega, Range::Positive(100.0, "rad/s"));
  p.hp_zeta = m.NumberOr("hp_zeta", p.hp_zeta, Range::Positive(10.0));
  p.hp_break = m.NumberOr("hp_break_radps", p.hp_break, Range::Positive(100.0, "rad/s"));
  p.leak = m.NumberOr("leak_radps", p.leak, Range::Closed(0.0, 100.0, "rad/s"));
}

void ParseRotational(YamlMap& m, RotationalParams& p) {
  p.scale = m.NumberOr("scale", p.scale, Range::Closed(0.0, 10.0));
  p.limit = kDegToRad * m.NumberOr("limit_degps", p.limit / kDegToRad, Range::Positive(3600.0, "deg/s"));
  p.hp_order = m.IntegerOr("hp_order", p.hp_order, 1, 2);
  p.hp_omega = m.NumberOr("hp_omega_radps", p.hp_omega, Range::Positive(100.0, "rad/s"));
  p.hp_zeta = m.NumberOr("hp_zeta", p.hp_zeta, Range::Positive(10.0));
  p.leak = m.NumberOr("leak_radps", p.leak, Range::Closed(0.0, 100.0, "rad/s"));
}

void ParseTilt(YamlMap& m, TiltParams& p) {
  p.enabled = m.BoolOr("enabled", p.enabled);
  p.scale = m.NumberOr("scale", p.scale, Range::Closed(0.0, 10.0));
  p.lp_omega = m.NumberOr("lp_omega_radps", p.lp_omega, Range::Positive(100.0, "rad/s"));
  p.lp_zeta = m.NumberOr("lp_zeta", p.lp_zeta, Range::Positive(10.0));
  p.max_rate =
      kDegToRad * m.NumberOr("max_rate_degps", p.max_rate / kDegToRad, Range::Positive(90.0, "deg/s"));
  p.max_angle =
      kDegToRad * m.NumberOr("max_angle_deg", p.max_angle / kDegToRad, Range::Positive(60.0, "deg"));
  p.max_accel = kDegToRad * m.NumberOr("max_accel_degps2", p.max_accel / kDegToRad,
                                       Range::Positive(10000.0, "deg/s^2"));
}

}  // namespace

const TranslationalParams& WashoutParams::translation(Dof dof) const {
  PWSIM_DEMAND(!IsRotational(dof));
  return translational[At(dof)];
}

const RotationalParams& WashoutParams::rotation(Dof dof) const {
  PWSIM_DEMAND(IsRotational(dof));
  return rotational[At(dof) - 3];
}

std::string WashoutParams::Validate() const {
  for (Dof dof : kTranslations) {
    const TranslationalParams& p = translation(dof);
    const std::string name(DofName(dof));
    if (!(p.scale >= 0.0) || !(p.limit > 0.0)) return name + ": scale >= 0 and limit > 0 required";
    if (p.hp_order != 2 && p.hp_order != 3) return name + ": hp_order must be 2 or 3";
    if (!(p.hp_omega > 0.0) || !(p.hp_zeta > 0.0) || !(p.hp_break > 0.0)) {
      return name + ": high-pass frequencies and damping must be > 0";
    }
    if (!(p.leak >= 0.0)) return name + ": leak must be >= 0";
  }
  for (Dof dof : kRotations) {
    const RotationalParams& p = rotation(dof);
    const std::string name(DofName(dof));
    if (!(p.scale >= 0.0) || !(p.limit > 0.0)) return name + ": scale >= 0 and limit > 0 required";
    if (p.hp_order != 1 && p.hp_order != 2) return name + ": hp_order must be 1 or 2";
    if (!(p.hp_omega > 0.0) || !(p.hp_zeta > 0.0)) return name + ": high-pass must be > 0";
    if (!(p.leak >= 0.0)) return name + ": leak must be >= 0";
  }
  for (const TiltParams* t : {&tilt_pitch, &tilt_roll}) {
    if (!(t->scale >= 0.0) || !(t->lp_omega > 0.0) || !(t->lp_zeta > 0.0) || !(t->max_rate > 0.0) || !(t->max_accel > 0.0) ||
        !(t->max_angle > 0.0 && t->max_angle <= 60.0 * kDegToRad)) {
      return std::string(t == &tilt_pitch ? "tilt_pitch" : "tilt_roll") +
             ": scale >= 0, low-pass > 0, max_rate > 0, max_accel > 0, max_angle in (0, 60] deg required";
    }
  }
  if (!(bank.max_angle > 0.0 && bank.max_angle <= 60.0 * kDegToRad)) return "bank: max_angle in (0, 60] deg required";
  if (!(shape.accel_scale > 0.0) || !std::isfinite(shape.accel_scale)) return "shape: accel_scale > 0 required";
  if (!(tilt_rate_threshold > 0.0) || !std::isfinite(tilt_rate_threshold)) return "tilt_rate_threshold must be > 0";
  if (!(fault.hold_time >= 0.0) || !(fault.return_speed_fraction > 0.0) ||
      !(fault.return_speed_fraction <= 1.0)) {
    return "fault: hold_s >= 0 and return_speed_fraction in (0, 1] required";
  }
  return {};
}

WashoutParams DefaultWashoutParams() {
  WashoutParams p;
  for (Dof dof : kTranslations) {
    p.translational[At(dof)] = {.scale = 1.0, .limit = 5.0, .hp_order = 3, .hp_omega = 2.0,
                                .hp_zeta = 1.0, .hp_break = 0.5, .leak = 0.0};
  }
  // heave: the cushion's bumps are short; a faster washout keeps them inside the travel
  p.translational[At(Dof::kHeave)] = {.scale = 0.8, .limit = 9.0, .hp_order = 3, .hp_omega = 3.0,
                                      .hp_zeta = 1.0, .hp_break = 0.5, .leak = 0.0};
  for (Dof dof : kRotations) {
    p.rotational[At(dof) - 3] = {.scale = 1.0, .limit = 60.0 * kDegToRad, .hp_order = 2,
                                 .hp_omega = 0.5, .hp_zeta = 1.0, .leak = 0.0};
  }
  p.tilt_pitch = TiltParams{};
  p.tilt_roll = TiltParams{};
  p.fault = FaultParams{};
  return p;
}

WashoutParams ParseWashoutParams(YamlMap& map, const WashoutParams& base) {
  WashoutParams p = base;
  for (Dof dof : kTranslations) {
    const std::string key(DofName(dof));
    if (!map.Has(key)) continue;
    YamlMap axis = map.Map(key);
    ParseTranslational(axis, p.translational[At(dof)]);
    axis.Finish();
  }
  for (Dof dof : kRotations) {
    const std::string key(DofName(dof));
    if (!map.Has(key)) continue;
    YamlMap axis = map.Map(key);
    ParseRotational(axis, p.rotational[At(dof) - 3]);
    axis.Finish();
  }
  for (auto [key, tilt] : {std::pair{"tilt_pitch", &p.tilt_pitch}, std::pair{"tilt_roll", &p.tilt_roll}}) {
    if (!map.Has(key)) continue;
    YamlMap axis = map.Map(key);
    ParseTilt(axis, *tilt);
    axis.Finish();
  }
  if (map.Has("bank")) {
    YamlMap bank = map.Map("bank");
    p.bank.enabled = bank.BoolOr("enabled", p.bank.enabled);
    p.bank.max_angle = kDegToRad * bank.NumberOr("max_angle_deg", p.bank.max_angle / kDegToRad,
                                                 Range::Positive(60.0, "deg"));
    bank.Finish();
  }
  if (map.Has("shape")) {
    YamlMap shape = map.Map("shape");
    p.shape.enabled = shape.BoolOr("enabled", p.shape.enabled);
    p.shape.accel_scale = shape.NumberOr("accel_scale", p.shape.accel_scale, Range::Positive(100.0));
    shape.Finish();
  }
  if (map.Has("fault")) {
    YamlMap fault = map.Map("fault");
    p.fault.hold_time = fault.NumberOr("hold_s", p.fault.hold_time, Range::Closed(0.0, 60.0, "s"));
    p.fault.return_speed_fraction = fault.NumberOr(
        "return_speed_fraction", p.fault.return_speed_fraction, Range::Positive(1.0));
    fault.Finish();
  }
  if (const std::string problem = p.Validate(); !problem.empty()) {
    map.Fail("", "consistent washout parameters (" + problem + ")", "inconsistent ones");
  }
  return p;
}

ContinuousSystem ChannelSystem(const WashoutParams& params, Dof dof) {
  if (IsRotational(dof)) {
    const RotationalParams& p = params.rotation(dof);
    const ContinuousSystem hp =
        p.hp_order == 1 ? HighPass1(p.hp_omega) : HighPass2(p.hp_omega, p.hp_zeta);
    return Series(Series(Gain(p.scale), hp), LeakyIntegrator(p.leak));
  }
  const TranslationalParams& p = params.translation(dof);
  ContinuousSystem hp = HighPass2(p.hp_omega, p.hp_zeta);
  if (p.hp_order == 3) hp = Series(hp, HighPass1(p.hp_break));
  const ContinuousSystem integrate = Series(LeakyIntegrator(p.leak), LeakyIntegrator(p.leak));
  return Series(Series(Gain(p.scale), hp), integrate);
}

ClassicalWashout::ClassicalWashout(const WashoutParams& params, const PlatformSpec& platform,
                                   double dt)
    : params_(params),
      platform_(platform),
      dt_(dt),
      inv_dt_(1.0 / dt),
      limiter_(platform, dt, TiltGuards(platform, params.tilt_rate_threshold)) {
  PWSIM_DEMAND(params.Validate().empty());
  PWSIM_DEMAND(platform.Validate().empty());
  PWSIM_DEMAND(dt > 0.0);
  // the scale is applied before the input clamp, so the filters run unscaled
  WashoutParams unscaled = params;
  for (auto& t : unscaled.translational) t.scale = 1.0;
  for (auto& r : unscaled.rotational) r.scale = 1.0;
  for (Dof dof : kAllDofs) channel_[At(dof)] = Discretize(ChannelSystem(unscaled, dof), dt);
  tilt_lp_[0] = Discretize(LowPass2(params.tilt_pitch.lp_omega, params.tilt_pitch.lp_zeta), dt);
  tilt_lp_[1] = Discretize(LowPass2(params.tilt_roll.lp_omega, params.tilt_roll.lp_zeta), dt);
  tilt_sin_max_ = {std::sin(params.tilt_pitch.max_angle), std::sin(params.tilt_roll.max_angle)};
  tilt_limits_ = {TiltLimits(params.tilt_pitch), TiltLimits(params.tilt_roll)};
  bank_[0] = Discretize(Complement(RotationHighPass(params.rotation(Dof::kPitch))), dt);
  bank_[1] = Discretize(Complement(RotationHighPass(params.rotation(Dof::kRoll))), dt);
  band_accel_ = {platform.Has(Dof::kRoll) ? platform.limits(Dof::kRoll).brake_accel() : 0.0,
                 platform.Has(Dof::kPitch) ? platform.limits(Dof::kPitch).brake_accel() : 0.0};
  for (auto [i, dof] : {std::pair{0, Dof::kRoll}, std::pair{1, Dof::kPitch}}) {
    if (!platform.Has(dof)) continue;
    const DofLimits& box = platform.limits(dof);
    shape_limits_[static_cast<std::size_t>(i)] = {.present = true, .travel = kUnlimited, .speed = box.speed,
                                                  .accel = params.shape.accel_scale * box.accel};
  }
  hold_ticks_ = static_cast<std::int64_t>(std::llround(params.fault.hold_time / dt));
  Reset();
}

void ClassicalWashout::Reset() {
  state_ = WashoutState{};
  command_ = McaCommand{};
  limiter_.Reset();
}

void ClassicalWashout::Follow(const HeadMotion& vehicle) {
  state_.follow_rate[0] = StepFollowRate(state_.follow_rate[0], vehicle.w[0], band_accel_[0], dt_);
  state_.follow_rate[1] = StepFollowRate(state_.follow_rate[1], -vehicle.w[1], band_accel_[1], dt_);
}

const McaCommand& ClassicalWashout::Step(const HeadMotion& input) {
  if (Finite(input)) {
    StepHealthy(input);
  } else {
    StepFaulted();
  }
  return command_;
}

void ClassicalWashout::StepHealthy(const HeadMotion& input) {
  if (state_.fault_ticks > 0) {
    state_.fault_ticks = 0;
    state_.recovering = true;
  }
  state_.held = input;
  Follow(input);
  DofArray desired{};
  // specific-force channels on the deviation from rest (0, 0, g)
  const std::array<double, 3> deviation{input.fs[0], input.fs[1], input.fs[2] - kGravity};
  for (Dof dof : kTranslations) {
    if (!platform_.Has(dof)) continue;
    const TranslationalParams& p = params_.translation(dof);
    const double u = std::clamp(p.scale * deviation[At(dof)], -p.limit, p.limit);
    desired[At(dof)] = mca::Step(channel_[At(dof)], state_.channel[At(dof)], u);
  }
  // angular-rate channels
  const std::array<double, 3> rates = CueRates(input);
  for (Dof dof : kRotations) {
    if (!platform_.Has(dof)) continue;
    const RotationalParams& p = params_.rotation(dof);
    const double u = std::clamp(p.scale * rates[At(dof) - 3], -p.limit, p.limit);
    desired[At(dof)] = mca::Step(channel_[At(dof)], state_.channel[At(dof)], u);
  }
  // bank: the sustained attitude, the complement of the rotation channel's high-pass
  std::array<double, 3> kinematic = input.fs;  // the specific force the bank does not present
  if (params_.bank.enabled) {
    const std::array<double, 3> gravity = GravityAtAttitude(input.attitude);
    kinematic[0] -= gravity[0];
    kinematic[1] -= gravity[1];
    const double limit = params_.bank.max_angle;
    if (platform_.Has(Dof::kPitch)) {
      command_.bank_pitch = std::clamp(mca::Step(bank_[0], state_.bank[0], input.attitude[1]), -limit, limit);
      desired[At(Dof::kPitch)] += command_.bank_pitch;
    }
    if (platform_.Has(Dof::kRoll)) {
      command_.bank_roll = std::clamp(mca::Step(bank_[1], state_.bank[1], input.attitude[0]), -limit, limit);
      desired[At(Dof::kRoll)] += command_.bank_roll;
    }
  }
  // tilt coordination: sustained surge -> pitch, sustained sway -> roll
  if (platform_.Has(Dof::kPitch) && params_.tilt_pitch.enabled) {
    const double f = mca::Step(tilt_lp_[0], state_.tilt_lp[0], params_.tilt_pitch.scale * kinematic[0]);
    TiltStep(0, TiltTarget(tilt_sin_max_[0], f));
    desired[At(Dof::kPitch)] += state_.tilt[0].pose;
  }
  if (platform_.Has(Dof::kRoll) && params_.tilt_roll.enabled) {
    const double f = mca::Step(tilt_lp_[1], state_.tilt_lp[1], params_.tilt_roll.scale * kinematic[1]);
    TiltStep(1, TiltTarget(tilt_sin_max_[1], f));
    desired[At(Dof::kRoll)] += state_.tilt[1].pose;
  }
  Shape(&desired, true);
  Limit(desired, state_.recovering ? params_.fault.return_speed_fraction : 1.0);
  if (state_.recovering) {
    bool joined = true;
    for (Dof dof : kAllDofs) {
      if (std::abs(command_.pose[At(dof)] - desired[At(dof)]) > kRejoinTolerance) joined = false;
    }
    state_.recovering = !joined;
  }
  command_.fault = false;
}

void ClassicalWashout::StepFaulted() {
  if (state_.fault_ticks == 0) {
    // hold the last safe pose; the filters restart from rest when input returns
    state_.hold_pose = limiter_.pose();
    state_.tilt_hold = {state_.tilt[0].pose, state_.tilt[1].pose};
    state_.channel = {};
    state_.tilt_lp = {};
    state_.bank = {};
  }
  ++state_.fault_ticks;
  // the tilt band's vehicle rate: the last finite input for hold_s, then rest
  Follow(state_.fault_ticks <= hold_ticks_ ? state_.held : HeadMotion{});
  command_.bank_pitch = command_.bank_roll = 0.0;
  ++state_.fault_total;
  state_.recovering = false;
  DofArray desired{};
  const bool holding = state_.fault_ticks <= hold_ticks_;
  if (holding) {
    // the tilt stops within its acceleration limit, the pose is held
    TiltStep(0, state_.tilt_hold[0]);
    TiltStep(1, state_.tilt_hold[1]);
    desired = state_.hold_pose;
  } else {
    // wash out to neutral; the tilt returns below the perception threshold
    TiltStep(0, 0.0);
    TiltStep(1, 0.0);
    desired[At(Dof::kPitch)] = platform_.Has(Dof::kPitch) ? state_.tilt[0].pose : 0.0;
    desired[At(Dof::kRoll)] = platform_.Has(Dof::kRoll) ? state_.tilt[1].pose : 0.0;
  }
  state_.desired_prev = desired;  // targets are piecewise constant: no feed-forward
  Shape(&desired, false);
  Limit(desired, holding ? 1.0 : params_.fault.return_speed_fraction);
  command_.fault = true;
}

void ClassicalWashout::TiltStep(int axis, double target) {
  const auto i = static_cast<std::size_t>(axis);
  const TiltParams& p = axis == 0 ? params_.tilt_pitch : params_.tilt_roll;
  const double target_rate = (target - state_.tilt_target[i]) * inv_dt_;
  state_.tilt[i] = StepLimiter(tilt_limits_[i], state_.tilt[i], target, target_rate, p.max_rate, dt_);
  state_.tilt_target[i] = target;
}

void ClassicalWashout::Shape(DofArray* desired, bool feed_forward) {
  if (!params_.shape.enabled) return;
  for (auto [i, dof] : {std::pair{std::size_t{0}, Dof::kRoll}, std::pair{std::size_t{1}, Dof::kPitch}}) {
    if (!platform_.Has(dof)) continue;
    const std::size_t d = At(dof);
    const double target = (*desired)[d];
    const double target_rate = feed_forward ? (target - state_.shape_target[i]) * inv_dt_ : 0.0;
    // from where the platform is: a gap the limiter left is closed at the box's pace
    const LimiterState now{.pose = limiter_.pose()[d], .rate = limiter_.rate()[d], .accel = limiter_.accel()[d]};
    state_.shape[i] = StepLimiter(shape_limits_[i], now, target, target_rate,
                                  TiltBand(state_.follow_rate[i], params_.tilt_rate_threshold), dt_);
    state_.shape_target[i] = target;
    (*desired)[d] = state_.shape[i].pose;
    state_.desired_prev[d] = now.pose;  // the limiter's target rate: this shaped step
  }
}

void ClassicalWashout::Limit(const DofArray& desired, double speed_fraction) {
  DofArray target_rate{};
  for (std::size_t i = 0; i < kDofCount; ++i) target_rate[i] = (desired[i] - state_.desired_prev[i]) * inv_dt_;
  std::array<RateWindow, kDofCount> windows{};
  if (platform_.Has(Dof::kRoll)) windows[At(Dof::kRoll)] = TiltBand(state_.follow_rate[0], params_.tilt_rate_threshold);
  if (platform_.Has(Dof::kPitch)) windows[At(Dof::kPitch)] = TiltBand(state_.follow_rate[1], params_.tilt_rate_threshold);
  limiter_.Step(desired, target_rate, windows, speed_fraction);
  for (Dof dof : kAllDofs) {
    const std::size_t i = At(dof);
    if (!platform_.Has(dof)) continue;
    command_.pose[i] = limiter_.pose()[i];
    command_.rate[i] = limiter_.rate()[i];
    command_.accel[i] = limiter_.accel()[i];
  }
  state_.desired_prev = desired;
  command_.desired = desired;
  command_.tilt_rate_pitch =
      platform_.Has(Dof::kPitch) ? TiltCoordinationRate(command_.rate[At(Dof::kPitch)], state_.follow_rate[1]) : 0.0;
  command_.tilt_rate_roll =
      platform_.Has(Dof::kRoll) ? TiltCoordinationRate(command_.rate[At(Dof::kRoll)], state_.follow_rate[0]) : 0.0;
  command_.tilt_pitch = state_.tilt[0].pose;
  command_.tilt_roll = state_.tilt[1].pose;
}

}  // namespace pwsim::mca
