#include "sysid/effects/effect_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <numbers>

#include <Eigen/Dense>

#include "engine/check.h"
#include "engine/geometric_model.h"
#include "engine/lumped_model.h"

namespace pwsim::effects {

std::vector<bool> CasterWheels(const Chair& chair) {
  double largest = 0.0;
  for (const Wheel& w : chair.wheels) largest = std::max(largest, w.radius);
  std::vector<bool> caster;
  for (const Wheel& w : chair.wheels) {
    const bool named = w.name.find("caster") != std::string::npos;
    caster.push_back(named || w.radius < 0.85 * largest);
  }
  return caster;
}

std::vector<double> StaticWheelLoads(const Chair& chair, double load_kg) {
  std::vector<double> loads;
  const double weight = MovingMass(chair, load_kg) * kGravity;
  for (std::size_t i = 0; i < chair.wheels.size(); ++i) {
    const double share = chair.gm && i < chair.gm->alpha.size() ? chair.gm->alpha[i]
                                                                : 1.0 / static_cast<double>(chair.wheels.size());
    loads.push_back(std::max(0.0, share) * weight);
  }
  return loads;
}

std::vector<double> CushionHeightFactors(const Chair& chair, double load_kg, const EffectParams& fx) {
  const std::vector<double> loads = StaticWheelLoads(chair, load_kg);
  const bool whole_chair = fx.member.cushion_load == CushionLoad::kWholeChair;
  std::vector<double> factors(loads.size());
  for (std::size_t i = 0; i < loads.size(); ++i) {
    const double load_kn = 1e-3 * (whole_chair ? MovingMass(chair, load_kg) * kGravity : loads[i]);
    const double loss = fx.cushion_loss_per_kn == 0.0
                            ? 0.0
                            : fx.cushion_loss_per_kn * std::pow(std::max(0.0, load_kn), fx.cushion_exponent);
    factors[i] = std::max(0.0, fx.cushion_height_gain - loss);
  }
  return factors;
}

EnvelopePoint RollingDiscEnvelope(const Terrain& terrain, double x, double radius) {
  if (radius <= 0.0) return {terrain.HeightAt(x), terrain.SlopeAt(x)};
  const double r2 = radius * radius;
  double best = -std::numeric_limits<double>::infinity();
  double best_s = 0.0;
  auto consider = [&](double s, double z) {
    const double value = z + std::sqrt(std::max(0.0, r2 - s * s));
    if (value > best) {
      best = value;
      best_s = s;
    }
  };
  const std::size_t n = terrain.x.size();
  if (n < 2) return {};
  // Flat ground (z = 0) left and right of the listed span: stationary point s = 0, clipped.
  if (terrain.x.front() - x >= -radius) consider(std::clamp(0.0, -radius, terrain.x.front() - x), 0.0);
  if (terrain.x.back() - x <= radius) consider(std::clamp(0.0, terrain.x.back() - x, radius), 0.0);
  // Listed segments overlapping [x - R, x + R].
  auto first = std::upper_bound(terrain.x.begin(), terrain.x.end(), x - radius);
  std::size_t j = first == terrain.x.begin() ? 0 : static_cast<std::size_t>(first - terrain.x.begin()) - 1;
  for (; j + 1 < n && terrain.x[j] <= x + radius; ++j) {
    const double a = std::max(-radius, terrain.x[j] - x);
    const double b = std::min(radius, terrain.x[j + 1] - x);
    if (a > b) continue;
    const double m = (terrain.z[j + 1] - terrain.z[j]) / (terrain.x[j + 1] - terrain.x[j]);
    const double s = std::clamp(m * radius / std::sqrt(1.0 + m * m), a, b);
    consider(s, terrain.z[j] + m * (x + s - terrain.x[j]));
  }
  const double root = std::sqrt(std::max(1e-12, r2 - best_s * best_s));
  return {best - radius, std::clamp(best_s / root, -5.0, 5.0)};
}

std::vector<double> EstimateAcceleration(const std::vector<double>& t, const std::vector<double>& x,
                                         double window) {
  PWSIM_DEMAND(t.size() == x.size());
  const std::size_t n = t.size();
  std::vector<double> accel(n, 0.0);
  std::size_t lo = 0, hi = 0;
  for (std::size_t k = 0; k < n; ++k) {
    while (t[k] - t[lo] > window) ++lo;
    while (hi + 1 < n && t[hi + 1] - t[k] <= window) ++hi;
    if (hi - lo < 4) continue;
    // Least-squares quadratic x = c0 + c1 τ + c2 τ² around t[k].
    double s[5] = {0, 0, 0, 0, 0}, r[3] = {0, 0, 0};
    for (std::size_t m = lo; m <= hi; ++m) {
      const double tau = t[m] - t[k];
      double p = 1.0;
      for (int e = 0; e < 5; ++e) {
        s[e] += p;
        if (e < 3) r[e] += p * x[m];
        p *= tau;
      }
    }
    // Solve [[s0 s1 s2][s1 s2 s3][s2 s3 s4]] c = r for c2 by Cramer's rule.
    auto det3 = [](double a, double b, double c, double d, double e, double f, double g,
                   double h, double i) {
      return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    };
    const double d = det3(s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4]);
    if (std::abs(d) < 1e-300) continue;
    const double d2 = det3(s[0], s[1], r[0], s[1], s[2], r[1], s[2], s[3], r[2]);
    accel[k] = 2.0 * d2 / d;
  }
  return accel;
}

PreparedTrial PrepareTrial(const Chair& chair, const Terrain& terrain, double load_kg,
                           std::vector<double> t, std::vector<double> x,
                           std::vector<double> accel, double accel_window) {
  PWSIM_DEMAND(chair.gm.has_value());
  PWSIM_DEMAND(t.size() == x.size() && t.size() >= 2);
  PreparedTrial trial;
  trial.chair = chair;
  trial.terrain = terrain;
  trial.load_kg = load_kg;
  trial.is_caster = CasterWheels(chair);
  const std::size_t n = t.size();
  if (accel.size() != n) accel = EstimateAcceleration(t, x, accel_window);
  trial.t = std::move(t);
  trial.x = std::move(x);
  trial.accel = std::move(accel);
  return trial;
}

