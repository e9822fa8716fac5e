#include "tests/truth/law_space.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

namespace pwsim::truth {
namespace {

/// Uniform, log-uniform and discrete draws from one generator.
struct Draw {
  std::mt19937_64 rng;
  double In(double lo, double hi) { return lo + (hi - lo) * std::uniform_real_distribution<double>(0.0, 1.0)(rng); }
  double Log(double lo, double hi) { return std::exp(In(std::log(lo), std::log(hi))); }
  int Pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); }
  bool Coin() { return Pick(2) == 1; }
  double Sign() { return Coin() ? 1.0 : -1.0; }
};

std::string Fmt(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

double WheelDampingMean(const TruthChair& chair) {
  double sum = 0.0;
  for (const TruthWheel& w : chair.wheels) sum += w.c_nspm;
  return sum / static_cast<double>(std::max<std::size_t>(1, chair.wheels.size()));
}

/// `others`: the set's other effects (massless tyres are not drawn beside friction, whose
/// rate-dependent laws would make the hub balance implicit).
std::string DrawEffect(const std::string& name, const std::vector<std::string>& others, const TruthChair& chair,
                       Draw& d, TruthEffects& fx) {
  if (name == "wheel_radius") {
    fx.contact_radius_scale = d.In(0.6, 1.4);
    return "rolling discs, radius " + Fmt(fx.contact_radius_scale) + " x nominal";
  }
  if (name == "tyre_compliance") {
    const bool beside_friction = std::find(others.begin(), others.end(), "suspension_friction") != others.end();
    if (d.Coin() || beside_friction) {
      fx.caster_tyre_hz = d.In(5.0, 12.0);
      fx.caster_unsprung_kg = d.In(2.0, 4.0);
      fx.drive_unsprung_kg = d.In(5.0, 10.0);
      fx.drive_tyre_hz = d.Coin() ? d.In(8.0, 25.0) : 0.0;
      fx.tyre_zeta = d.In(0.04, 0.2);
      return "unsprung mass on a tyre: casters " + Fmt(fx.caster_tyre_hz) + " Hz on " + Fmt(fx.caster_unsprung_kg) +
             " kg, drive " + (fx.drive_tyre_hz > 0 ? Fmt(fx.drive_tyre_hz) + " Hz on " + Fmt(fx.drive_unsprung_kg) + " kg" : "rigid") +
             ", zeta " + Fmt(fx.tyre_zeta);
    }
    fx.tyre_massless = true;
    fx.caster_tyre_ratio = d.Log(0.4, 3.0);
    const int drive = d.Pick(3);  // same as the casters, 2-3 x stiffer, rigid
    fx.drive_tyre_ratio = drive == 0 ? fx.caster_tyre_ratio : (drive == 1 ? fx.caster_tyre_ratio * d.In(2.0, 3.0) : 0.0);
    fx.tyre_tau_s = d.In(0.002, 0.01);
    return "massless series spring-damper: k_t/k casters " + Fmt(fx.caster_tyre_ratio) + ", drive " +
           (fx.drive_tyre_ratio > 0 ? Fmt(fx.drive_tyre_ratio) : std::string("rigid")) + ", tau_t " +
           Fmt(fx.tyre_tau_s * 1e3) + " ms";
  }
  if (name == "cushion_compliance") {
    const int law = d.Pick(3);
    fx.cushion_yield = d.In(0.08, 0.25);
    fx.cushion_tau_s = d.In(0.01, 0.03);
    fx.cushion_exponent = d.In(0.5, 1.5);
    fx.cushion_whole_chair = law == 1;
    fx.cushion_proportional = law == 2;
    fx.cushion_ref_n = law == 1 ? 1500.0 : 500.0;
    const std::string what = law == 0 ? "sinks under each wheel's load" : (law == 1 ? "sinks under the whole chair's weight" : "yields a fixed share");
    return what + ": yield " + Fmt(fx.cushion_yield) + (law == 2 ? "" : ", exponent " + Fmt(fx.cushion_exponent)) +
           ", tau " + Fmt(fx.cushion_tau_s * 1e3) + " ms";
  }
  if (name == "heave_pitch_coupling") {
    fx.stiffness_asymmetry = d.Sign() * d.In(0.15, 0.4);
    fx.damper_asymmetry = d.Coin();
    return std::string(fx.damper_asymmetry ? "asymmetric springs and dampers" : "asymmetric springs") +
           ", front x (1 + e), rear x (1 - e), e " + Fmt(fx.stiffness_asymmetry);
  }
  if (name == "nonlinear_stiffness") {
    const int side = d.Pick(3);
    fx.bump_gain = d.In(0.3, 1.2);
    fx.bump_gap_m = d.In(0.002, 0.006);
    fx.bump_symmetric = side == 2;
    fx.bump_rebound_only = side == 1;
    return std::string("stops on ") + (side == 0 ? "compression" : (side == 1 ? "rebound" : "both")) + ", gap " +
           Fmt(fx.bump_gap_m * 1e3) + " mm, gain " + Fmt(fx.bump_gain);
  }
  if (name == "suspension_friction") {
    const int law = d.Pick(4);
    fx.dahl_force_n = d.In(20.0, 60.0);
    fx.friction_smooth_mps = d.In(0.002, 0.01);
    fx.friction_viscous_nspm = d.In(0.0, 0.3) * WheelDampingMean(chair);
    std::string what;
    if (law == 0) {
      fx.friction_law = TruthEffects::FrictionLaw::kDahl;
      fx.dahl_presliding_m = d.In(3e-4, 1.5e-3);
      what = "Dahl per wheel, presliding " + Fmt(fx.dahl_presliding_m * 1e3) + " mm";
    } else if (law == 1 || law == 2) {
      fx.friction_law = TruthEffects::FrictionLaw::kSmoothCoulomb;
      fx.friction_chair_level = law == 2;
      what = std::string("smooth Coulomb ") + (law == 2 ? "at chair level" : "per wheel") + ", v_s " +
             Fmt(fx.friction_smooth_mps * 1e3) + " mm/s";
    } else {
      fx.friction_law = TruthEffects::FrictionLaw::kStribeck;
      fx.friction_breakaway_ratio = d.In(1.3, 2.0);
      fx.friction_stribeck_mps = d.In(0.005, 0.02);
      what = "Stribeck per wheel, F_s/F_c " + Fmt(fx.friction_breakaway_ratio) + ", v_St " +
             Fmt(fx.friction_stribeck_mps * 1e3) + " mm/s";
    }
    return what + ", F_c " + Fmt(fx.dahl_force_n) + " N, viscous " + Fmt(fx.friction_viscous_nspm) + " N s/m";
  }
  if (name == "inertial_pitch") {
    fx.chassis_cm_height_m = chair.cm_height_m * d.In(0.5, 1.5);
    fx.load_cm_height_m = d.In(0.35, 0.8);
    return "inertial torque, chassis CM " + Fmt(fx.chassis_cm_height_m) + " m, load CM " + Fmt(fx.load_cm_height_m) + " m";
  }
  if (name == "marker_offset") {
    fx.marker_x_m = d.Sign() * d.In(0.05, 0.2);
    fx.marker_z_m = d.In(0.2, 0.7);
    return "marker lever, (" + Fmt(fx.marker_x_m) + ", " + Fmt(fx.marker_z_m) + ") m";
  }
  if (name == "occupant_seat") {
    fx.occupant_share = d.In(0.4, 0.9);
    fx.seat_hz = d.In(3.0, 6.0);
    fx.seat_zeta = d.In(0.15, 0.4);
    fx.seat_x_m = d.In(-0.1, 0.1);
    return "seat spring, occupant share " + Fmt(fx.occupant_share) + ", " + Fmt(fx.seat_hz) + " Hz, zeta " +
           Fmt(fx.seat_zeta) + " at x " + Fmt(fx.seat_x_m) + " m";
  }
  throw std::invalid_argument("unknown truth effect '" + name + "'");
}

/// σ of the white part for x, z (m) and pitch (rad), the same for every kind.
void DrawWhite(Draw& d, MeasurementNoise& n, double gain) {
  const double s = d.Log(1.5e-4, 6e-4);
  const double pitch_per_m = d.In(1.2, 2.0);
  const double raw = s / std::sqrt(gain);
  n.x.white_sigma = raw;
  n.z.white_sigma = raw;
  n.pitch.white_sigma = raw * pitch_per_m;
}

/// The kinds the law space never draws (law_space.h ExtraNoiseKinds), from the same stream.
std::string DrawExtraNoise(const std::string& kind, Draw& d, MeasurementNoise& n) {
  n.white_only = false;
  n.kind = kind;
  std::string text = kind + ":";
  if (kind == "pink") {
    n.pink_lo_hz = d.In(0.05, 0.2);
    n.pink_hi_hz = 40.0;
    text += " 1/f noise from " + Fmt(n.pink_lo_hz) + " to 40 Hz;";
  }
  DrawWhite(d, n, 1.0);
  text += " white sigma " + Fmt(n.z.white_sigma * 1e3) + " mm;";
  if (kind == "sine") {  // the drift kind's sinusoid alone, at its slowest
    n.drift_sine = true;
    n.drift_sine_hz = d.In(0.05, 0.15);
    const double a = d.In(5e-4, 1.5e-3);
    n.x.drift_sine_amp = n.z.drift_sine_amp = a;
    n.pitch.drift_sine_amp = a * d.In(1.0, 2.0);
    text += " sinusoidal drift " + Fmt(a * 1e3) + " mm at " + Fmt(n.drift_sine_hz) + " Hz;";
  }
  if (kind == "step") {
    const double s = d.In(3e-4, 1.5e-3);
    n.x.drift_step = n.z.drift_step = s;
    n.pitch.drift_step = s * d.In(1.0, 2.0);
    text += " level step " + Fmt(s * 1e3) + " mm;";
  }
  if (kind == "burst") {
    n.outlier_prob = d.In(0.0005, 0.002);
    n.burst_length = 2 + d.Pick(4);
    const double m = d.In(3e-3, 1e-2);
    n.x.outlier_size = n.z.outlier_size = m;
    n.pitch.outlier_size = m * d.In(1.0, 3.0);
    text += " outlier bursts of up to " + std::to_string(n.burst_length) + " samples, p " +
            Fmt(n.outlier_prob * 100) + " %, " + Fmt(m * 1e3) + " mm;";
  }
  if (kind == "quantised") {
    const double q = d.In(1.0, 3.0) * n.z.white_sigma;
    n.x.quantum = n.z.quantum = q;
    n.pitch.quantum = q * n.pitch.white_sigma / n.z.white_sigma;
    text += " quantised to " + Fmt(q * 1e3) + " mm;";
  }
  return text;
}

std::string DrawNoise(const std::string& kind, Draw& d, MeasurementNoise& n) {
  constexpr double kRateHz = 100.0;
  n.white_only = false;
  n.kind = kind;
  const bool lowpass = kind == "lowpass" || kind == "mix";
  const bool drift = kind == "drift" || kind == "mix";
  const bool outliers = kind == "outliers" || kind == "mix";
  std::string text = kind + ":";
  double gain = 1.0;
  if (lowpass) {
    n.lowpass_order = 2 + d.Pick(3);
    n.lowpass_cutoff_hz = d.In(6.0, 15.0);
    gain = NoiseVarianceGain(ButterworthLowPass(n.lowpass_order, n.lowpass_cutoff_hz, kRateHz), true, 4000);
    text += " Butterworth order " + std::to_string(n.lowpass_order) + " at " + Fmt(n.lowpass_cutoff_hz) + " Hz zero phase;";
  }
  DrawWhite(d, n, gain);
  text += " white sigma " + Fmt(n.z.white_sigma * std::sqrt(gain) * 1e3) + " mm (after any filter);";
  if (drift) {
    n.drift_sine = d.Coin();
    if (n.drift_sine) {
      n.drift_sine_hz = d.In(0.05, 0.3);
      const double a = d.In(3e-4, 1.5e-3);
      n.x.drift_sine_amp = a;
      n.z.drift_sine_amp = a;
      n.pitch.drift_sine_amp = a * d.In(1.0, 2.0);
      text += " sinusoidal drift " + Fmt(a * 1e3) + " mm at " + Fmt(n.drift_sine_hz) + " Hz;";
    } else {
      const double over_10s = d.In(5e-4, 2e-3);
      const double walk = over_10s / std::sqrt(10.0);
      n.x.drift_walk_sigma = walk;
      n.z.drift_walk_sigma = walk;
      n.pitch.drift_walk_sigma = walk * d.In(1.0, 2.0);
      text += " random-walk drift " + Fmt(over_10s * 1e3) + " mm over 10 s;";
    }
  }
  if (outliers) {
    n.outlier_prob = d.In(0.001, 0.005);
    const double m = d.In(3e-3, 1e-2);
    n.x.outlier_size = m;
    n.z.outlier_size = m;
    n.pitch.outlier_size = m * d.In(1.0, 3.0);
    text += " outliers p " + Fmt(n.outlier_prob * 100) + " %, " + Fmt(m * 1e3) + " mm;";
  }
  return text;
}

}  // namespace

