#include "tests/truth/independent_truth.h"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "tests/truth/law_space.h"

namespace pwsim::truth {
namespace {

constexpr double kG = 9.81;
using State = std::vector<double>;

double Clamp(double v, double lo, double hi) { return std::min(hi, std::max(lo, v)); }

/// Jerk-limited speed profile: v(t) and a(t) in closed form per phase.
struct Profile {
  DriveProfile p;
  double t_acc{0}, t_cruise{0}, t_dec{0}, t_end{0};
  double x_after_acc{0};

  /// Acceleration of a trapezoid pulse of height a, ramp r, total duration T starting at 0.
  static double Pulse(double tau, double a, double r, double total) {
    if (tau <= 0.0 || tau >= total) return 0.0;
    if (tau < r) return a * tau / r;
    if (tau > total - r) return a * (total - tau) / r;
    return a;
  }
  double Accel(double t) const {
    const double total = p.speed_mps / p.accel_mps2 + p.jerk_time_s;
    if (t < t_acc) return Pulse(t - p.still_s, p.accel_mps2, p.jerk_time_s, total);
    if (t < t_cruise) return 0.0;
    return -Pulse(t - t_cruise, p.accel_mps2, p.jerk_time_s, total);
  }
};

Profile MakeProfile(const DriveProfile& d) {
  Profile pr;
  pr.p = d;
  const double pulse = d.speed_mps / d.accel_mps2 + d.jerk_time_s;  // ∫a = a (T - r) = v
  pr.t_acc = d.still_s + pulse;
  // Distance covered while accelerating: v T / 2 by symmetry of the trapezoid.
  pr.x_after_acc = 0.5 * d.speed_mps * pulse;
  pr.t_cruise = pr.t_acc + std::max(0.0, (d.cruise_until_m - pr.x_after_acc) / d.speed_mps);
  pr.t_dec = pr.t_cruise + pulse;
  pr.t_end = pr.t_dec + d.still_s;
  return pr;
}

/// Centre height minus R of a disc resting on the profile at horizontal position x.
double DiscGround(const Obstacle& o, double x, double r) {
  if (r <= 0.0) return o.HeightAt(x);
  // Candidate support intervals: every segment of the profile plus the flat outside.
  std::vector<double> knots{x - r};
  for (double k : o.x_m)
    if (k > x - r && k < x + r) knots.push_back(k);
  knots.push_back(x + r);
  double best = -1e9;
  for (std::size_t s = 0; s + 1 < knots.size(); ++s) {
    double lo = knots[s], hi = knots[s + 1];
    auto f = [&](double u) {
      const double dx = u - x;
      return o.HeightAt(u) + std::sqrt(std::max(0.0, r * r - dx * dx));
    };
    for (int it = 0; it < 60 && hi - lo > 1e-10; ++it) {  // concave on the segment
      const double m1 = lo + (hi - lo) / 3.0, m2 = hi - (hi - lo) / 3.0;
      if (f(m1) < f(m2)) lo = m1;
      else hi = m2;
    }
    best = std::max({best, f(0.5 * (lo + hi)), f(knots[s]), f(knots[s + 1])});
  }
  return best - r;
}

struct Layout {
  int n{0};
  int tyre{-1}, dahl{-1}, foam{-1}, occ{-1}, size{6};
};

struct System {
  const TruthTrialConfig* c{nullptr};
  Profile prof;
  Layout lay;
  std::vector<double> k, cdamp, f0, radius, mu, kt, ct, t0;
  double mc{0}, jc{0}, m_occ{0}, k_seat{0}, c_seat{0}, torque_per_accel{0};
  double whole_weight{0};
  double friction_lever_m{0};  ///< L of chair-level friction

  /// Rate-dependent friction force (smooth Coulomb or Stribeck) at relative rate v; 0 for Dahl.
  double RateFriction(double v) const {
    const TruthEffects& fx = c->effects;
    if (fx.dahl_force_n <= 0.0 || fx.friction_law == TruthEffects::FrictionLaw::kDahl) return 0.0;
    double level = fx.dahl_force_n;
    if (fx.friction_law == TruthEffects::FrictionLaw::kStribeck) {
      const double r = v / fx.friction_stribeck_mps;
      level += (fx.friction_breakaway_ratio - 1.0) * fx.dahl_force_n * std::exp(-r * r);
    }
    return level * std::tanh(v / fx.friction_smooth_mps);
  }