WheelPlane WeightedPlane(const WheelArray& w, const WheelArray& x, int wheels) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0;
  for (int i = 0; i < wheels; ++i) {
    s0 += w[i];
    s1 += w[i] * x[i];
    s2 += w[i] * x[i] * x[i];
  }
  const double det = s0 * s2 - s1 * s1;
  WheelPlane p;
  if (!(det > 0.0)) return p;
  for (int i = 0; i < wheels; ++i) {
    p.z[i] = w[i] * (s2 - s1 * x[i]) / det;
    p.pitch[i] = w[i] * (s0 * x[i] - s1) / det;
  }
  return p;
}

WheelArray TyreCompliances(const EffectParams& fx, const PreparedTrial& trial) {
  const int n = trial.chair.wheel_count();
  bool front = false, rear = false;
  for (int i = 0; i < n; ++i) {
    if (!trial.is_caster[i]) continue;
    front = front || trial.chair.wheels[i].x > 0.0;
    rear = rear || trial.chair.wheels[i].x < 0.0;
  }
  const double rear_ratio = front && rear ? fx.rear_caster_compliance_ratio : 1.0;
  WheelArray c{};
  for (int i = 0; i < n; ++i) {
    if (!trial.is_caster[i]) c[i] = fx.drive_tyre_compliance;
    else c[i] = trial.chair.wheels[i].x < 0.0 ? rear_ratio * fx.caster_tyre_compliance : fx.caster_tyre_compliance;
  }
  return c;
}

namespace {

/// Suspension shares s_i of wheels whose tyres (compliance c_i, 0 = rigid) are in series with
/// their suspension springs k_i = s_i K: the pairs' series stiffnesses k'_i = 1/(1/k_i + c_i)
/// keep the static GM's shares (k'_i = λ α_i, what the GM identified on the ground heights saw),
/// i.e. k_i = 1/(1/(λ α_i) - c_i), with λ such that Σ k_i = K (Σ k_i grows monotonically in
/// λ on (0, min 1/(α_i c_i)): bisection). Rigid tyres everywhere: s = α.
WheelArray SuspensionShares(const WheelArray& alpha, const WheelArray& compliance, int wheels,
                            double k_total) {
  WheelArray share{};
  double lambda_max = std::numeric_limits<double>::infinity();
  for (int i = 0; i < wheels; ++i)
    if (alpha[i] > 0.0 && compliance[i] > 0.0) lambda_max = std::min(lambda_max, 1.0 / (alpha[i] * compliance[i]));
  auto stiffness = [&](double lambda, int i) {
    if (alpha[i] <= 0.0) return 0.0;
    return 1.0 / (1.0 / (lambda * alpha[i]) - compliance[i]);
  };
  double lambda = k_total;  // all rigid: k_i = K α_i
  if (std::isfinite(lambda_max) && k_total > 0.0) {
    double lo = 0.0, hi = lambda_max;
    for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      double sum = 0.0;
      for (int i = 0; i < wheels; ++i) sum += stiffness(mid, i);
      (sum < k_total ? lo : hi) = mid;
    }
    lambda = 0.5 * (lo + hi);
  }
  double sum = 0.0;
  for (int i = 0; i < wheels; ++i) sum += (share[i] = std::max(0.0, stiffness(lambda, i)));
  for (int i = 0; i < wheels; ++i) share[i] = sum > 0.0 ? share[i] / sum : alpha[i];
  return share;
}

/// Everything one simulation needs, fixed for the trial and the parameters.
struct Setup {
  int wheels{0};
  std::array<double, kMaxWheels> wheel_x{};
  std::array<double, kMaxWheels> alpha{};
  std::array<double, kMaxWheels> radius{};         ///< rolling-disc radius (0 = point)
  std::array<double, kMaxWheels> height_factor{};  ///< cushion: effective / nominal height
  double gm_pitch_gain{1.0};                       ///< cushion: q, the β rescaled
  std::array<int, kMaxWheels> tyre{};              ///< 0 rigid, 1 caster tyre, 2 drive tyre
  std::array<double, kMaxWheels> inv_unsprung{};   ///< 1/m_u = ω² c_t [1/kg] (0: no reaction)
  std::array<double, kMaxWheels> friction{};       ///< F_c [N]
  std::array<double, kMaxWheels> smooth_rate{};    ///< v_s [m/s] of each wheel (smooth Coulomb)
  std::array<double, kMaxWheels> lift_off{};       ///< -(W_i/m_u + g): the tyre's pull limit [m/s²]
  std::array<double, 3> tyre_omega2{}, tyre_2zw{};  ///< ω², 2ζω of each tyre class
  std::array<AxisPropagator, 3> tyre_propagator{};
  // Compliant tyres: each wheel's own suspension (header, tyre_compliance).
  std::array<double, kMaxWheels> share{};             ///< s_i, suspension shares (Σ s_i = 1)
  std::array<double, kMaxWheels> k_wheel{}, c_wheel{};  ///< s_i K_Z [N/m], s_i C_Z [N s/m]
  std::array<double, kMaxWheels> plane_z{}, plane_t{};  ///< s-weighted plane: Z = Σ plane_z_i u_i
  std::array<double, kMaxWheels> gm_dz{}, gm_dt{};      ///< GM correction (s-plane - α-plane)
  // Massless tyres (header, TyreLaw::kMassless).
  std::array<double, kMaxWheels> k_tyre{}, c_tyre{};  ///< k_t [N/m], τ_t k_t [N s/m] (0: rigid)
  std::array<double, kMaxWheels * kMaxWheels> hub_step{};  ///< (τ_t K_t + D + Δt S/2)^-1, row-major
  AxisPropagator heave, pitch;
  double mass{1.0}, lever{0.0};
  double k_z{0}, c_z{0}, k_t{0}, c_t{0}, k_zt{0}, c_zt{0};
  double hard_z{0}, hard_t{0}, bump_gain{0}, bump_gap{0}, presliding{5e-4};
  double marker_x{0}, marker_z{0};
  /// The families' discrete laws (header: the stops' sides, the friction law, the tyres' law,
  /// the kinematics), as the catalogue names them.
  EffectMembers member;
  /// Which terms the values switch on, derived once from them (MakeSetup).
  struct On {
    bool radius{false};    ///< some wheel has a rolling-disc radius
    bool tyre{false};      ///< some wheel has a tyre (unsprung or massless)
    bool series{false};    ///< some tyre is compliant (c_t > 0): the GM's series shift
    bool massless{false};  ///< some massless tyre (TyreLaw::kMassless)
    bool friction{false};  ///< some wheel has suspension friction
    bool gm_scaled{false};  ///< a cushion factor or q != 1: the trial's cached GM output does not hold
    bool held_forces{false};  ///< coupling, hardening, bump stops, friction or exact kinematics
  } on;
  bool Exact() const { return member.kinematics == Kinematics::kExact; }
  bool StopsInCompression() const { return member.stops != StopSides::kRebound; }
  bool StopsInRebound() const { return member.stops != StopSides::kCompression; }
  bool SmoothCoulomb() const { return member.friction == FrictionLaw::kSmoothCoulomb; }
};