std::vector<std::string> NoiseKinds() { return {"white", "lowpass", "drift", "outliers", "mix"}; }
std::vector<std::string> ExtraNoiseKinds() { return {"pink", "sine", "step", "burst", "quantised"}; }

LawDraw DrawLaws(std::uint64_t seed, const std::vector<std::string>& effects, const TruthChair& chair,
                 const std::string& noise_kind) {
  LawDraw out;
  // Its own stream: the effects' laws from one, the noise from another, so that forcing the noise
  // kind leaves the laws as drawn.
  Draw laws{std::mt19937_64(seed * 7919u + 17u)};
  for (const std::string& name : effects) out.laws.push_back(name + ": " + DrawEffect(name, effects, chair, laws, out.effects));
  Draw noise{std::mt19937_64(seed * 104729u + 29u)};
  const std::vector<std::string> kinds = NoiseKinds();
  const int drawn = noise.Pick(static_cast<int>(kinds.size()));
  const std::string kind = noise_kind.empty() ? kinds[static_cast<std::size_t>(drawn)] : noise_kind;
  const std::vector<std::string> extra = ExtraNoiseKinds();
  if (std::find(extra.begin(), extra.end(), kind) != extra.end()) {
    out.laws.push_back("noise " + DrawExtraNoise(kind, noise, out.noise));
    return out;
  }
  if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end())
    throw std::invalid_argument("unknown noise kind '" + kind +
                                "' (white, lowpass, drift, outliers, mix; pink, sine, step, burst, quantised)");
  out.laws.push_back("noise " + DrawNoise(kind, noise, out.noise));
  return out;
}

}  // namespace pwsim::truth
