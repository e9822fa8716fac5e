#include "mca/vestibular.h"

#include <cmath>

#include "engine/check.h"

namespace pwsim::mca {

std::string VestibularParams::Validate() const {
  const OtolithParams& o = otolith;
  if (!(o.gain > 0.0 && o.tau_a > 0.0 && o.tau_l > 0.0 && o.tau_s > 0.0)) {
    return "otolith: gain and time constants must be > 0";
  }
  if (!(canals.tau_a > 0.0 && canals.tau_s > 0.0)) return "canals: time constants must be > 0";
  for (double t : canals.tau_l) {
    if (!(t > 0.0)) return "canals: time constants must be > 0";
  }
  for (double t : thresholds.fs) {
    if (!(t > 0.0)) return "thresholds: must be > 0";
  }
  for (double t : thresholds.w) {
    if (!(t > 0.0)) return "thresholds: must be > 0";
  }
  if (!(thresholds.tilt_rate > 0.0)) return "thresholds: must be > 0";
  return {};
}

VestibularParams ParseVestibularParams(YamlMap& map, const VestibularParams& base) {
  VestibularParams p = base;
  const Range time = Range::Positive(1000.0, "s");
  if (map.Has("otolith")) {
    YamlMap o = map.Map("otolith");
    p.otolith.gain = o.NumberOr("gain", p.otolith.gain, Range::Positive(100.0));
    p.otolith.tau_a = o.NumberOr("tau_a_s", p.otolith.tau_a, time);
    p.otolith.tau_l = o.NumberOr("tau_l_s", p.otolith.tau_l, time);
    p.otolith.tau_s = o.NumberOr("tau_s_s", p.otolith.tau_s, time);
    o.Finish();
  }
  if (map.Has("canals")) {
    YamlMap c = map.Map("canals");
    p.canals.tau_a = c.NumberOr("tau_a_s", p.canals.tau_a, time);
    p.canals.tau_s = c.NumberOr("tau_s_s", p.canals.tau_s, time);
    p.canals.tau_l[0] = c.NumberOr("tau_l_roll_s", p.canals.tau_l[0], time);
    p.canals.tau_l[1] = c.NumberOr("tau_l_pitch_s", p.canals.tau_l[1], time);
    p.canals.tau_l[2] = c.NumberOr("tau_l_yaw_s", p.canals.tau_l[2], time);
    c.Finish();
  }
  if (map.Has("thresholds")) {
    YamlMap t = map.Map("thresholds");
    const Range force = Range::Positive(10.0, "m/s^2");
    const Range rate = Range::Positive(90.0, "deg/s");
    p.thresholds.fs[0] = t.NumberOr("surge_mps2", p.thresholds.fs[0], force);
    p.thresholds.fs[1] = t.NumberOr("sway_mps2", p.thresholds.fs[1], force);
    p.thresholds.fs[2] = t.NumberOr("heave_mps2", p.thresholds.fs[2], force);
    p.thresholds.w[0] = kDegToRad * t.NumberOr("roll_degps", p.thresholds.w[0] / kDegToRad, rate);
    p.thresholds.w[1] = kDegToRad * t.NumberOr("pitch_degps", p.thresholds.w[1] / kDegToRad, rate);
    p.thresholds.w[2] = kDegToRad * t.NumberOr("yaw_degps", p.thresholds.w[2] / kDegToRad, rate);
    p.thresholds.tilt_rate =
        kDegToRad * t.NumberOr("tilt_rate_degps", p.thresholds.tilt_rate / kDegToRad, rate);
    t.Finish();
  }
  return p;
}

ContinuousSystem OtolithSystem(const OtolithParams& p) {
  return FromTransferFunction({p.gain * p.tau_a, p.gain},
                              PolyMultiply({p.tau_l, 1.0}, {p.tau_s, 1.0}));
}

ContinuousSystem CanalSystem(const CanalParams& p, int axis) {
  PWSIM_DEMAND(axis >= 0 && axis < 3);
  const double tau_l = p.tau_l[static_cast<std::size_t>(axis)];
  return FromTransferFunction({p.tau_a * tau_l, 0.0, 0.0},
                              PolyMultiply(PolyMultiply({p.tau_a, 1.0}, {tau_l, 1.0}), {p.tau_s, 1.0}));
}

VestibularModel::VestibularModel(const VestibularParams& params, double dt) {
  PWSIM_DEMAND(params.Validate().empty());
  for (int axis = 0; axis < 3; ++axis) {
    const auto i = static_cast<std::size_t>(axis);
    otolith_[i] = Discretize(OtolithSystem(params.otolith), dt);
    canal_[i] = Discretize(CanalSystem(params.canals, axis), dt);
  }
}

void VestibularModel::Reset() {
  otolith_state_ = {};
  canal_state_ = {};
}

Perceived VestibularModel::Step(const HeadMotion& motion) {
  Perceived out;
  const std::array<double, 3> deviation{motion.fs[0], motion.fs[1], motion.fs[2] - kGravity};
  for (std::size_t i = 0; i < 3; ++i) {
    const double f = std::isfinite(deviation[i]) ? deviation[i] : 0.0;
    const double w = std::isfinite(motion.w[i]) ? motion.w[i] : 0.0;
    out.fs[i] = mca::Step(otolith_[i], otolith_state_[i], f);
    out.w[i] = mca::Step(canal_[i], canal_state_[i], w);
  }
  return out;
}

}  // namespace pwsim::mca