/// The massless hubs' step matrix (header, TyreLaw::kMassless). The suspension's reaction on
/// wheel i depends on the hubs' rates u̇_j through R_i = ... - Σ_j D_ij u̇_j and on their
/// heights through - Σ_j S'_ij u_j, with the GM linearised about level ground (Z_GM = Σ g_j u_j,
/// θ_GM = Σ p_j u_j, the series shift included):
///   D_ij = a_i (C_Z g_j + C_Zθ p_j) + b_i (C_θ p_j + C_Zθ g_j) + c_i (δ_ij - a_j - x_i b_j)
/// (a, b the suspension plane's coefficients, c_i the wheel's own damper), S' the same with the
/// stiffnesses. Rigid wheels' rows are u̇_i = ḣ_i. Stored: (τ_t K_t + D + Δt (K_t + S')/2)^-1.
void MakeHubStep(const Chair& chair, double dt, Setup& m) {
  const int w = m.wheels;
  const GeometricModel gm(chair);
  std::array<double, kMaxWheels> unit{}, g{}, p{};
  constexpr double kProbe = 1e-6;  // [m]: the GM's asin is linear to 1e-13 relative here
  for (int j = 0; j < w; ++j) {
    unit.fill(0.0);
    unit[j] = kProbe;
    const GeometricOutput out = gm.Evaluate(std::span<const double>(unit.data(), static_cast<std::size_t>(w)));
    g[j] = out.z / kProbe + m.gm_dz[j];
    p[j] = m.gm_pitch_gain * out.pitch / kProbe + m.gm_dt[j];
  }
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxWheels, kMaxWheels>;
  Matrix step = Matrix::Zero(w, w);
  for (int i = 0; i < w; ++i) {
    if (m.k_tyre[i] <= 0.0) {
      step(i, i) = 1.0;
      continue;
    }
    for (int j = 0; j < w; ++j) {
      const double plane = (i == j ? 1.0 : 0.0) - m.plane_z[j] - m.wheel_x[i] * m.plane_t[j];
      const double damping = m.plane_z[i] * (m.c_z * g[j] + m.c_zt * p[j]) +
                             m.plane_t[i] * (m.c_t * p[j] + m.c_zt * g[j]) + m.c_wheel[i] * plane;
      const double stiffness = m.plane_z[i] * (m.k_z * g[j] + m.k_zt * p[j]) +
                               m.plane_t[i] * (m.k_t * p[j] + m.k_zt * g[j]) + m.k_wheel[i] * plane;
      step(i, j) = damping + 0.5 * dt * stiffness;
    }
    step(i, i) += m.c_tyre[i] + 0.5 * dt * m.k_tyre[i];
  }
  const Matrix inverse = step.fullPivLu().inverse();
  for (int i = 0; i < w; ++i)
    for (int j = 0; j < w; ++j) m.hub_step[static_cast<std::size_t>(i * kMaxWheels + j)] = inverse(i, j);
}

/// tyre_compliance (unsprung): each tyre class's mode ω², 2ζω and exact propagator.
void SetupTyreModes(const EffectParams& fx, double dt, Setup& m) {
  for (int t = 1; t <= 2; ++t) {
    const double period = t == 1 ? fx.caster_tyre_period : fx.drive_tyre_period;
    if (period <= 1e-6) continue;
    const double omega = 2.0 * std::numbers::pi / period;
    m.tyre_propagator[t] = MakeAxisPropagator({1.0, 2.0 * fx.tyre_damping * omega, omega * omega}, dt);
    m.tyre_omega2[t] = omega * omega;
    m.tyre_2zw[t] = 2.0 * fx.tyre_damping * omega;
  }
}

/// Each wheel's own data: position and GM share, and per effect its radius (wheel_radius), its
/// tyre (tyre_compliance; its compliance returned), its friction (suspension_friction) and its
/// cushion factor (cushion_compliance).
std::array<double, kMaxWheels> SetupWheels(const PreparedTrial& trial, const EffectParams& fx, Setup& m) {
  const Chair& chair = trial.chair;
  const std::vector<double> factors = CushionHeightFactors(chair, trial.load_kg, fx);
  const WheelArray tyre_compliance = TyreCompliances(fx, trial);
  std::array<double, kMaxWheels> compliance{};
  for (int i = 0; i < m.wheels; ++i) {
    const bool caster = trial.is_caster[i];
    m.wheel_x[i] = chair.wheels[i].x;
    m.alpha[i] = chair.gm->alpha[i];
    m.radius[i] = caster ? fx.caster_radius : fx.drive_radius;
    m.on.radius = m.on.radius || m.radius[i] > 0.0;
    const double period = caster ? fx.caster_tyre_period : fx.drive_tyre_period;
    if (fx.member.tyre == TyreLaw::kMassless) {
      compliance[i] = std::max(0.0, tyre_compliance[i]);
      m.tyre[i] = compliance[i] > 0.0 ? (caster ? 1 : 2) : 0;
      m.k_tyre[i] = m.tyre[i] != 0 ? 1.0 / compliance[i] : 0.0;
      m.c_tyre[i] = std::max(0.0, fx.tyre_time_constant) * m.k_tyre[i];
      m.on.massless = m.on.massless || m.tyre[i] != 0;
    } else {
      m.tyre[i] = period > 1e-6 ? (caster ? 1 : 2) : 0;
      const double omega = m.tyre[i] != 0 ? 2.0 * std::numbers::pi / period : 0.0;
      if (m.tyre[i] != 0)
        compliance[i] = std::max(0.0, tyre_compliance[i]);
      m.inv_unsprung[i] = omega * omega * compliance[i];
    }
    m.on.tyre = m.on.tyre || m.tyre[i] != 0;
    m.on.series = m.on.series || m.inv_unsprung[i] > 0.0 || m.k_tyre[i] > 0.0;
    m.friction[i] = caster ? fx.caster_friction : fx.drive_friction;
    m.on.friction = m.on.friction || m.friction[i] > 0.0;
    m.height_factor[i] = factors[static_cast<std::size_t>(i)];
    m.on.gm_scaled = m.on.gm_scaled || m.height_factor[i] != 1.0;
  }
  m.gm_pitch_gain = fx.cushion_pitch_gain;
  m.on.gm_scaled = m.on.gm_scaled || m.gm_pitch_gain != 1.0;
  return compliance;
}