  double Ground(int i, double xi) const {
    return radius[i] > 0.0 ? DiscGround(c->terrain, xi, radius[i]) : c->terrain.HeightAt(xi);
  }

  void operator()(const State& s, State& ds, double t) const {
    const TruthEffects& fx = c->effects;
    const double x = s[0], v = s[1], z = s[2], zr = s[3], th = s[4], thr = s[5];
    const double a = prof.Accel(t);
    std::fill(ds.begin(), ds.end(), 0.0);
    ds[0] = v;
    ds[1] = a;
    const double ct_ = c->small_angle ? 1.0 : std::cos(th), st_ = c->small_angle ? th : std::sin(th);
    double force = 0.0, moment = 0.0;
    for (int i = 0; i < lay.n; ++i) {
      const TruthWheel& w = c->chair.wheels[static_cast<std::size_t>(i)];
      const double xi = x + w.x_m * ct_;
      const double xi_rate = v - w.x_m * st_ * thr;
      const double eps = 1e-4;
      double g = Ground(i, xi);
      double g_rate = (Ground(i, xi + eps) - Ground(i, xi - eps)) / (2 * eps) * xi_rate;
      if (lay.foam >= 0) {
        const double d = s[static_cast<std::size_t>(lay.foam + i)];
        g -= d;
        // Target deflection from the load (dynamic wheel force or the whole chair's weight).
        const double h = c->terrain.HeightAt(xi);
        double load = whole_weight;
        if (!fx.cushion_whole_chair && !fx.cushion_proportional) {
          const double susp = f0[i] + k[i] * ((lay.tyre >= 0 ? s[static_cast<std::size_t>(lay.tyre + 2 * i)] : g) -
                                              (z + w.x_m * st_));
          load = std::max(0.0, susp);
        }
        const double y = fx.cushion_proportional
                             ? std::min(0.8, fx.cushion_yield)
                             : std::min(0.8, fx.cushion_yield * std::pow(load / fx.cushion_ref_n, fx.cushion_exponent));
        const double dd = (h * y - d) / fx.cushion_tau_s;
        ds[static_cast<std::size_t>(lay.foam + i)] = dd;
        g_rate -= dd;
      }
      const bool has_tyre = lay.tyre >= 0 && kt[i] > 0.0;
      const std::size_t tyre_j = static_cast<std::size_t>(lay.tyre + 2 * i);
      double u = has_tyre ? s[tyre_j] : g;
      const double anchor = z + w.x_m * st_, anchor_rate = zr + w.x_m * ct_ * thr;
      const double delta = u - anchor;
      // Rate-independent extra forces: bump stops B(δ) = bump_on - bump_off and the Dahl state F_d.
      double bump_on = 0.0, bump_off = 0.0, fd = 0.0;
      if (fx.bump_gain > 0.0) {
        const double over = delta - fx.bump_gap_m;
        const bool compression = !fx.bump_rebound_only, rebound = fx.bump_symmetric || fx.bump_rebound_only;
        if (compression && over > 0.0) bump_on = k[i] * fx.bump_gain * over * over / fx.bump_gap_m;
        const double under = -delta - fx.bump_gap_m;
        if (rebound && under > 0.0) bump_off = k[i] * fx.bump_gain * under * under / fx.bump_gap_m;
      }
      if (lay.dahl >= 0) fd = s[static_cast<std::size_t>(lay.dahl + i)];
      const double extra = bump_on - bump_off + fd;
      double u_rate = g_rate;
      if (has_tyre && fx.tyre_massless) {
        // k_t (g - u) + c_t (ġ - u̇) = k δ + c (u̇ - Ȧ) + extra, solved for u̇.
        u_rate = (kt[i] * (g - u) + ct[i] * g_rate - k[i] * delta + cdamp[i] * anchor_rate - extra) /
                 (ct[i] + cdamp[i]);
      } else if (has_tyre) {
        u_rate = s[tyre_j + 1];
      }
      const double delta_rate = u_rate - anchor_rate;
      double susp = f0[i] + k[i] * delta + cdamp[i] * delta_rate;
      susp += bump_on;  // added one by one, in the order the development sets were made with
      susp -= bump_off;
      susp += fd;
      if (fx.dahl_force_n > 0.0) {
        susp += fx.friction_viscous_nspm * delta_rate;
        if (!fx.friction_chair_level) susp += RateFriction(delta_rate);
      }
      if (lay.dahl >= 0) {
        const double sigma = fx.dahl_force_n / fx.dahl_presliding_m;
        const double sgn = delta_rate > 0 ? 1.0 : (delta_rate < 0 ? -1.0 : 0.0);
        ds[static_cast<std::size_t>(lay.dahl + i)] = sigma * delta_rate * (1.0 - sgn * fd / fx.dahl_force_n);
      }
      if (has_tyre && fx.tyre_massless) {
        ds[tyre_j] = u_rate;
      } else if (has_tyre) {
        const double tyre = std::max(0.0, t0[i] + kt[i] * (g - u) + ct[i] * (g_rate - u_rate));
        ds[tyre_j] = u_rate;
        ds[tyre_j + 1] = ((tyre - t0[i]) - (susp - f0[i])) / mu[i];
      } else if (fx.unilateral_contact) {
        susp = std::max(0.0, susp);  // a wheel can leave the ground, not pull on it
      }
      force += susp - f0[i];
      moment += (susp - f0[i]) * w.x_m * ct_;
    }
    if (fx.dahl_force_n > 0.0 && fx.friction_chair_level) {
      const double lever = friction_lever_m;
      force -= RateFriction(zr);
      moment -= lever * RateFriction(lever * thr);
    }
    if (lay.occ >= 0) {
      const std::size_t j = static_cast<std::size_t>(lay.occ);
      const double seat = z + fx.seat_x_m * st_, seat_rate = zr + fx.seat_x_m * ct_ * thr;
      const double q = k_seat * (s[j] - seat) + c_seat * (s[j + 1] - seat_rate);
      force += q;
      moment += q * fx.seat_x_m * ct_;
      ds[j] = s[j + 1];
      ds[j + 1] = -q / m_occ;
    }
    ds[2] = zr;
    ds[3] = force / mc;
    ds[4] = thr;
    ds[5] = (moment + torque_per_accel * a) / jc;
  }
};

}  // namespace

double Obstacle::HeightAt(double x) const {
  if (x_m.size() < 2 || x < x_m.front() || x >= x_m.back()) return 0.0;
  const auto up = std::upper_bound(x_m.begin(), x_m.end(), x);
  const std::size_t k = static_cast<std::size_t>(up - x_m.begin());
  return z_m[k - 1] + (z_m[k] - z_m[k - 1]) * (x - x_m[k - 1]) / (x_m[k] - x_m[k - 1]);
}

TruthTrial SimulateTruthTrial(const TruthTrialConfig& c) {
  System sys;
  sys.c = &c;
  sys.prof = MakeProfile(c.drive);
  const TruthEffects& fx = c.effects;
  const int n = static_cast<int>(c.chair.wheels.size());
  Layout& lay = sys.lay;
  lay.n = n;
  const bool tyres = fx.tyre_massless ? (fx.caster_tyre_ratio > 0.0 || fx.drive_tyre_ratio > 0.0)
                                      : (fx.caster_tyre_hz > 0.0 || fx.drive_tyre_hz > 0.0);
  if (tyres && fx.tyre_massless && fx.dahl_force_n > 0.0 &&
      (fx.friction_law != TruthEffects::FrictionLaw::kDahl || fx.friction_viscous_nspm > 0.0))
    throw std::invalid_argument("massless tyres with rate-dependent friction: the hub balance would be implicit");
  if (tyres) { lay.tyre = lay.size; lay.size += 2 * n; }  // massless tyres use the first of the two
  if (fx.dahl_force_n > 0.0 && fx.friction_law == TruthEffects::FrictionLaw::kDahl) {
    lay.dahl = lay.size;
    lay.size += n;
  }
  if (fx.cushion_yield > 0.0) { lay.foam = lay.size; lay.size += n; }
  const double f = Clamp(fx.occupant_share, 0.0, 1.0);
  if (f > 0.0 && c.load_kg > 0.0) { lay.occ = lay.size; lay.size += 2; }
  const double m_load_rigid = (1.0 - (lay.occ >= 0 ? f : 0.0)) * c.load_kg;
  sys.mc = c.chair.mass_kg + m_load_rigid;
  sys.jc = c.chair.inertia_kgm2 + c.chair.cm_height_m * c.chair.cm_height_m * sys.mc;
  sys.m_occ = c.load_kg * f;
  if (lay.occ >= 0) {
    const double w = 2.0 * std::numbers::pi * fx.seat_hz;
    sys.k_seat = sys.m_occ * w * w;
    sys.c_seat = 2.0 * fx.seat_zeta * sys.m_occ * w;
  }
  sys.torque_per_accel = (c.chair.mass_kg) * fx.chassis_cm_height_m + c.load_kg * fx.load_cm_height_m;
  const double weight = (c.chair.mass_kg + c.load_kg) * kG;
  sys.whole_weight = weight;
  double ksum = 0.0;
  for (int i = 0; i < n; ++i) {
    const TruthWheel& w = c.chair.wheels[static_cast<std::size_t>(i)];
    double ki = w.k_npm, ci = w.c_nspm;
    const double e = fx.stiffness_asymmetry;
    if (e != 0.0 && w.x_m != 0.0) {
      ki *= w.x_m > 0 ? 1.0 + e : 1.0 - e;
      if (fx.damper_asymmetry) ci *= w.x_m > 0 ? 1.0 + e : 1.0 - e;
    }
    sys.k.push_back(ki);
    sys.cdamp.push_back(ci);
    ksum += ki;
    sys.radius.push_back(fx.contact_radius_scale * w.radius_m);
    sys.friction_lever_m = std::max(sys.friction_lever_m, std::abs(w.x_m));
    if (fx.tyre_massless) {
      const double ratio = w.caster ? fx.caster_tyre_ratio : fx.drive_tyre_ratio;
      sys.mu.push_back(0.0);
      sys.kt.push_back(ratio * ki);
      sys.ct.push_back(ratio * ki * fx.tyre_tau_s);
      continue;
    }
    const double m_u = w.caster ? fx.caster_unsprung_kg : fx.drive_unsprung_kg;
    const double hz = w.caster ? fx.caster_tyre_hz : fx.drive_tyre_hz;
    const double om = 2.0 * std::numbers::pi * hz;
    sys.mu.push_back(m_u);
    sys.kt.push_back(hz > 0.0 ? m_u * om * om : 0.0);
    sys.ct.push_back(hz > 0.0 ? 2.0 * fx.tyre_zeta * m_u * om : 0.0);
  }
  for (int i = 0; i < n; ++i) {
    sys.f0.push_back(weight * sys.k[static_cast<std::size_t>(i)] / ksum);
    sys.t0.push_back(sys.f0.back() + sys.mu[static_cast<std::size_t>(i)] * kG);
  }

  State s(static_cast<std::size_t>(lay.size), 0.0);
  // Static equilibrium at rest at x = 0 (flat ground there): every deviation zero.
  TruthTrial out;
  const double dt = 1.0 / c.rate_hz;
  std::vector<double> times;
  for (double t = 0.0; t <= sys.prof.t_end + 1e-12; t += dt) times.push_back(t);
  namespace ode = boost::numeric::odeint;
  // The step is capped (2 ms) so that the controller, idle at rest on the flat, cannot step over the obstacle.
  auto stepper = ode::make_dense_output(1e-9, 1e-7, 2e-3, ode::runge_kutta_dopri5<State>());
  std::vector<State> states;
  ode::integrate_times(stepper, std::ref(sys), s, times.begin(), times.end(), 1e-3,
                       [&](const State& st, double) { states.push_back(st); });
  std::mt19937_64 rng(c.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const std::size_t n_out = std::min(times.size(), states.size());
  std::vector<double> ex, ez, ep;  // the general noise model's sequences, one generator per trial
  if (!c.noise.white_only) {
    ex = ChannelNoiseSequence(c.noise, c.noise.x, n_out, c.rate_hz, rng);
    ez = ChannelNoiseSequence(c.noise, c.noise.z, n_out, c.rate_hz, rng);
    ep = ChannelNoiseSequence(c.noise, c.noise.pitch, n_out, c.rate_hz, rng);
  }
  for (std::size_t k = 0; k < n_out; ++k) {
    const State& st = states[k];
    const double th = st[4];
    out.t.push_back(times[k]);
    out.true_x.push_back(st[0]);
    out.true_z.push_back(st[2]);
    out.true_pitch.push_back(th);
    const double mx = st[0] + fx.marker_x_m * std::cos(th) - fx.marker_z_m * std::sin(th);
    const double mz = c.z_offset_m + st[2] + fx.marker_x_m * std::sin(th) + fx.marker_z_m * std::cos(th);
    if (c.noise.white_only) {  // the historical draw order: x, z, pitch per sample
      out.x.push_back(mx + c.noise_x_m * gauss(rng));
      out.z.push_back(mz + c.noise_z_m * gauss(rng));
      out.pitch.push_back(th + c.noise_pitch_rad * gauss(rng));
    } else {
      // Quantised exports (quantum 0: as is): the recorded value on its grid.
      auto grid = [](double v, double q) { return q > 0.0 ? q * std::round(v / q) : v; };
      out.x.push_back(grid(mx + ex[k], c.noise.x.quantum));
      out.z.push_back(grid(mz + ez[k], c.noise.z.quantum));
      out.pitch.push_back(grid(th + ep[k], c.noise.pitch.quantum));
    }
  }
  return out;
}

TruthChair RandomTruthChair(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto in = [&](double lo, double hi) { return lo + (hi - lo) * u(rng); };
  TruthChair c;
  c.mass_kg = in(45.0, 70.0);
  c.inertia_kgm2 = in(7.0, 13.0);
  c.cm_height_m = in(0.35, 0.50);
  const double xf = in(0.33, 0.45), xr = -in(0.33, 0.45);
  const double k_theta = in(4.0e3, 7.0e3);
  const double kappa = k_theta / (xf - xr);  // k_f x_f = -k_r x_r = κ
  const double kf = kappa / xf, kr = kappa / -xr;
  const double kd = in(0.2, 0.6) * (kf + kr);
  const double tau = in(0.035, 0.06);  // stiffness-proportional damping [s]
  c.wheels = {{"front_caster", xf, in(0.09, 0.11), kf, tau * kf, true},
              {"drive", 0.0, in(0.15, 0.18), kd, tau * kd, false},
              {"rear_caster", xr, in(0.09, 0.11), kr, tau * kr, true}};
  return c;
}

Obstacle RandomCushion(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto in = [&](double lo, double hi) { return lo + (hi - lo) * u(rng); };
  const double start = in(3.8, 4.2), h = in(0.05, 0.08), up = in(0.25, 0.35), top = in(1.2, 1.8),
               down = in(0.25, 0.35);
  Obstacle o;
  o.x_m = {0.0, start, start + up, start + up + top, start + up + top + down, 14.0};
  o.z_m = {0.0, 0.0, h, h, 0.0, 0.0};
  return o;
}

std::vector<std::string> TruthEffectNames() {
  return {"wheel_radius",       "tyre_compliance",     "cushion_compliance",
          "heave_pitch_coupling", "nonlinear_stiffness", "suspension_friction",
          "inertial_pitch",     "marker_offset",       "occupant_seat"};
}

void AddEffect(const std::string& name, double s, int form, const TruthChair& chair, TruthEffects& fx) {
  const int v = ((form % 3) + 3) % 3;
  if (name == "wheel_radius") {
    fx.contact_radius_scale = s;  // every form: the wheels' own radii scaled
  } else if (name == "tyre_compliance") {
    // 0: soft casters, stiff drive tyres; 1: every tyre soft; 2: casters only, lightly damped.
    fx.caster_tyre_hz = 7.0 / s;
    fx.drive_tyre_hz = v == 1 ? 9.0 / s : (v == 0 ? 16.0 / s : 0.0);
    fx.tyre_zeta = v == 2 ? 0.06 : 0.12;
    if (v == 2) fx.drive_tyre_hz = 0.0;
  } else if (name == "cushion_compliance") {
    // 0: per-wheel dynamic load, linear; 1: per-wheel, softening (p = 0.5); 2: whole chair.
    fx.cushion_yield = 0.15 * s;
    fx.cushion_exponent = v == 1 ? 0.5 : (v == 2 ? 1.0 : 1.0);
    fx.cushion_whole_chair = v == 2;
    if (v == 2) fx.cushion_ref_n = 1500.0;
  } else if (name == "heave_pitch_coupling") {
    fx.stiffness_asymmetry = (v == 1 ? -0.3 : 0.3) * s;
    fx.damper_asymmetry = v != 2;
  } else if (name == "nonlinear_stiffness") {
    fx.bump_gain = 0.6 * s;
    fx.bump_gap_m = v == 1 ? 0.002 : 0.004;
    fx.bump_symmetric = v == 2;
  } else if (name == "suspension_friction") {
    fx.dahl_force_n = 40.0 * s;
    fx.dahl_presliding_m = v == 1 ? 1e-3 : 4e-4;
  } else if (name == "inertial_pitch") {
    fx.chassis_cm_height_m = chair.cm_height_m * s;
    fx.load_cm_height_m = (v == 1 ? 0.7 : 0.55) * s;
  } else if (name == "marker_offset") {
    // A lever arm in the chair frame: forward (or back) and up.
    fx.marker_x_m = (v == 1 ? -0.12 : 0.12) * s;
    fx.marker_z_m = (v == 2 ? 0.7 : 0.4) * s;
  } else if (name == "occupant_seat") {
    fx.occupant_share = std::min(0.9, 0.7 * s);
    fx.seat_hz = v == 1 ? 3.5 : 4.5;
    fx.seat_zeta = v == 2 ? 0.35 : 0.2;
    fx.seat_x_m = v == 1 ? 0.05 : -0.05;
  } else {
    throw std::invalid_argument("unknown truth effect '" + name + "'");
  }
}

TruthSet SimulateTruthSet(const TruthSetConfig& config) {
  TruthSet set;
  std::mt19937_64 rng(config.seed);
  set.chair = RandomTruthChair(rng);
  set.terrain = RandomCushion(rng);
  if (config.draw_laws) {
    LawDraw draw = DrawLaws(config.seed, config.effects, set.chair, config.noise_kind);
    set.effects = draw.effects;
    set.noise = draw.noise;
    set.laws = std::move(draw.laws);
  } else {
    for (const std::string& e : config.effects) AddEffect(e, config.strength, config.form, set.chair, set.effects);
  }
  const double end_x = set.terrain.x_m[4] - set.chair.wheels.back().x_m + 1.0;
  int index = 0;
  for (double speed : config.speeds) {
    for (double load : config.loads) {
      TruthTrialConfig c;
      c.chair = set.chair;
      c.effects = set.effects;
      c.noise = set.noise;
      c.terrain = set.terrain;
      c.load_kg = load;
      c.drive.speed_mps = speed;
      c.drive.cruise_until_m = end_x;
      c.rate_hz = config.rate_hz;
      c.small_angle = config.small_angle;
      c.seed = config.seed * 1000 + static_cast<std::uint64_t>(index++);
      std::ostringstream name;
      name << "s" << speed << "_l" << load;
      set.names.push_back(name.str());
      set.trials.push_back(SimulateTruthTrial(c));
      set.configs.push_back(std::move(c));
    }
  }
  return set;
}

namespace {

std::string Num(double v) {
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

void WriteText(const std::filesystem::path& file, const std::string& text) {
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, file);
}

}  // namespace

void WriteTruthSet(const TruthSet& set, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  std::string chair = "format: pwsim-chair/1\nname: " + set.chair.name + "\nmass_kg: " +
                      Num(set.chair.mass_kg) + "\ninertia_kgm2: " + Num(set.chair.inertia_kgm2) +
                      "\ncm_height_m: " + Num(set.chair.cm_height_m) + "\nwheels:\n";
  for (const TruthWheel& w : set.chair.wheels)
    chair += "  - {name: " + w.name + ", x_m: " + Num(w.x_m) + ", radius_m: " + Num(w.radius_m) + "}\n";
  std::string terrain = "format: pwsim-terrain/1\nprofile_m: [";
  for (std::size_t k = 0; k < set.terrain.x_m.size(); ++k)
    terrain += (k ? ", [" : "[") + Num(set.terrain.x_m[k]) + ", " + Num(set.terrain.z_m[k]) + "]";
  terrain += "]\n";
  for (std::size_t r = 0; r < set.trials.size(); ++r) {
    const std::filesystem::path folder = dir / set.names[r];
    std::filesystem::create_directories(folder);
    WriteText(folder / "chair.yaml", chair);
    WriteText(folder / "terrain.yaml", terrain);
    const TruthTrial& t = set.trials[r];
    std::string csv = "# independent truth (tests/truth): O_V tracked by mocap\nt_s,x_m,z_m,pitch_rad\n";
    for (std::size_t k = 0; k < t.t.size(); ++k)
      csv += Num(t.t[k]) + "," + Num(t.x[k]) + "," + Num(t.z[k]) + "," + Num(t.pitch[k]) + "\n";
    WriteText(folder / "mocap.csv", csv);
    const TruthTrialConfig& c = set.configs[r];
    WriteText(folder / "trial.yaml",
              "format: pwsim-trial/1\nchair: chair.yaml\nterrain: terrain.yaml\nload_kg: " +
                  Num(c.load_kg) + "\nprofile:\n  speed_mps: " + Num(c.drive.speed_mps) +
                  "\n  accel_mps2: " + Num(c.drive.accel_mps2) +
                  "\nmocap:\n  file: mocap.csv\n  format: csv\n");
  }
  const TruthEffects& fx = set.effects;
  std::string truth = "# Truth of the independently simulated set " + dir.filename().string() +
                      " (tests/truth/independent_truth.h)\nwheels:\n";
  for (const TruthWheel& w : set.chair.wheels)
    truth += "  - {name: " + w.name + ", x_m: " + Num(w.x_m) + ", k_npm: " + Num(w.k_npm) +
             ", c_nspm: " + Num(w.c_nspm) + "}\n";
  truth += "effects: {contact_radius_scale: " + Num(fx.contact_radius_scale) +
           ", caster_tyre_hz: " + Num(fx.caster_tyre_hz) + ", drive_tyre_hz: " + Num(fx.drive_tyre_hz) +
           ", cushion_yield: " + Num(fx.cushion_yield) + ", cushion_exponent: " + Num(fx.cushion_exponent) +
           ", cushion_whole_chair: " + (fx.cushion_whole_chair ? "true" : "false") +
           ", stiffness_asymmetry: " + Num(fx.stiffness_asymmetry) + ", bump_gain: " + Num(fx.bump_gain) +
           ", dahl_force_n: " + Num(fx.dahl_force_n) + ", chassis_cm_height_m: " + Num(fx.chassis_cm_height_m) +
           ", load_cm_height_m: " + Num(fx.load_cm_height_m) + ", marker_x_m: " + Num(fx.marker_x_m) +
           ", marker_z_m: " + Num(fx.marker_z_m) + ", occupant_share: " + Num(fx.occupant_share) + "}\n";
  const bool small_angle = !set.configs.empty() && set.configs.front().small_angle;
  truth += std::string("kinematics: ") + (small_angle ? "small_angle" : "exact") + "\n";
  if (!set.laws.empty()) {
    truth += "laws:\n";
    for (const std::string& law : set.laws) truth += "  - \"" + law + "\"\n";
  }
  std::filesystem::path beside = dir;
  if (beside.filename().empty()) beside = beside.parent_path();
  WriteText(beside.string() + ".truth.yaml", truth);
}

}  // namespace pwsim::truth
