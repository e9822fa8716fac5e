#include "sysid/diagnose/base_residuals.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "engine/check.h"
#include "sysid/diagnose/format_text.h"
#include "sysid/identify/fitness.h"

namespace pwsim::diagnose {
namespace {

using effects::EffectId;

/// Terrain points where the slope changes (the outside of the listed span is flat at 0), with
/// the sign of the change (+1 concave up, e.g. the foot of a ramp; -1 at a crest).
std::vector<std::pair<double, double>> Breakpoints(const Terrain& terrain) {
  std::vector<std::pair<double, double>> out;
  const std::size_t n = terrain.x.size();
  for (std::size_t j = 0; j < n; ++j) {
    const double left = j == 0 ? 0.0 : (terrain.z[j] - terrain.z[j - 1]) / (terrain.x[j] - terrain.x[j - 1]);
    const double right = j + 1 == n ? 0.0 : (terrain.z[j + 1] - terrain.z[j]) / (terrain.x[j + 1] - terrain.x[j]);
    const bool jump = (j == 0 || j + 1 == n) && terrain.z[j] != 0.0;
    if (std::abs(left - right) > 1e-9 || jump) {
      const double change = jump ? (j == 0 ? terrain.z[j] : -terrain.z[j]) : right - left;
      out.emplace_back(terrain.x[j], change > 0.0 ? 1.0 : -1.0);
    }
  }
  return out;
}

struct Binned {
  std::vector<double> sum, count;
  explicit Binned(std::size_t bins) : sum(bins, 0.0), count(bins, 0.0) {}
  void Add(int bin, double v) {
    if (bin < 0 || bin >= static_cast<int>(sum.size())) return;
    sum[bin] += v;
    count[bin] += 1.0;
  }
  std::vector<double> Mean() const {
    std::vector<double> m(sum.size(), 0.0);
    for (std::size_t b = 0; b < m.size(); ++b) m[b] = count[b] > 0 ? sum[b] / count[b] : 0.0;
    return m;
  }
};

double BinnedCorrelation(const Binned& a, const Binned& b) {
  std::vector<double> x, y;
  const auto ma = a.Mean(), mb = b.Mean();
  for (std::size_t k = 0; k < ma.size(); ++k) {
    if (a.count[k] > 0 && b.count[k] > 0) {
      x.push_back(ma[k]);
      y.push_back(mb[k]);
    }
  }
  return x.size() >= 3 ? Correlation(x, y) : 0.0;
}

std::vector<double> Diff(const std::vector<double>& v, const std::vector<double>& t) {
  std::vector<double> d(v.size(), 0.0);
  for (std::size_t k = 1; k + 1 < v.size(); ++k) d[k] = (v[k + 1] - v[k - 1]) / (t[k + 1] - t[k - 1]);
  return d;
}

void Append(std::vector<double>& to, const std::vector<double>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

/// Which wheels the located residual follows: ∂θ_GM/∂Z_Oi (small-angle) signs for the wheels
/// with at least 30 % of the largest pitch lever, the wheels with α_i ≥ 30 % of the largest for
/// heave; and the drive wheel (the largest).
struct WheelRoles {
  int drive{0};
  std::vector<double> pitch_lever;  ///< +1, -1 or 0 (not followed)
  std::vector<bool> heave_share;
};

WheelRoles RolesOf(const Chair& chair) {
  WheelRoles roles;
  for (int i = 0; i < chair.wheel_count(); ++i)
    if (chair.wheels[i].radius > chair.wheels[roles.drive].radius) roles.drive = i;
  roles.pitch_lever.assign(chair.wheel_count(), 0.0);
  roles.heave_share.assign(chair.wheel_count(), false);
  std::vector<double> g(chair.wheel_count(), 0.0);
  for (const PairWeight& p : chair.gm->beta) {
    const double dx = chair.wheels[p.i].x - chair.wheels[p.j].x;
    g[p.i] += p.weight / dx;
    g[p.j] -= p.weight / dx;
  }
  double gmax = 0.0, amax = 0.0;
  for (int i = 0; i < chair.wheel_count(); ++i) {
    gmax = std::max(gmax, std::abs(g[i]));
    amax = std::max(amax, chair.gm->alpha[i]);
  }
  for (int i = 0; i < chair.wheel_count(); ++i) {
    if (std::abs(g[i]) >= 0.3 * gmax && gmax > 0.0) roles.pitch_lever[i] = g[i] > 0.0 ? 1.0 : -1.0;
    roles.heave_share[i] = chair.gm->alpha[i] >= 0.3 * amax;
  }
  return roles;
}

constexpr int kBins = 25;              ///< located residual: bins either side of a breakpoint
constexpr double kSpaceBin = 0.02;     ///< [m]
constexpr double kTimeBin = 0.01;      ///< [s]

/// What the residual analysis pools over the trials.
struct Pools {
  PooledFit fit_z, fit_pitch;
  std::vector<double> ez, ep, model_z, model_pitch, measured_z, measured_pitch, accel;
  std::vector<double> sign_z, sign_pitch, cube_z, cube_pitch;  ///< friction, hardening regressors
  double rate_hz{100.0};
  std::size_t richest{0};  ///< the trial with the most GM pitch excitation
  double richest_dev{-1.0};
  Binned slow_x{kBins}, fast_x{kBins}, slow_t{kBins}, fast_t{kBins}, slow_xz{kBins}, fast_xz{kBins};
  std::map<std::string, std::pair<double, std::vector<double>>> phase_acc;  ///< rms accumulators
  std::vector<double> plateau_load, plateau_ez;  ///< cushion: obstacle-top Z residual vs load
  std::vector<double> slow_gain, fast_gain;      ///< measured/model pitch gain
};

/// Suspension deflection and its rate in the base model: the friction (-sign of the rate) and
/// hardening (-δ³) regressors.
void AddSuspensionRegressors(const TrialAnalysis& t, Pools& pools) {
  const std::size_t n = t.t.size();
  std::vector<double> dz(n), dp(n);
  for (std::size_t k = 0; k < n; ++k) {
    dz[k] = t.z_base[k] - t.z_base[0] - t.z_gm[k] + t.z_gm[0];
    dp[k] = t.pitch_base[k] - t.pitch_base[0] - t.pitch_gm[k] + t.pitch_gm[0];
  }
  const std::vector<double> dz_rate = Diff(dz, t.t), dp_rate = Diff(dp, t.t);
  for (std::size_t k = 0; k < n; ++k) {
    pools.sign_z.push_back(-std::tanh(dz_rate[k] / 0.02));
    pools.sign_pitch.push_back(-std::tanh(dp_rate[k] / 0.04));
    pools.cube_z.push_back(-dz[k] * dz[k] * dz[k]);
    pools.cube_pitch.push_back(-dp[k] * dp[k] * dp[k]);
  }
}

/// The located residual (each wheel against the nearest slope breakpoint, slow or fast trial)
/// and the residual per drive phase.
void AddLocatedAndPhases(const TrialAnalysis& t, const effects::TrialRecord& rec, const Chair& chair,
                         const WheelRoles& roles, bool slow, const std::vector<double>& ez,
                         const std::vector<double>& ep, Pools& pools) {
  const std::size_t n = t.t.size();
  const std::vector<std::pair<double, double>> breaks = Breakpoints(rec.terrain);
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double v = (t.x[k + 1] - t.x[k - 1]) / (t.t[k + 1] - t.t[k - 1]);
    for (int i = 0; i < chair.wheel_count(); ++i) {
      const double xi = t.x[k] + chair.wheels[i].x;
      double best = 1e9, sign = 1.0;
      for (const auto& [b, s] : breaks) {
        if (std::abs(xi - b) < std::abs(best)) {
          best = xi - b;
          sign = s;
        }
      }
      if (std::abs(best) >= 0.5 * kBins * kSpaceBin) continue;  // flat ground or far away
      const int bx = static_cast<int>(std::floor(best / kSpaceBin)) + kBins / 2;
      // Only the wheels that move a channel much, signed by how they move it.
      const double lever = roles.pitch_lever[i];
      if (lever != 0.0) (slow ? pools.slow_x : pools.fast_x).Add(bx, lever * sign * ep[k]);
      if (roles.heave_share[i]) (slow ? pools.slow_xz : pools.fast_xz).Add(bx, sign * ez[k]);
      if (lever != 0.0 && v > 0.05 && std::abs(best / v) < 0.5 * kBins * kTimeBin) {
        const int bt = static_cast<int>(std::floor(best / v / kTimeBin)) + kBins / 2;
        (slow ? pools.slow_t : pools.fast_t).Add(bt, lever * sign * ep[k]);
      }
    }
    const char* phase = v < 0.05 ? "still" : t.accel[k] > 0.15 ? "accelerate"
                                           : t.accel[k] < -0.15 ? "decelerate" : "cruise";
    auto& acc = pools.phase_acc[phase];
    acc.first += 1.0;
    if (acc.second.empty()) acc.second.assign(2, 0.0);
    acc.second[0] += ez[k] * ez[k];
    acc.second[1] += ep[k] * ep[k];
  }
}

/// The mean heave residual while the drive wheel is on the obstacle's top, against its load.
void AddPlateau(const TrialAnalysis& t, const effects::TrialRecord& rec, const Chair& chair,
                int drive, const std::vector<double>& ez, Pools& pools) {
  const std::vector<double> loads_unit = effects::StaticWheelLoads(chair, 0.0);
  double top = 0.0;
  for (double z : rec.terrain.z) top = std::max(top, z);
  double sum = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < t.t.size(); ++k) {
    const double h = rec.terrain.HeightAt(t.x[k] + chair.wheels[drive].x);
    if (top > 0.0 && h > 0.9 * top) {
      sum += ez[k];
      ++count;
    }
  }
  if (count > 5) {
    pools.plateau_load.push_back(loads_unit[drive] / MovingMass(chair, 0.0) *
                                 MovingMass(chair, t.load_kg) * 1e-3);
    pools.plateau_ez.push_back(sum / count);
  }
}

/// One trial's base-model residual into the pools.
void AddTrial(std::size_t r, const TrialAnalysis& t, const effects::TrialRecord& rec,
              const Chair& chair, const WheelRoles& roles, double median_speed, Pools& pools) {
  const std::size_t n = t.t.size();
  if (n > 1) pools.rate_hz = (static_cast<double>(n) - 1.0) / (t.t.back() - t.t.front());
  std::vector<double> ez(n), ep(n);
  for (std::size_t k = 0; k < n; ++k) {
    ez[k] = t.z[k] - t.z_base[k];
    ep[k] = t.pitch[k] - t.pitch_base[k];
  }
  pools.fit_z.Add(t.z, t.z_base);
  pools.fit_pitch.Add(t.pitch, t.pitch_base);
  Append(pools.ez, ez);
  Append(pools.ep, ep);
  Append(pools.model_z, t.z_base);
  Append(pools.model_pitch, t.pitch_base);
  Append(pools.measured_z, t.z);
  Append(pools.measured_pitch, t.pitch);
  Append(pools.accel, t.accel);
  double dev = 0.0;
  for (double v : t.pitch_gm) dev += v * v;
  if (dev > pools.richest_dev) {
    pools.richest_dev = dev;
    pools.richest = r;
  }
  AddSuspensionRegressors(t, pools);
  const bool slow = t.speed <= median_speed;
  AddLocatedAndPhases(t, rec, chair, roles, slow, ez, ep, pools);
  AddPlateau(t, rec, chair, roles.drive, ez, pools);
  const ScaleLag g = RegressScaleLag(t.pitch, t.pitch_base, pools.rate_hz, 0.0);
  (slow ? pools.slow_gain : pools.fast_gain).push_back(g.scale);
}

/// Whiteness, input and cross-channel correlation tests and the lags, on the trial with the
/// most excitation (concatenated records would mix their edges).
void RichestTrialTests(const TrialAnalysis& rich, double rate_hz, ResidualReport& rep) {
  std::vector<double> ez(rich.t.size()), ep(rich.t.size());
  for (std::size_t k = 0; k < ez.size(); ++k) {
    ez[k] = rich.z[k] - rich.z_base[k];
    ep[k] = rich.pitch[k] - rich.pitch_base[k];
  }
  rep.whiteness_z = AutoCorrelationTest(ez);
  rep.whiteness_pitch = AutoCorrelationTest(ep);
  rep.input_z = CrossCorrelationTest(ez, rich.z_gm);
  rep.input_pitch = CrossCorrelationTest(ep, rich.pitch_gm);
  rep.cross_z = CrossCorrelationTest(ez, rich.pitch_gm);
  rep.cross_pitch = CrossCorrelationTest(ep, rich.z_gm);
  rep.scale_z.lag_s = RegressScaleLag(rich.z, rich.z_base, rate_hz, 0.15).lag_s;
  rep.scale_pitch.lag_s = RegressScaleLag(rich.pitch, rich.pitch_base, rate_hz, 0.15).lag_s;
}

LocatedResidual Located(const Pools& pools) {
  LocatedResidual loc;
  for (int b = 0; b < kBins; ++b) loc.distance.push_back((b - kBins / 2 + 0.5) * kSpaceBin);
  loc.slow_pitch = pools.slow_x.Mean();
  loc.fast_pitch = pools.fast_x.Mean();
  loc.slow_z = pools.slow_xz.Mean();
  loc.fast_z = pools.fast_xz.Mean();
  loc.space_lock = BinnedCorrelation(pools.slow_x, pools.fast_x);
  loc.time_lock = BinnedCorrelation(pools.slow_t, pools.fast_t);
  return loc;
}

std::vector<PhaseRms> Phases(const Pools& pools) {
  std::vector<PhaseRms> out;
  for (const char* name : {"still", "accelerate", "cruise", "decelerate"}) {
    auto it = pools.phase_acc.find(name);
    PhaseRms p;
    p.phase = name;
    if (it != pools.phase_acc.end() && it->second.first > 0) {
      p.samples = static_cast<std::size_t>(it->second.first);
      p.z = std::sqrt(it->second.second[0] / it->second.first);
      p.pitch = std::sqrt(it->second.second[1] / it->second.first);
    }
    out.push_back(p);
  }
  return out;
}

double PhasePitchRms(const std::vector<PhaseRms>& phases, const char* name) {
  for (const auto& p : phases)
    if (p.phase == name) return p.pitch;
  return 0.0;
}

double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

/// One evidence line per effect: the statistic that effect's signature moves.
std::string EvidenceLine(EffectId id, const ResidualReport& rep, const Pools& pools) {
  const LocatedResidual& loc = rep.located;
  switch (id) {
    case EffectId::kWheelRadius:
      return Format(
          "residual at the terrain breakpoints locked in space (slow/fast r = %.2f) vs in time "
          "(r = %.2f); measured lags model by %.0f ms (pitch)",
          loc.space_lock, loc.time_lock, 1e3 * rep.scale_pitch.lag_s);
    case EffectId::kTyreCompliance:
      return Format(
          "residual power above 6 Hz: Z %.0f %%, pitch %.0f %% (pitch peak %.1f Hz); "
          "whiteness fails at %d/%d pitch lags",
          100 * rep.high_band_z, 100 * rep.high_band_pitch, rep.peak_hz_pitch,
          rep.whiteness_pitch.outside, static_cast<int>(rep.whiteness_pitch.lags.size()) - 1);
    case EffectId::kCushionCompliance:
      return Format("obstacle-top Z residual vs drive-wheel load: %.2f mm/kN (r = %.2f, %d trials)",
                    1e3 * Slope(pools.plateau_load, pools.plateau_ez),
                    pools.plateau_load.size() > 2 ? Correlation(pools.plateau_load, pools.plateau_ez) : 0.0,
                    static_cast<int>(pools.plateau_load.size()));
    case EffectId::kHeavePitchCoupling:
      return Format(
          "cross-channel: e_Z vs pitch_GM max |r| = %.2f, e_pitch vs Z_GM max |r| = %.2f "
          "(99 %% bounds %.2f, %.2f)",
          rep.cross_z.worst, rep.cross_pitch.worst, rep.cross_z.bound, rep.cross_pitch.bound);
    case EffectId::kNonlinearStiffness:
      return Format(
          "measured/model pitch gain %.3f on slow vs %.3f on fast trials; e_Z vs -δ³ r = %.2f, "
          "e_pitch vs -δ³ r = %.2f",
          Mean(pools.slow_gain), Mean(pools.fast_gain), Correlation(pools.ez, pools.cube_z),
          Correlation(pools.ep, pools.cube_pitch));
    case EffectId::kSuspensionFriction:
      return Format("residual vs -sign(suspension rate): Z r = %.2f, pitch r = %.2f",
                    Correlation(pools.ez, pools.sign_z), Correlation(pools.ep, pools.sign_pitch));
    case EffectId::kInertialPitch:
      return Format(
          "pitch residual vs a_x r = %.2f; RMS pitch residual %.2f/%.2f mrad accelerating/"
          "decelerating vs %.2f cruising",
          Correlation(pools.ep, pools.accel), 1e3 * PhasePitchRms(rep.phases, "accelerate"),
          1e3 * PhasePitchRms(rep.phases, "decelerate"), 1e3 * PhasePitchRms(rep.phases, "cruise"));
    case EffectId::kMarkerOffset:
      return Format("Z residual vs model pitch: slope %.3f m (r = %.2f)", Slope(pools.model_pitch, pools.ez),
                    Correlation(pools.model_pitch, pools.ez));
  }
  return {};
}

double MedianSpeed(const std::vector<TrialAnalysis>& trials) {
  std::vector<double> speeds;
  for (const auto& t : trials) speeds.push_back(t.speed);
  std::sort(speeds.begin(), speeds.end());
  return speeds[(speeds.size() - 1) / 2];
}

}  // namespace