/// tyre_compliance: each wheel's own suspension under its tyre (header): the shares s, its
/// spring and damper, the s-weighted plane, the GM's series shift and the lift-off limit.
void SetupSeriesSuspension(const std::array<double, kMaxWheels>& compliance, const LumpedParams& lm,
                           double dt, Setup& m) {
  m.share = SuspensionShares(m.alpha, compliance, m.wheels, lm.k_z);
  const WheelPlane by_share = WeightedPlane(m.share, m.wheel_x, m.wheels);
  const WheelPlane by_alpha = WeightedPlane(m.alpha, m.wheel_x, m.wheels);
  for (int i = 0; i < m.wheels; ++i) {
    m.k_wheel[i] = m.share[i] * lm.k_z;
    // Held over the step, the wheel's own damper is stable while c Δt / m_u < 2: capped at 1.
    // (A massless hub's balance is solved implicitly: no cap.)
    m.c_wheel[i] = m.k_tyre[i] > 0.0 ? m.share[i] * lm.c_z
                   : m.inv_unsprung[i] > 0.0
                       ? std::min(m.share[i] * lm.c_z, 1.0 / (m.inv_unsprung[i] * dt))
                       : 0.0;
    m.plane_z[i] = by_share.z[i];
    m.plane_t[i] = by_share.pitch[i];
    m.gm_dz[i] = by_share.z[i] - by_alpha.z[i];
    m.gm_dt[i] = by_share.pitch[i] - by_alpha.pitch[i];
    // A tyre pushes, never pulls: its force (static W_i + m_u g plus the deviation) stays ≥ 0;
    // the static load W_i is the suspension's share of the weight.
    m.lift_off[i] = -(m.share[i] * m.mass * kGravity * m.inv_unsprung[i] + kGravity);
  }
}

/// The LM (eq. 3) and the effects that act on it: heave_pitch_coupling, nonlinear_stiffness.
void SetupLumped(const PreparedTrial& trial, const ExtendedParams& params, Setup& m) {
  const EffectParams& fx = params.fx;
  const double dt = trial.step;
  m.k_z = params.lm.k_z;
  m.c_z = params.lm.c_z;
  m.k_t = params.lm.k_theta;
  m.c_t = params.lm.c_theta;
  m.heave = MakeAxisPropagator({m.mass, m.c_z, m.k_z}, dt);
  m.pitch = MakeAxisPropagator({PitchInertia(trial.chair, trial.load_kg), m.c_t, m.k_t}, dt);
  m.k_zt = fx.stiffness_coupling * std::sqrt(std::max(0.0, m.k_z * m.k_t));
  m.c_zt = fx.damping_coupling * std::sqrt(std::max(0.0, m.c_z * m.c_t));
  m.hard_z = fx.heave_hardening;
  m.hard_t = fx.pitch_hardening;
  m.bump_gain = fx.bump_gain;
  m.bump_gap = fx.bump_gap;
}

/// suspension_friction: Dahl's presliding length, or smooth Coulomb's rate kept stable.
void SetupFriction(const PreparedTrial& trial, const EffectParams& fx, Setup& m) {
  const double dt = trial.step;
  m.presliding = std::max(1e-6, fx.friction_presliding);
  if (m.SmoothCoulomb()) {
    // Held over the step, the law's slope F_c/v_s is a damper on the chassis: kept below one
    // n-th of the explicit limit (c Δt (1/M + x_i²/I_θ) < 1 for each of n wheels).
    const double inv_inertia = 1.0 / PitchInertia(trial.chair, trial.load_kg);
    for (int i = 0; i < m.wheels; ++i)
      m.smooth_rate[i] = std::max(fx.friction_smooth_rate,
                                  m.wheels * m.friction[i] * dt *
                                      (1.0 / m.mass + m.wheel_x[i] * m.wheel_x[i] * inv_inertia));
  }
}

Setup MakeSetup(const PreparedTrial& trial, const ExtendedParams& params) {
  const Chair& chair = trial.chair;
  const EffectParams& fx = params.fx;
  PWSIM_DEMAND(chair.gm.has_value() && trial.step > 0.0);
  Setup m;
  m.wheels = chair.wheel_count();
  PWSIM_DEMAND(m.wheels <= kMaxWheels);
  m.member = fx.member;
  const double dt = trial.step;
  SetupTyreModes(fx, dt, m);
  const std::array<double, kMaxWheels> compliance = SetupWheels(trial, fx, m);
  m.mass = MovingMass(chair, trial.load_kg);
  if (m.on.tyre) SetupSeriesSuspension(compliance, params.lm, dt, m);
  SetupLumped(trial, params, m);
  SetupFriction(trial, fx, m);
  // inertial_pitch: Γ_θ = M lever a_x with the mass-weighted lever of chair and occupant.
  m.lever = (chair.mass * fx.cm_lever + trial.load_kg * fx.load_cm_lever) / m.mass;
  // marker_offset.
  m.marker_x = fx.marker_lever_x;
  m.marker_z = fx.marker_lever_z;
  m.on.held_forces = m.k_zt != 0.0 || m.c_zt != 0.0 || m.hard_z != 0.0 || m.hard_t != 0.0 ||
                     m.bump_gain > 0.0 || m.on.friction || m.Exact();
  if (m.on.massless) MakeHubStep(chair, dt, m);
  return m;
}

