#include "sysid/effects/effect_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "engine/check.h"

namespace pwsim::effects {
namespace {

constexpr int kMaxState = 4 + 2 * kMaxWheels;
using State = std::array<double, kMaxState>;

struct Ground {
  double height{0.0};
  double slope{0.0};
};

Ground GroundAt(const Terrain& terrain, double x) {
  const std::size_t n = terrain.x.size();
  if (n < 2 || x < terrain.x.front() || x >= terrain.x.back()) return {};
  const auto upper = std::upper_bound(terrain.x.begin(), terrain.x.end(), x);
  const std::size_t k = static_cast<std::size_t>(upper - terrain.x.begin());
  const double m = (terrain.z[k] - terrain.z[k - 1]) / (terrain.x[k] - terrain.x[k - 1]);
  return {terrain.z[k - 1] + m * (x - terrain.x[k - 1]), m};
}

/// Everything the right-hand side needs, precomputed from the trial and parameters.
struct Rhs {
  const PreparedTrial* trial{nullptr};
  int wheels{0};
  std::array<double, kMaxWheels> wheel_x{};
  std::array<double, kMaxWheels> alpha{};
  std::array<double, kMaxWheels> radius{};
  std::array<double, kMaxWheels> omega{};  ///< tyre mode [rad/s]; 0 = rigid
  std::array<double, kMaxWheels> height_factor{};
  std::array<int, kMaxWheels> tyre_slot{};  ///< index of the wheel's tyre state or -1
  struct Pair {
    int i, j;
    double weight, inv_dx;
  };
  std::vector<Pair> pairs;
  double zeta{0.5};
  double mass{1.0}, inertia{1.0};
  double k_z{0}, c_z{0}, k_t{0}, c_t{0}, k_zt{0}, c_zt{0};
  double hard_z{0}, hard_t{0}, fric_z{0}, fric_t{0}, lever{0};
  double bump_gain{0}, bump_gap{0};  ///< per-wheel bump stops (nonlinear_stiffness)

  struct Gm {
    double z, z_rate, pitch, pitch_rate;
  };

  /// GM output given the effective contact heights and rates.
  Gm Geometric(const double* zc, const double* zc_rate) const {
    Gm gm{0, 0, 0, 0};
    for (int i = 0; i < wheels; ++i) {
      gm.z += alpha[i] * zc[i];
      gm.z_rate += alpha[i] * zc_rate[i];
    }
    for (const Pair& p : pairs) {
      const double arg = std::clamp((zc[p.i] - zc[p.j]) * p.inv_dx, -1.0, 1.0);
      gm.pitch += p.weight * std::asin(arg);
      const double root = std::sqrt(std::max(1e-9, 1.0 - arg * arg));
      gm.pitch_rate += p.weight * (zc_rate[p.i] - zc_rate[p.j]) * p.inv_dx / root;
    }
    return gm;
  }

  bool use_wheel_cache{false};
  bool use_gm_cache{false};

  /// Contact heights (before tyres) and their time rates at position x with speed v.
  void Contacts(double x, double v, double* h, double* h_rate, long point) const {
    if (use_wheel_cache && point >= 0) {
      const double* c = trial->wheel_cache.data() + point * 2 * wheels;
      for (int i = 0; i < wheels; ++i) {
        h[i] = c[2 * i] * height_factor[i];
        h_rate[i] = c[2 * i + 1] * height_factor[i] * v;
      }
      return;
    }
    for (int i = 0; i < wheels; ++i) {
      const double xi = x + wheel_x[i];
      double height, slope;
      if (radius[i] > 0.0) {
        const EnvelopePoint e = RollingDiscEnvelope(trial->terrain, xi, radius[i]);
        height = e.height;
        slope = e.slope;
      } else {
        const Ground g = GroundAt(trial->terrain, xi);
        height = g.height;
        slope = g.slope;
      }
      h[i] = height * height_factor[i];
      h_rate[i] = slope * height_factor[i] * v;
    }
  }

  /// ds/dt at one instant; fills gm_out with the GM output seen by the LM.
  double marker_x{0.0}, marker_z{0.0};