ResidualReport Analyse(const std::vector<TrialAnalysis>& trials, const Chair& chair,
                       const std::vector<effects::TrialRecord>& records) {
  const WheelRoles roles = RolesOf(chair);
  const double median_speed = MedianSpeed(trials);
  Pools pools;
  for (std::size_t r = 0; r < trials.size(); ++r)
    AddTrial(r, trials[r], records[r], chair, roles, median_speed, pools);
  ResidualReport rep;
  rep.fit = {pools.fit_z.Percent(), pools.fit_pitch.Percent()};
  rep.spectrum_z = WelchSpectrum(pools.ez, pools.rate_hz);
  rep.spectrum_pitch = WelchSpectrum(pools.ep, pools.rate_hz);
  rep.high_band_z = BandFraction(rep.spectrum_z, 6.0, 1e9);
  rep.high_band_pitch = BandFraction(rep.spectrum_pitch, 6.0, 1e9);
  rep.peak_hz_pitch = PeakFrequency(rep.spectrum_pitch, 0.5);
  rep.scale_z = RegressScaleLag(pools.measured_z, pools.model_z, pools.rate_hz, 0.0);
  rep.scale_pitch = RegressScaleLag(pools.measured_pitch, pools.model_pitch, pools.rate_hz, 0.0);
  RichestTrialTests(trials[pools.richest], pools.rate_hz, rep);
  rep.located = Located(pools);
  rep.phases = Phases(pools);
  for (EffectId id : effects::AllEffects()) rep.evidence.push_back(EvidenceLine(id, rep, pools));
  return rep;
}

}  // namespace pwsim::diagnose