/// The LM state (deviations are taken from the GM output, as in eq. 3).
struct Body {
  double z{0}, z_rate{0}, pitch{0}, pitch_rate{0};
};

/// sin θ and cos θ of a pitch angle, taken once per angle: a step's terms (the stops, the
/// exact kinematics, the friction's deflection) share them, and the end of one step is the
/// start of the next (the same values as each term's own std::sin and std::cos, bit for bit).
/// The cosine only `with_cos`: the stops and the friction need the sine alone, and a cosine
/// not taken is no value (reading it is a contract violation, never a silent 1). An angle
/// whose sine no term reads is itself std::nullopt (Trig).
struct PitchTrig {
  double sin{0.0};
  std::optional<double> cos;
};
PitchTrig TrigOf(double pitch, bool with_cos) {
  return with_cos ? PitchTrig{std::sin(pitch), std::cos(pitch)} : PitchTrig{std::sin(pitch), std::nullopt};
}
/// The angle's PitchTrig where `used`, else no value.
std::optional<PitchTrig> Trig(double pitch, bool used, bool with_cos) {
  return used ? std::optional<PitchTrig>(TrigOf(pitch, with_cos)) : std::nullopt;
}

/// Force on the chassis [N] and torque [N m] from the held (non-linear or coupling) effects
/// at `body` (its pitch's sine and cosine `bt`), with the GM output `gm` (`gt`) and its rate,
/// and the wheels' contact heights `zc`.
struct Load {
  double heave{0.0}, pitch{0.0};
};
Load HeldForces(const Setup& m, const Body& b, const std::optional<PitchTrig>& bt,
                const GeometricOutput& gm, const std::optional<PitchTrig>& gt, double gm_z_rate, double gm_pitch_rate, const double* zc,
                const double* friction_state) {
  Load f;
  const double dz = b.z - gm.z, dp = b.pitch - gm.pitch;
  const double dz_rate = b.z_rate - gm_z_rate, dp_rate = b.pitch_rate - gm_pitch_rate;
  const double qz = dz / kHeaveRef, qp = dp / kPitchRef;
  f.heave -= m.k_z * dz * m.hard_z * qz * qz + m.k_zt * dp + m.c_zt * dp_rate;
  f.pitch -= m.k_t * dp * m.hard_t * qp * qp + m.k_zt * dz + m.c_zt * dz_rate;
  if (m.bump_gain > 0.0) {
    // Bump stops: F_i = b K_Z α_i max(0, c_i - g)² / δ_ref on each wheel's compression
    // c_i = Z_Oi - (Z + x_i sin θ), pushing the chassis up at x_i; rebound stops the same on
    // its extension -c_i, pulling it down.
    const double sin_t = bt.value().sin;
    for (int i = 0; i < m.wheels; ++i) {
      const double compression = zc[i] - (b.z + m.wheel_x[i] * sin_t);
      const double over = compression - m.bump_gap;
      const double under = m.StopsInRebound() ? -compression - m.bump_gap : 0.0;
      double force = 0.0;
      if (m.StopsInCompression() && over > 0.0) force = m.bump_gain * m.k_z * m.alpha[i] * over * over / kHeaveRef;
      if (under > 0.0) force = -m.bump_gain * m.k_z * m.alpha[i] * under * under / kHeaveRef;
      f.heave += force;
      f.pitch += force * m.wheel_x[i];
    }
  }
  if (m.on.friction) {
    for (int i = 0; i < m.wheels; ++i) {
      f.heave -= friction_state[i];
      f.pitch -= friction_state[i] * m.wheel_x[i];
    }
  }
  if (m.Exact()) {
    // Exact kinematics: the pitch torque -cos θ [K_θ (sin θ - sin θ_GM) + C_θ (cos θ θ̇ -
    // cos θ_GM θ̇_GM)] in place of the small-angle one that the propagator applies.
    const double c = bt.value().cos.value(), c_gm = gt.value().cos.value();
    f.pitch += m.k_t * dp + m.c_t * dp_rate -
               c * (m.k_t * (bt->sin - gt->sin) + m.c_t * (c * b.pitch_rate - c_gm * gm_pitch_rate));
  }
  return f;
}

/// Each wheel's height off the suspension plane through the heights `u` (its own spring's
/// share of the deflection, which the chassis does not see).
void OffPlane(const Setup& m, const double* u, double* d) {
  double plane_z = 0.0, plane_t = 0.0;
  for (int i = 0; i < m.wheels; ++i) {
    plane_z += m.plane_z[i] * u[i];
    plane_t += m.plane_t[i] * u[i];
  }
  for (int i = 0; i < m.wheels; ++i) d[i] = u[i] - plane_z - m.wheel_x[i] * plane_t;
}

/// One step of the massless hubs (header, TyreLaw::kMassless) from heights `u0` to `u1`, the
/// ground going from h0 to h1, the chassis at `body` over its GM output `gm` (at u0): the
/// balance's right-hand side b(u0) with every hub at rest, times MakeHubStep's matrix.
void AdvanceMasslessHubs(const Setup& m, const Body& body, const std::optional<PitchTrig>& bt,
                         const GeometricOutput& gm, const std::optional<PitchTrig>& gt, const double* h0, const double* h1, const double* u0,
                         const double* off_static, double dt, double* u1) {
  const int w = m.wheels;
  // The suspension's force and torque on the chassis with the hubs at rest (u̇ = 0).
  const double dz = body.z - gm.z, dp = body.pitch - gm.pitch;
  const double pitch_spring = m.Exact() ? m.k_t * (bt.value().sin - gt.value().sin) +
                                            m.c_t * bt->cos.value() * body.pitch_rate
                                      : m.k_t * dp + m.c_t * body.pitch_rate;
  const double force = m.k_z * dz + m.c_z * body.z_rate + m.k_zt * dp + m.c_zt * body.pitch_rate;
  const double torque = pitch_spring + m.k_zt * dz + m.c_zt * body.z_rate;
  std::array<double, kMaxWheels> off{}, b{};
  OffPlane(m, u0, off.data());
  for (int i = 0; i < w; ++i) {
    const double ground_rate = (h1[i] - h0[i]) / dt;
    if (m.k_tyre[i] <= 0.0) {
      b[i] = ground_rate;
      continue;
    }
    const double reaction = m.plane_z[i] * force + m.plane_t[i] * torque - m.k_wheel[i] * (off[i] - off_static[i]);
    // The trapezoid's mean of the tyre's spring force over the step, less S Δu / 2 (the matrix).
    b[i] = m.k_tyre[i] * (0.5 * (h0[i] + h1[i]) - u0[i]) + m.c_tyre[i] * ground_rate + reaction;
  }
  for (int i = 0; i < w; ++i) {
    if (m.k_tyre[i] <= 0.0) {
      u1[i] = h1[i];  // a rigid wheel on its ground
      continue;
    }
    double rate = 0.0;
    const double* row = m.hub_step.data() + static_cast<std::size_t>(i * kMaxWheels);
    for (int j = 0; j < w; ++j) rate += row[j] * b[j];
    u1[i] = u0[i] + dt * rate;
  }
}

}  // namespace