  void Eval(double x, double v, double a, const State& s, State& ds, Gm* gm_out,
            long point) const {
    if (marker_x != 0.0 || marker_z != 0.0) {
      x -= marker_x * std::cos(s[2]) - marker_z * std::sin(s[2]);
      point = -1;
    }
    Gm gm;
    std::array<double, kMaxWheels> zc{};
    if (use_gm_cache && point >= 0) {
      const double* c = trial->gm_cache.data() + point * 4;
      gm = {c[0], c[1] * v, c[2], c[3] * v};
    } else {
      gm = ContactGm(x, v, s, ds, point, zc.data());
    }
    Lumped(a, s, ds, gm);
    if (bump_gain > 0.0) {
      // Bump stops: F_i = b K_Z α_i max(0, c_i - g)² / δ_ref on each wheel's compression
      // c_i = Z_Oi - (Z + x_i sin θ), pushing the chassis up at x_i.
      double fz = 0.0, fp = 0.0;
      const double sin_t = std::sin(s[2]);
      for (int i = 0; i < wheels; ++i) {
        const double over = zc[i] - (s[0] + wheel_x[i] * sin_t) - bump_gap;
        if (over <= 0.0) continue;
        const double f = bump_gain * k_z * alpha[i] * over * over / kHeaveRef;
        fz += f;
        fp += f * wheel_x[i];
      }
      ds[1] += fz / mass;
      ds[3] += fp / inertia;
    }
    if (gm_out) *gm_out = gm;
  }

  Gm ContactGm(double x, double v, const State& s, State& ds, long point, double* zc_out = nullptr) const {
    std::array<double, kMaxWheels> h{}, h_rate{}, zc{}, zc_rate{};
    Contacts(x, v, h.data(), h_rate.data(), point);
    for (int i = 0; i < wheels; ++i) {
      const int slot = tyre_slot[i];
      if (slot < 0) {
        zc[i] = h[i];
        zc_rate[i] = h_rate[i];
      } else {
        const double zt = s[slot], zt_rate = s[slot + 1];
        zc[i] = zt;
        zc_rate[i] = zt_rate;
        ds[slot] = zt_rate;
        ds[slot + 1] = omega[i] * omega[i] * (h[i] - zt) + 2.0 * zeta * omega[i] * (h_rate[i] - zt_rate);
      }
    }
    if (zc_out) std::copy(zc.begin(), zc.begin() + wheels, zc_out);
    return Geometric(zc.data(), zc_rate.data());
  }

