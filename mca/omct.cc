#include "mca/omct.h"

#include <Eigen/Dense>
#include <cmath>

#include "engine/check.h"
#include "mca/cue_analysis.h"

namespace pwsim::mca {
namespace {

double Signal(const HeadMotion& m, OmctSignal s) {
  const std::array<double, 3> rates = CueRates(m);
  switch (s) {
    case OmctSignal::kFx: return m.fs[0];
    case OmctSignal::kFy: return m.fs[1];
    case OmctSignal::kFz: return m.fs[2] - kGravity;
    case OmctSignal::kP: return rates[0];
    case OmctSignal::kQ: return rates[1];
    case OmctSignal::kR: return rates[2];
  }
  return 0.0;
}

HeadMotion Excite(OmctSignal s, double value) {
  HeadMotion m;
  switch (s) {
    case OmctSignal::kFx: m.fs[0] = value; break;
    case OmctSignal::kFy: m.fs[1] = value; break;
    case OmctSignal::kFz: m.fs[2] += value; break;
    case OmctSignal::kP: m.w[0] = value; break;
    case OmctSignal::kQ: m.w[1] = -value; break;  // nose-up pitch rate is -w_y
    case OmctSignal::kR: m.w[2] = value; break;
  }
  return m;
}

bool IsForce(OmctSignal s) { return static_cast<int>(s) < 3; }

}  // namespace

const std::array<OmctTest, 10>& OmctTests() {
  static const std::array<OmctTest, 10> tests{{
      {"p_to_p", OmctSignal::kP, OmctSignal::kP},
      {"q_to_q", OmctSignal::kQ, OmctSignal::kQ},
      {"r_to_r", OmctSignal::kR, OmctSignal::kR},
      {"fx_to_fx", OmctSignal::kFx, OmctSignal::kFx},
      {"fy_to_fy", OmctSignal::kFy, OmctSignal::kFy},
      {"fz_to_fz", OmctSignal::kFz, OmctSignal::kFz},
      {"fx_to_q", OmctSignal::kFx, OmctSignal::kQ},
      {"fy_to_p", OmctSignal::kFy, OmctSignal::kP},
      {"q_to_fx", OmctSignal::kQ, OmctSignal::kFx},
      {"p_to_fy", OmctSignal::kP, OmctSignal::kFy},
  }};
  return tests;
}

std::array<double, 12> OmctFrequencies() {
  std::array<double, 12> f{};
  for (int k = -5; k <= 6; ++k) f[static_cast<std::size_t>(k + 5)] = std::pow(10.0, k / 5.0);
  return f;
}

bool OmctApplies(const OmctTest& test, const WashoutParams& params, const PlatformSpec& platform) {
  auto drives = [&](OmctSignal s) {
    switch (s) {
      case OmctSignal::kFx:
        return platform.Has(Dof::kSurge) || (platform.Has(Dof::kPitch) && params.tilt_pitch.enabled);
      case OmctSignal::kFy:
        return platform.Has(Dof::kSway) || (platform.Has(Dof::kRoll) && params.tilt_roll.enabled);
      case OmctSignal::kFz: return platform.Has(Dof::kHeave);
      case OmctSignal::kP: return platform.Has(Dof::kRoll);
      case OmctSignal::kQ: return platform.Has(Dof::kPitch);
      case OmctSignal::kR: return platform.Has(Dof::kYaw);
    }
    return false;
  };
  auto produces = [&](OmctSignal s) {
    switch (s) {
      case OmctSignal::kFx: return platform.Has(Dof::kSurge) || platform.Has(Dof::kPitch);
      case OmctSignal::kFy: return platform.Has(Dof::kSway) || platform.Has(Dof::kRoll);
      case OmctSignal::kFz: return platform.Has(Dof::kHeave);
      case OmctSignal::kP: return platform.Has(Dof::kRoll);
      case OmctSignal::kQ: return platform.Has(Dof::kPitch);
      case OmctSignal::kR: return platform.Has(Dof::kYaw);
    }
    return false;
  };
  return drives(test.input) && produces(test.output);
}

namespace {

/// Drives `step` (HeadMotion in, const McaCommand& out, one MCA tick each) with the test's
/// sinusoid and fits the delivered output over the measured window.
template <class StepFn>
OmctPoint MeasurePoint(const OmctTest& test, double frequency, const PlatformSpec& platform,
                       const OmctOptions& options, StepFn&& step) {
  PWSIM_DEMAND(frequency > 0.0 && options.rate_hz > 0.0);
  const double dt = 1.0 / options.rate_hz;
  const double period = 2.0 * kPi / frequency;
  const double amplitude = IsForce(test.input) ? options.force_amplitude : options.rate_amplitude;
  const double settle = std::max(options.settle_periods * period, options.settle_min);
  const auto settle_ticks = static_cast<std::int64_t>(std::ceil(settle / dt));
  const auto measure_ticks =
      static_cast<std::int64_t>(std::llround(options.measure_periods * period / dt));

  // run, keeping the poses of the measured window and one tick either side
  std::vector<DofArray> poses;
  poses.reserve(static_cast<std::size_t>(measure_ticks + 2));
  const std::int64_t first = settle_ticks - 1;
  const std::int64_t last = settle_ticks + measure_ticks;
  bool within_limits = true;
  for (std::int64_t tick = 0; tick <= last; ++tick) {
    const double t = static_cast<double>(tick) * dt;
    const McaCommand& command = step(Excite(test.input, amplitude * std::sin(frequency * t)));
    for (Dof dof : kAllDofs) {
      const DofLimits& limits = platform.limits(dof);
      const auto i = static_cast<std::size_t>(Index(dof));
      if (limits.present && !(std::abs(command.pose[i]) <= limits.travel)) within_limits = false;
    }
    if (tick >= first) poses.push_back(command.pose);
  }
  const std::vector<HeadMotion> delivered = DeliveredHeadMotion(platform, poses, dt);

  // least-squares fit y = a sin + b cos + c over the measured window
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (std::int64_t tick = settle_ticks; tick < last; ++tick) {
    const double t = static_cast<double>(tick) * dt;
    const Eigen::Vector3d basis(std::sin(frequency * t), std::cos(frequency * t), 1.0);
    const double y = Signal(delivered[static_cast<std::size_t>(tick - first)], test.output);
    normal += basis * basis.transpose();
    rhs += basis * y;
  }
  const Eigen::Vector3d coeff = normal.ldlt().solve(rhs);
  OmctPoint point;
  point.test = test.name;
  point.frequency = frequency;
  point.gain = std::hypot(coeff(0), coeff(1)) / amplitude;
  point.phase = std::atan2(coeff(1), coeff(0)) / kDegToRad;
  point.within_limits = within_limits;
  return point;
}

}  // namespace

OmctPoint RunOmctPoint(const OmctTest& test, double frequency, const WashoutParams& params,
                       const PlatformSpec& platform, const OmctOptions& options) {
  ClassicalWashout washout(params, platform, 1.0 / options.rate_hz);
  return MeasurePoint(test, frequency, platform, options,
                      [&washout](const HeadMotion& m) -> const McaCommand& { return washout.Step(m); });
}

OmctPoint RunOmctPoint(const OmctTest& test, double frequency, const McaConfig& config,
                       const OmctOptions& options) {
  if (config.algorithm == McaAlgorithm::kWashout) {
    return RunOmctPoint(test, frequency, config.washout, config.platform, options);
  }
  MpcParams held = config.mpc;
  held.preview = false;  // the OMCT's sinusoid is the input, known up to now: no preview, no vehicle model
  MpcCueing mpc(held, config.washout, config.vestibular, config.platform, 1.0 / options.rate_hz);
  return MeasurePoint(test, frequency, config.platform, options,
                      [&mpc](const HeadMotion& m) -> const McaCommand& { return mpc.Step(m); });
}

bool OmctApplies(const OmctTest& test, const McaConfig& config) {
  if (config.algorithm == McaAlgorithm::kWashout) return OmctApplies(test, config.washout, config.platform);
  // the MPC's specific force contains g·θ and g·φ: it tilts wherever it has pitch or roll
  WashoutParams tilting = config.washout;
  tilting.tilt_pitch.enabled = true;
  tilting.tilt_roll.enabled = true;
  return OmctApplies(test, tilting, config.platform);
}

std::vector<OmctPoint> RunOmct(const McaConfig& config, const OmctOptions& options) {
  std::vector<OmctPoint> points;
  for (const OmctTest& test : OmctTests()) {
    if (!OmctApplies(test, config)) continue;
    for (double frequency : OmctFrequencies()) {
      points.push_back(RunOmctPoint(test, frequency, config, options));
    }
  }
  return points;
}

std::vector<OmctPoint> RunOmct(const WashoutParams& params, const PlatformSpec& platform,
                               const OmctOptions& options) {
  std::vector<OmctPoint> points;
  for (const OmctTest& test : OmctTests()) {
    if (!OmctApplies(test, params, platform)) continue;
    for (double frequency : OmctFrequencies()) {
      points.push_back(RunOmctPoint(test, frequency, params, platform, options));
    }
  }
  return points;
}

}  // namespace pwsim::mca