void CacheInputs(PreparedTrial& trial) {
  trial.cache_step = 0.0;
  trial.wheel_cache.clear();
  trial.gm_cache.clear();
  trial.x_grid = InterpolateOnGrid(trial.t, trial.x, trial.step);
  trial.accel_grid = InterpolateOnGrid(trial.t, trial.accel, trial.step);
  const GeometricModel gm(trial.chair);
  const int w = gm.wheel_count();
  std::array<double, kMaxWheels> h{};
  trial.wheel_cache.reserve(trial.x_grid.size() * static_cast<std::size_t>(w));
  trial.gm_cache.reserve(trial.x_grid.size() * 2);
  for (double x : trial.x_grid) {
    gm.ContactHeights(trial.terrain, x, std::span<double>(h.data(), static_cast<std::size_t>(w)));
    trial.wheel_cache.insert(trial.wheel_cache.end(), h.begin(), h.begin() + w);
    const GeometricOutput out = gm.Evaluate(std::span<const double>(h.data(), static_cast<std::size_t>(w)));
    trial.gm_cache.push_back(out.z);
    trial.gm_cache.push_back(out.pitch);
  }
  trial.cache_step = trial.step;
}

namespace {

/// The terms one simulation takes, fixed for the trial and the parameters: where the inputs
/// come from (the trial's caches or the terrain) and which pitch angles' sines and cosines
/// some term reads.
struct Paths {
  bool marker{false};          ///< marker_offset is on: x and Z read through the lever
  bool wheel_cache{false};     ///< the contact heights are the trial's cached ones
  bool gm_cache{false};        ///< and the GM output as well
  bool need_contacts{false};   ///< some term reads the contact heights
  bool body_trig{false};       ///< the body's sin θ is read (stops, friction, exact, marker)
  bool body_cos{false};        ///< and its cos θ (exact, marker)
  bool predicted_trig{false};  ///< the Heun predictor's sin θ (stops, exact)
};

Paths PathsOf(const Setup& m, bool cached) {
  Paths p;
  p.marker = m.marker_x != 0.0 || m.marker_z != 0.0;
  p.wheel_cache = cached && !p.marker && !m.on.radius && !m.Exact();
  p.gm_cache = p.wheel_cache && !m.on.tyre && !m.on.gm_scaled;
  p.need_contacts = !p.gm_cache || m.on.held_forces;
  p.body_trig = m.Exact() || m.bump_gain > 0.0 || m.on.friction || p.marker;
  p.body_cos = m.Exact() || p.marker;
  p.predicted_trig = m.on.held_forces && (m.Exact() || m.bump_gain > 0.0);
  return p;
}

/// The ground under the wheels and the GM's output on it, at grid point j.
class Ground {
 public:
  Ground(const PreparedTrial& trial, const Setup& m, const Paths& paths, const std::vector<double>& x_grid)
      : trial_(trial), m_(m), paths_(paths), x_grid_(x_grid), gm_(trial.chair) {}

  /// Contact heights h_i under the wheels, the chair pitched by θ (each wheel's breakpoint
  /// search starts where its last ended).
  void Contacts(std::size_t j, double theta, double* h) {
    const int w = m_.wheels;
    if (paths_.wheel_cache) {
      const double* c = trial_.wheel_cache.data() + j * static_cast<std::size_t>(w);
      for (int i = 0; i < w; ++i) h[i] = c[i] * m_.height_factor[i];
      return;
    }
    double x = x_grid_[j];
    if (paths_.marker) x -= m_.marker_x * std::cos(theta) - m_.marker_z * std::sin(theta);
    const double lever = m_.Exact() ? std::cos(theta) : 1.0;  // wheel i at x_i cos θ (exact)
    for (int i = 0; i < w; ++i) {
      const double xi = m_.Exact() ? x + m_.wheel_x[i] * lever : x + m_.wheel_x[i];
      const double height = m_.radius[i] > 0.0 ? RollingDiscEnvelope(trial_.terrain, xi, m_.radius[i]).height
                                               : trial_.terrain.HeightAtNear(xi, terrain_hint_[i]);
      h[i] = height * m_.height_factor[i];
    }
  }

  /// The GM on the wheels' heights zc (the cushion's q, the tyres' series shift).
  GeometricOutput Geometric(std::size_t j, const double* zc) const {
    if (paths_.gm_cache) return GeometricOutput{trial_.gm_cache[2 * j], trial_.gm_cache[2 * j + 1]};
    const int w = m_.wheels;
    GeometricOutput out = gm_.Evaluate(std::span<const double>(zc, static_cast<std::size_t>(w)));
    out.pitch *= m_.gm_pitch_gain;
    if (m_.on.series) {
      // The GM saw the ground through tyre and suspension in series; on the unsprung wheels'
      // heights it is the suspension's: shift it by the difference of the two planes.
      for (int i = 0; i < w; ++i) {
        out.z += m_.gm_dz[i] * zc[i];
        out.pitch += m_.gm_dt[i] * zc[i];
      }
    }
    return out;
  }