  void Lumped(double a, const State& s, State& ds, const Gm& gm) const {
    const double dz = s[0] - gm.z, dz_rate = s[1] - gm.z_rate;
    const double dp = s[2] - gm.pitch, dp_rate = s[3] - gm.pitch_rate;
    const double qz = dz / kHeaveRef, qp = dp / kPitchRef;
    double fz = k_z * dz * (1.0 + hard_z * qz * qz) + k_zt * dp + c_z * dz_rate + c_zt * dp_rate;
    double fp = k_t * dp * (1.0 + hard_t * qp * qp) + k_zt * dz + c_t * dp_rate + c_zt * dz_rate;
    if (fric_z > 0.0) fz += fric_z * std::tanh(dz_rate / kHeaveFrictionEps);
    if (fric_t > 0.0) fp += fric_t * std::tanh(dp_rate / kPitchFrictionEps);
    ds[0] = s[1];
    ds[1] = -fz / mass;
    ds[2] = s[3];
    ds[3] = (mass * lever * a - fp) / inertia;
  }
};

}  // namespace

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

EnvelopePoint RollingDiscEnvelope(const Terrain& terrain, double x, double radius) {
  if (radius <= 0.0) {
    const Ground g = GroundAt(terrain, x);
    return {g.height, g.slope};
  }
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
  if (accel.size() != n) {
    accel.assign(n, 0.0);
    std::size_t lo = 0, hi = 0;
    for (std::size_t k = 0; k < n; ++k) {
      while (t[k] - t[lo] > accel_window) ++lo;
      while (hi + 1 < n && t[hi + 1] - t[k] <= accel_window) ++hi;
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
  }
  trial.t = std::move(t);
  trial.x = std::move(x);
  trial.accel = std::move(accel);
  return trial;
}

namespace {

Rhs MakeRhs(const PreparedTrial& trial, const ExtendedParams& params, int* state_size) {
  const Chair& chair = trial.chair;
  const EffectParams& fx = params.fx;
  Rhs rhs;
  rhs.trial = &trial;
  rhs.wheels = chair.wheel_count();
  PWSIM_DEMAND(rhs.wheels <= kMaxWheels && chair.gm.has_value());
  const std::vector<double> loads = StaticWheelLoads(chair, trial.load_kg);
  int slot = 4;
  for (int i = 0; i < rhs.wheels; ++i) {
    const bool caster = trial.is_caster[i];
    rhs.wheel_x[i] = chair.wheels[i].x;
    rhs.alpha[i] = chair.gm->alpha[i];
    rhs.radius[i] = caster ? fx.caster_radius : fx.drive_radius;
    const double period = caster ? fx.caster_tyre_period : fx.drive_tyre_period;
    rhs.omega[i] = period > 1e-6 ? 2.0 * std::numbers::pi / period : 0.0;
    rhs.tyre_slot[i] = rhs.omega[i] > 0.0 ? slot : -1;
    if (rhs.omega[i] > 0.0) slot += 2;
    const double load_kn =
        1e-3 * (fx.cushion_whole_chair ? MovingMass(chair, trial.load_kg) * kGravity : loads[i]);
    const double loss = fx.cushion_loss_per_kn == 0.0
                            ? 0.0
                            : fx.cushion_loss_per_kn * std::pow(std::max(0.0, load_kn), fx.cushion_exponent);
    rhs.height_factor[i] = std::max(0.0, fx.cushion_height_gain - loss);
  }
  for (const PairWeight& p : chair.gm->beta) {
    if (p.weight == 0.0) continue;
    rhs.pairs.push_back({p.i, p.j, p.weight, 1.0 / (chair.wheels[p.i].x - chair.wheels[p.j].x)});
  }
  rhs.zeta = fx.tyre_damping;
  rhs.mass = MovingMass(chair, trial.load_kg);
  rhs.inertia = PitchInertia(chair, trial.load_kg);
  rhs.k_z = params.lm.k_z;
  rhs.c_z = params.lm.c_z;
  rhs.k_t = params.lm.k_theta;
  rhs.c_t = params.lm.c_theta;
  rhs.k_zt = fx.stiffness_coupling * std::sqrt(std::max(0.0, rhs.k_z * rhs.k_t));
  rhs.c_zt = fx.damping_coupling * std::sqrt(std::max(0.0, rhs.c_z * rhs.c_t));
  rhs.hard_z = fx.heave_hardening;
  rhs.hard_t = fx.pitch_hardening;
  rhs.fric_z = fx.heave_friction;
  rhs.fric_t = fx.pitch_friction;
  // Γ_θ = M lever a_x with the mass-weighted lever of chair and occupant.
  rhs.lever = (chair.mass * fx.cm_lever + trial.load_kg * fx.load_cm_lever) / MovingMass(chair, trial.load_kg);
  rhs.bump_gain = fx.bump_gain;
  rhs.bump_gap = fx.bump_gap;
  rhs.marker_x = fx.marker_lever_x;
  rhs.marker_z = fx.marker_lever_z;
  if (state_size) *state_size = slot;
  return rhs;
}

/// The largest RK4 step for these dynamics: h·|λ| about 1 or less for the fastest mode.
double StableStep(const Rhs& rhs, double max_step) {
  for (int i = 0; i < rhs.wheels; ++i) {
    if (rhs.omega[i] > 0.0) max_step = std::min(max_step, 1.2 / (rhs.omega[i] * (1.0 + rhs.zeta)));
  }
  if (rhs.fric_z > 0.0) max_step = std::min(max_step, 1.2 * kHeaveFrictionEps * rhs.mass / rhs.fric_z);
  if (rhs.fric_t > 0.0) max_step = std::min(max_step, 1.2 * kPitchFrictionEps * rhs.inertia / rhs.fric_t);
  return std::max(max_step, 2e-4);
}

int StepsFor(double dt, double max_step) {
  return std::max(1, static_cast<int>(std::ceil(dt / max_step - 1e-9)));
}

}  // namespace

void CacheInputs(PreparedTrial& trial) {
  trial.cache_step = 0.0;
  trial.wheel_cache.clear();
  trial.gm_cache.clear();
  const Rhs rhs = MakeRhs(trial, ExtendedParams{}, nullptr);
  const int w = rhs.wheels;
  std::array<double, kMaxWheels> h{}, slope{};
  auto add = [&](double x) {
    rhs.Contacts(x, 1.0, h.data(), slope.data(), -1);
    for (int i = 0; i < w; ++i) {
      trial.wheel_cache.push_back(h[i]);
      trial.wheel_cache.push_back(slope[i]);
    }
    const Rhs::Gm gm = rhs.Geometric(h.data(), slope.data());
    trial.gm_cache.insert(trial.gm_cache.end(), {gm.z, gm.z_rate, gm.pitch, gm.pitch_rate});
  };
  for (std::size_t k = 0; k + 1 < trial.t.size(); ++k) {
    const double dt = trial.t[k + 1] - trial.t[k];
    const double v = (trial.x[k + 1] - trial.x[k]) / dt;
    const int steps = StepsFor(dt, trial.max_step);
    const double hstep = dt / steps;
    for (int j = 0; j <= 2 * steps; ++j) add(trial.x[k] + v * (0.5 * hstep * j));
  }
  add(trial.x.back());
  trial.cache_step = trial.max_step;
}

ModelOutput SimulateExtended(const PreparedTrial& trial, const ExtendedParams& params) {
  const EffectParams& fx = params.fx;
  int dim = 4;
  Rhs rhs = MakeRhs(trial, params, &dim);
  const double max_step = StableStep(rhs, trial.max_step);
  const bool cached = trial.cache_step > 0.0 && trial.cache_step == max_step;
  bool rigid_points = true, plain = true;
  for (int i = 0; i < rhs.wheels; ++i) {
    if (rhs.radius[i] > 0.0) rigid_points = false;
    if (rhs.radius[i] > 0.0 || rhs.omega[i] > 0.0 || rhs.height_factor[i] != 1.0) plain = false;
    if (rhs.bump_gain > 0.0) plain = false;  // needs each wheel's contact height
  }
  rhs.use_wheel_cache = cached && rigid_points;
  rhs.use_gm_cache = cached && plain;

  const std::size_t n = trial.t.size();
  ModelOutput out;
  out.z.resize(n);
  out.pitch.resize(n);
  out.z_gm.resize(n);
  out.pitch_gm.resize(n);

  // Static equilibrium at the first sample.
  State s{};
  {
    std::array<double, kMaxWheels> h{}, h_rate{};
    const bool marker = rhs.marker_x != 0.0 || rhs.marker_z != 0.0;
    rhs.Contacts(trial.x[0] - rhs.marker_x, 0.0, h.data(), h_rate.data(), cached && !marker ? 0 : -1);
    for (int i = 0; i < rhs.wheels; ++i) {
      if (rhs.tyre_slot[i] >= 0) s[rhs.tyre_slot[i]] = h[i];
    }
    std::array<double, kMaxWheels> zero{};
    const Rhs::Gm gm = rhs.Geometric(h.data(), zero.data());
    const double torque = rhs.mass * rhs.lever * trial.accel[0];
    const double det = rhs.k_z * rhs.k_t - rhs.k_zt * rhs.k_zt;
    s[0] = gm.z + (det > 0 ? -rhs.k_zt * torque / det : 0.0);
    s[2] = gm.pitch + (det > 0 ? rhs.k_z * torque / det : 0.0);
  }

  auto output = [&](std::size_t k, const Rhs::Gm& gm) {
    out.z[k] = s[0] + fx.marker_lever_x * std::sin(s[2]) + fx.marker_lever_z * (std::cos(s[2]) - 1.0);
    out.pitch[k] = s[2];
    out.z_gm[k] = gm.z;
    out.pitch_gm[k] = gm.pitch;
  };

  State k1{}, k2{}, k3{}, k4{}, tmp{};
  long point = 0;  // index of the current interval's first half-step point in the caches
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double t0 = trial.t[k];
    const double dt = trial.t[k + 1] - t0;
    const double v = (trial.x[k + 1] - trial.x[k]) / dt;
    const double a0 = trial.accel[k];
    const double a_rate = (trial.accel[k + 1] - a0) / dt;
    const int steps = StepsFor(dt, max_step);
    const double h = dt / steps;
    for (int step = 0; step < steps; ++step) {
      const double tau = step * h;
      const long p0 = cached ? point + 2 * step : -1;
      auto at = [&](int half, const State& state, State& ds, Rhs::Gm* gm) {
        const double u = tau + 0.5 * h * half;
        rhs.Eval(trial.x[k] + v * u, v, a0 + a_rate * u, state, ds, gm, cached ? p0 + half : -1);
      };
      Rhs::Gm gm0;
      at(0, s, k1, &gm0);
      if (step == 0) output(k, gm0);
      for (int d = 0; d < dim; ++d) tmp[d] = s[d] + 0.5 * h * k1[d];
      at(1, tmp, k2, nullptr);
      for (int d = 0; d < dim; ++d) tmp[d] = s[d] + 0.5 * h * k2[d];
      at(1, tmp, k3, nullptr);
      for (int d = 0; d < dim; ++d) tmp[d] = s[d] + h * k3[d];
      at(2, tmp, k4, nullptr);
      for (int d = 0; d < dim; ++d) s[d] += h / 6.0 * (k1[d] + 2.0 * k2[d] + 2.0 * k3[d] + k4[d]);
    }
    point += 2 * steps + 1;
  }
  {
    Rhs::Gm gm;
    const std::size_t last = n - 1;
    const double v = (trial.x[last] - trial.x[last - 1]) / (trial.t[last] - trial.t[last - 1]);
    rhs.Eval(trial.x[last], v, trial.accel[last], s, k1, &gm, cached ? point : -1);
    output(last, gm);
  }
  return out;
}

}  // namespace pwsim::effects