 private:
  const PreparedTrial& trial_;
  const Setup& m_;
  const Paths& paths_;
  const std::vector<double>& x_grid_;
  const GeometricModel gm_;
  std::array<std::size_t, kMaxWheels> terrain_hint_{};
};

/// What one step starts from and hands to the next.
struct StepState {
  Body body;
  std::optional<PitchTrig> body_trig;  ///< where Paths::body_trig
  GeometricOutput gm;                  ///< the GM output at the step's start
  std::optional<PitchTrig> gm_trig;    ///< where exact kinematics
  double gm_z_rate{0.0}, gm_pitch_rate{0.0};  ///< the previous step's GM rates
  std::array<double, kMaxWheels> h{};      ///< ground heights under the wheels
  std::array<double, kMaxWheels> zc{};     ///< the GM's input: the hubs' (or the ground's) heights
  std::array<double, kMaxWheels> tyre_z{}, tyre_rate{};  ///< unsprung tyres
  std::array<double, kMaxWheels> friction{};  ///< each wheel's friction force [N]
  std::array<double, kMaxWheels> off_static{};  ///< each wheel's static height off the plane
};

/// The start of the run: static equilibrium at the first grid point, tyres undeflected
/// (deviations from the static state), the body at the GM output shifted by the inertial
/// torque through K.
StepState StaticStart(const Setup& m, const Paths& paths, Ground& ground, double accel) {
  StepState s;
  if (paths.need_contacts) ground.Contacts(0, 0.0, s.h.data());
  s.zc = s.h;
  s.tyre_z = s.h;
  s.gm = ground.Geometric(0, s.zc.data());
  const double torque = m.mass * m.lever * accel;
  const double det = m.k_z * m.k_t - m.k_zt * m.k_zt;
  s.body.z = s.gm.z + (det > 0 ? -m.k_zt * torque / det : 0.0);
  s.body.pitch = s.gm.pitch + (det > 0 ? m.k_z * torque / det : 0.0);
  s.body_trig = Trig(s.body.pitch, paths.body_trig, paths.body_cos);
  s.gm_trig = Trig(s.gm.pitch, m.Exact(), true);
  if (m.on.series) OffPlane(m, s.zc.data(), s.off_static.data());
  return s;
}

/// One step of the unsprung tyres (header, tyre_compliance) to the ground h1: each takes its
/// share of the suspension's force and torque at the step's start in reaction; zc1 the hubs'
/// heights at its end.
void AdvanceUnsprungTyres(const Setup& m, StepState& s, const double* h1, double dt, double* zc1) {
  const int w = m.wheels;
  const double inv_dt = 1.0 / dt;
  const Body& body = s.body;
  // The suspension's force and torque on the chassis (spring, damper and coupling, deviations
  // from equilibrium).
  const double dz = body.z - s.gm.z, dp = body.pitch - s.gm.pitch;
  const double dz_rate = body.z_rate - s.gm_z_rate, dp_rate = body.pitch_rate - s.gm_pitch_rate;
  // The pitch spring and damper (exact kinematics: on sin θ - sin θ_GM and its rate).
  const double pitch_spring =
      m.Exact() ? m.k_t * (s.body_trig.value().sin - s.gm_trig.value().sin) +
                    m.c_t * (s.body_trig->cos.value() * body.pitch_rate -
                             s.gm_trig->cos.value() * s.gm_pitch_rate)
              : m.k_t * dp + m.c_t * dp_rate;
  const double force = m.k_z * dz + m.c_z * dz_rate + m.k_zt * dp + m.c_zt * dp_rate;
  const double torque = pitch_spring + m.k_zt * dz + m.c_zt * dz_rate;
  std::array<double, kMaxWheels> off{}, off_rate{}, zc_rate{};
  if (m.on.series) {
    for (int i = 0; i < w; ++i) zc_rate[i] = m.tyre[i] != 0 ? s.tyre_rate[i] : (h1[i] - s.h[i]) * inv_dt;
    OffPlane(m, s.zc.data(), off.data());
    OffPlane(m, zc_rate.data(), off_rate.data());
  }
  for (int i = 0; i < w; ++i) {
    if (m.tyre[i] == 0) {
      zc1[i] = h1[i];
      continue;
    }
    // The chassis' force and torque split over the wheels by the suspension plane, plus the
    // wheel's own spring and damper on its height off that plane.
    const double reaction = m.plane_z[i] * force + m.plane_t[i] * torque -
                            m.k_wheel[i] * (off[i] - s.off_static[i]) - m.c_wheel[i] * off_rate[i];
    const int c = m.tyre[i];
    const double ground_rate = (h1[i] - s.h[i]) * inv_dt;
    const double tyre_accel =
        m.tyre_omega2[c] * (s.h[i] - s.tyre_z[i]) + m.tyre_2zw[c] * (ground_rate - s.tyre_rate[i]);
    if (tyre_accel < m.lift_off[i]) {
      // The wheel is off the ground over this step: only gravity, the static suspension load
      // and the reaction act on it.
      const double accel = m.lift_off[i] + reaction * m.inv_unsprung[i];
      s.tyre_z[i] += s.tyre_rate[i] * dt + 0.5 * accel * dt * dt;
      s.tyre_rate[i] += accel * dt;
    } else {
      AdvanceAxis(m.tyre_propagator[c], s.tyre_z[i], s.tyre_rate[i], s.h[i], ground_rate,
                  reaction * m.inv_unsprung[i]);
    }
    zc1[i] = s.tyre_z[i];
  }
}

/// The body over one step to the GM output g1 (rates gm_z_rate, gm_pitch_rate) with the
/// inertial torque; the held forces (coupling, hardening, stops, friction, exact kinematics)
/// by Heun: predicted with the start's, corrected with the mean of both ends.
Body AdvanceBody(const Setup& m, const Paths& paths, const StepState& s, const GeometricOutput& g1,
                 const std::optional<PitchTrig>& g1_trig, double gm_z_rate, double gm_pitch_rate,
                 double torque, const double* zc1) {
  Body next = s.body;
  if (!m.on.held_forces) {
    AdvanceAxis(m.heave, next.z, next.z_rate, s.gm.z, gm_z_rate, 0.0);
    AdvanceAxis(m.pitch, next.pitch, next.pitch_rate, s.gm.pitch, gm_pitch_rate, torque);
    return next;
  }
  const Load f0 = HeldForces(m, s.body, s.body_trig, s.gm, s.gm_trig, gm_z_rate, gm_pitch_rate, s.zc.data(),
                             s.friction.data());
  AdvanceAxis(m.heave, next.z, next.z_rate, s.gm.z, gm_z_rate, f0.heave);
  AdvanceAxis(m.pitch, next.pitch, next.pitch_rate, s.gm.pitch, gm_pitch_rate, torque + f0.pitch);
  const std::optional<PitchTrig> predicted = Trig(next.pitch, paths.predicted_trig, m.Exact());
  const Load f1 = HeldForces(m, next, predicted, g1, g1_trig, gm_z_rate, gm_pitch_rate, zc1, s.friction.data());
  next = s.body;
  AdvanceAxis(m.heave, next.z, next.z_rate, s.gm.z, gm_z_rate, 0.5 * (f0.heave + f1.heave));
  AdvanceAxis(m.pitch, next.pitch, next.pitch_rate, s.gm.pitch, gm_pitch_rate, torque + 0.5 * (f0.pitch + f1.pitch));
  return next;
}

/// Each wheel's friction over the step from `s` to the body `next` (sine s1) and the hubs zc1:
/// Dahl's F relaxes exactly towards F_c sgn ṙ_i with rate |ṙ_i| / δ_p for the step's deflection
/// rate ṙ_i held; smooth Coulomb F_c tanh(ṙ_i / v_s).
void UpdateFriction(const Setup& m, StepState& s, const Body& next, double s1, const double* zc1, double dt) {
  const double inv_dt = 1.0 / dt;
  const double s0 = s.body_trig.value().sin;
  for (int i = 0; i < m.wheels; ++i) {
    if (m.friction[i] <= 0.0) continue;
    const double r_rate =
        ((next.z + m.wheel_x[i] * s1) - (s.body.z + m.wheel_x[i] * s0) - (zc1[i] - s.zc[i])) * inv_dt;
    double& f = s.friction[i];
    if (m.SmoothCoulomb()) {
      f = m.friction[i] * std::tanh(r_rate / m.smooth_rate[i]);
      continue;
    }
    const double target = r_rate > 0.0 ? m.friction[i] : (r_rate < 0.0 ? -m.friction[i] : f);
    f = target + (f - target) * std::exp(-std::abs(r_rate) * dt / m.presliding);
  }
}

/// The run's outputs on the grid.
struct GridRecord {
  std::vector<double> z, pitch, z_gm, pitch_gm;
  explicit GridRecord(std::size_t n) : z(n), pitch(n), z_gm(n), pitch_gm(n) {}
  /// The measured altitude (through the marker's lever where it is on) and pitch, and the GM's.
  void Record(std::size_t j, const Setup& m, const Paths& paths, const StepState& s) {
    const Body& b = s.body;
    z[j] = paths.marker ? b.z + m.marker_x * s.body_trig.value().sin +
                              m.marker_z * (s.body_trig->cos.value() - 1.0)
                        : b.z;
    pitch[j] = b.pitch;
    z_gm[j] = s.gm.z;
    pitch_gm[j] = s.gm.pitch;
  }
};

}  // namespace

ModelOutput SimulateExtended(const PreparedTrial& trial, const ExtendedParams& params) {
  const Setup m = MakeSetup(trial, params);
  const double dt = trial.step;
  const double inv_dt = 1.0 / dt;
  const bool cached = trial.cache_step > 0.0 && trial.cache_step == dt;
  std::vector<double> x_local, a_local;
  if (!cached) {
    x_local = InterpolateOnGrid(trial.t, trial.x, dt);
    a_local = InterpolateOnGrid(trial.t, trial.accel, dt);
  }
  const std::vector<double>& x_grid = cached ? trial.x_grid : x_local;
  const std::vector<double>& a_grid = cached ? trial.accel_grid : a_local;
  const std::size_t grid = x_grid.size();
  const Paths paths = PathsOf(m, cached);
  Ground ground(trial, m, paths, x_grid);
  GridRecord record(grid);
  StepState s = StaticStart(m, paths, ground, a_grid[0]);
  record.Record(0, m, paths, s);

  std::array<double, kMaxWheels> h1{}, zc1{};
  for (std::size_t j = 0; j + 1 < grid; ++j) {
    if (paths.need_contacts) ground.Contacts(j + 1, s.body.pitch + dt * s.body.pitch_rate, h1.data());
    if (m.on.massless)
      AdvanceMasslessHubs(m, s.body, s.body_trig, s.gm, s.gm_trig, s.h.data(), h1.data(), s.zc.data(),
                          s.off_static.data(), dt, zc1.data());
    else if (m.on.tyre)
      AdvanceUnsprungTyres(m, s, h1.data(), dt, zc1.data());
    else
      zc1 = h1;
    const GeometricOutput g1 = ground.Geometric(j + 1, zc1.data());
    const std::optional<PitchTrig> g1_trig = Trig(g1.pitch, m.Exact(), true);
    const double gm_z_rate = (g1.z - s.gm.z) * inv_dt;
    const double gm_pitch_rate = (g1.pitch - s.gm.pitch) * inv_dt;
    const double torque = m.mass * m.lever * a_grid[j];
    const Body next = AdvanceBody(m, paths, s, g1, g1_trig, gm_z_rate, gm_pitch_rate, torque, zc1.data());
    std::optional<PitchTrig> next_trig = Trig(next.pitch, paths.body_trig, paths.body_cos);
    if (m.on.friction) UpdateFriction(m, s, next, next_trig.value().sin, zc1.data(), dt);
    s.body = next;
    s.body_trig = std::move(next_trig);
    s.gm = g1;
    s.gm_trig = g1_trig;
    s.h = h1;
    s.zc = zc1;
    s.gm_z_rate = gm_z_rate;
    s.gm_pitch_rate = gm_pitch_rate;
    record.Record(j + 1, m, paths, s);
  }

  const double t0 = trial.t.front();
  ModelOutput out;
  out.z = SampleGrid(record.z, t0, dt, trial.t);
  out.pitch = SampleGrid(record.pitch, t0, dt, trial.t);
  out.z_gm = SampleGrid(record.z_gm, t0, dt, trial.t);
  out.pitch_gm = SampleGrid(record.pitch_gm, t0, dt, trial.t);
  return out;
}

}  // namespace pwsim::effects
