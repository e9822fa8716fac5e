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

}  // namespace

ResidualReport Analyse(const std::vector<TrialAnalysis>& trials, const Chair& chair,
                       const std::vector<effects::TrialRecord>& records) {
  ResidualReport rep;
  PooledFit fz, fp;
  std::vector<double> all_ez, all_ep, all_mz, all_mp, all_yz, all_yp, all_a, all_gz, all_gp;
  std::vector<double> all_sign_z, all_sign_p, all_dz3, all_dp3;
  double rate_hz = 100.0;
  std::size_t richest = 0;
  double richest_dev = -1.0;
  double median_speed = 0.0;
  {
    std::vector<double> speeds;
    for (const auto& t : trials) speeds.push_back(t.speed);
    std::sort(speeds.begin(), speeds.end());
    median_speed = speeds[(speeds.size() - 1) / 2];
  }
  const int bins = 25;
  const double space_bin = 0.02, time_bin = 0.01;
  Binned slow_x(bins), fast_x(bins), slow_t(bins), fast_t(bins), slow_xz(bins), fast_xz(bins);
  std::map<std::string, std::pair<double, std::vector<double>>> phase_acc;  // rms accumulators
  std::vector<double> plateau_load, plateau_ez;
  std::vector<double> slow_gain, fast_gain;
  const std::vector<double> loads_unit = effects::StaticWheelLoads(chair, 0.0);
  int drive = 0;
  for (int i = 0; i < chair.wheel_count(); ++i)
    if (chair.wheels[i].radius > chair.wheels[drive].radius) drive = i;
  // ∂θ_GM/∂Z_Oi (small-angle) and α_i decide which wheels the located residual follows:
  // sign(∂θ/∂Z_Oi) for wheels with at least 30 % of the largest lever, α_i ≥ 30 % of the largest.
  std::vector<double> pitch_lever(chair.wheel_count(), 0.0);
  std::vector<bool> heave_share(chair.wheel_count(), false);
  {
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
      if (std::abs(g[i]) >= 0.3 * gmax && gmax > 0.0) pitch_lever[i] = g[i] > 0.0 ? 1.0 : -1.0;
      heave_share[i] = chair.gm->alpha[i] >= 0.3 * amax;
    }
  }

  for (std::size_t r = 0; r < trials.size(); ++r) {
    const TrialAnalysis& t = trials[r];
    const std::size_t n = t.t.size();
    if (n > 1) rate_hz = (static_cast<double>(n) - 1.0) / (t.t.back() - t.t.front());
    std::vector<double> ez(n), ep(n);
    for (std::size_t k = 0; k < n; ++k) {
      ez[k] = t.z[k] - t.z_base[k];
      ep[k] = t.pitch[k] - t.pitch_base[k];
    }
    fz.Add(t.z, t.z_base);
    fp.Add(t.pitch, t.pitch_base);
    Append(all_ez, ez);
    Append(all_ep, ep);
    Append(all_mz, t.z_base);
    Append(all_mp, t.pitch_base);
    Append(all_yz, t.z);
    Append(all_yp, t.pitch);
    Append(all_a, t.accel);
    Append(all_gz, t.z_gm);
    Append(all_gp, t.pitch_gm);
    double dev = 0.0;
    for (double v : t.pitch_gm) dev += v * v;
    if (dev > richest_dev) {
      richest_dev = dev;
      richest = r;
    }
    // Suspension deflection and its rate in the base model (friction, hardening regressors).
    std::vector<double> dz(n), dp(n);
    for (std::size_t k = 0; k < n; ++k) {
      dz[k] = t.z_base[k] - t.z_base[0] - t.z_gm[k] + t.z_gm[0];
      dp[k] = t.pitch_base[k] - t.pitch_base[0] - t.pitch_gm[k] + t.pitch_gm[0];
    }
    const std::vector<double> dz_rate = Diff(dz, t.t), dp_rate = Diff(dp, t.t);
    for (std::size_t k = 0; k < n; ++k) {
      all_sign_z.push_back(-std::tanh(dz_rate[k] / 0.02));
      all_sign_p.push_back(-std::tanh(dp_rate[k] / 0.04));
      all_dz3.push_back(-dz[k] * dz[k] * dz[k]);
      all_dp3.push_back(-dp[k] * dp[k] * dp[k]);
    }
    // Located residual: each wheel against the nearest slope breakpoint.
    const effects::TrialRecord& rec = records[r];
    const std::vector<std::pair<double, double>> breaks = Breakpoints(rec.terrain);
    const bool slow = t.speed <= median_speed;
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
        if (std::abs(best) >= 0.5 * bins * space_bin) continue;  // flat ground or far away
        const int bx = static_cast<int>(std::floor(best / space_bin)) + bins / 2;
        // Only the wheels that move a channel much, signed by how they move it.
        if (pitch_lever[i] != 0.0) (slow ? slow_x : fast_x).Add(bx, pitch_lever[i] * sign * ep[k]);
        if (heave_share[i]) (slow ? slow_xz : fast_xz).Add(bx, sign * ez[k]);
        if (pitch_lever[i] != 0.0 && v > 0.05 && std::abs(best / v) < 0.5 * bins * time_bin) {
          const int bt = static_cast<int>(std::floor(best / v / time_bin)) + bins / 2;
          (slow ? slow_t : fast_t).Add(bt, pitch_lever[i] * sign * ep[k]);
        }
      }
      // Phases.
      const char* phase = v < 0.05 ? "still" : t.accel[k] > 0.15 ? "accelerate"
                                             : t.accel[k] < -0.15 ? "decelerate" : "cruise";
      auto& acc = phase_acc[phase];
      acc.first += 1.0;
      if (acc.second.empty()) acc.second.assign(2, 0.0);
      acc.second[0] += ez[k] * ez[k];
      acc.second[1] += ep[k] * ep[k];
    }
    // Obstacle-top heave residual (drive wheel on the top of the obstacle).
    double top = 0.0;
    for (double z : rec.terrain.z) top = std::max(top, z);
    double sum = 0.0;
    int count = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double h = rec.terrain.HeightAt(t.x[k] + chair.wheels[drive].x);
      if (top > 0.0 && h > 0.9 * top) {
        sum += ez[k];
        ++count;
      }
    }
    if (count > 5) {
      plateau_load.push_back(loads_unit[drive] / MovingMass(chair, 0.0) *
                             MovingMass(chair, t.load_kg) * 1e-3);
      plateau_ez.push_back(sum / count);
    }
    const ScaleLag g = RegressScaleLag(t.pitch, t.pitch_base, rate_hz, 0.0);
    (slow ? slow_gain : fast_gain).push_back(g.scale);
  }
  rep.fit = {fz.Percent(), fp.Percent()};
  const TrialAnalysis& rich = trials[richest];
  {
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
  }
  rep.spectrum_z = WelchSpectrum(all_ez, rate_hz);
  rep.spectrum_pitch = WelchSpectrum(all_ep, rate_hz);
  rep.high_band_z = BandFraction(rep.spectrum_z, 6.0, 1e9);
  rep.high_band_pitch = BandFraction(rep.spectrum_pitch, 6.0, 1e9);
  rep.peak_hz_pitch = PeakFrequency(rep.spectrum_pitch, 0.5);
  rep.scale_z = RegressScaleLag(all_yz, all_mz, rate_hz, 0.0);
  rep.scale_pitch = RegressScaleLag(all_yp, all_mp, rate_hz, 0.0);
  {
    // Lag alone from the richest trial (concatenated records would mix their edges).
    const ScaleLag lz = RegressScaleLag(rich.z, rich.z_base, rate_hz, 0.15);
    const ScaleLag lp = RegressScaleLag(rich.pitch, rich.pitch_base, rate_hz, 0.15);
    rep.scale_z.lag_s = lz.lag_s;
    rep.scale_pitch.lag_s = lp.lag_s;
  }
  LocatedResidual& loc = rep.located;
  for (int b = 0; b < bins; ++b) loc.distance.push_back((b - bins / 2 + 0.5) * space_bin);
  loc.slow_pitch = slow_x.Mean();
  loc.fast_pitch = fast_x.Mean();
  loc.slow_z = slow_xz.Mean();
  loc.fast_z = fast_xz.Mean();
  loc.space_lock = BinnedCorrelation(slow_x, fast_x);
  loc.time_lock = BinnedCorrelation(slow_t, fast_t);
  for (const char* name : {"still", "accelerate", "cruise", "decelerate"}) {
    auto it = phase_acc.find(name);
    PhaseRms p;
    p.phase = name;
    if (it != phase_acc.end() && it->second.first > 0) {
      p.samples = static_cast<std::size_t>(it->second.first);
      p.z = std::sqrt(it->second.second[0] / it->second.first);
      p.pitch = std::sqrt(it->second.second[1] / it->second.first);
    }
    rep.phases.push_back(p);
  }
  auto phase_rms = [&](const char* name) {
    for (const auto& p : rep.phases)
      if (p.phase == name) return p.pitch;
    return 0.0;
  };
  auto mean = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  };

  // One evidence line per effect, catalogue order.
  for (EffectId id : effects::AllEffects()) {
    std::string line;
    switch (id) {
      case EffectId::kWheelRadius:
        line = Format(
            "residual at the terrain breakpoints locked in space (slow/fast r = %.2f) vs in time "
            "(r = %.2f); measured lags model by %.0f ms (pitch)",
            loc.space_lock, loc.time_lock, 1e3 * rep.scale_pitch.lag_s);
        break;
      case EffectId::kTyreCompliance:
        line = Format(
            "residual power above 6 Hz: Z %.0f %%, pitch %.0f %% (pitch peak %.1f Hz); "
            "whiteness fails at %d/%d pitch lags",
            100 * rep.high_band_z, 100 * rep.high_band_pitch, rep.peak_hz_pitch,
            rep.whiteness_pitch.outside, static_cast<int>(rep.whiteness_pitch.lags.size()) - 1);
        break;
      case EffectId::kCushionCompliance:
        line = Format("obstacle-top Z residual vs drive-wheel load: %.2f mm/kN (r = %.2f, %d trials)",
                      1e3 * Slope(plateau_load, plateau_ez),
                      plateau_load.size() > 2 ? Correlation(plateau_load, plateau_ez) : 0.0,
                      static_cast<int>(plateau_load.size()));
        break;
      case EffectId::kHeavePitchCoupling:
        line = Format(
            "cross-channel: e_Z vs pitch_GM max |r| = %.2f, e_pitch vs Z_GM max |r| = %.2f "
            "(99 %% bounds %.2f, %.2f)",
            rep.cross_z.worst, rep.cross_pitch.worst, rep.cross_z.bound, rep.cross_pitch.bound);
        break;
      case EffectId::kNonlinearStiffness:
        line = Format(
            "measured/model pitch gain %.3f on slow vs %.3f on fast trials; e_Z vs -δ³ r = %.2f, "
            "e_pitch vs -δ³ r = %.2f",
            mean(slow_gain), mean(fast_gain), Correlation(all_ez, all_dz3),
            Correlation(all_ep, all_dp3));
        break;
      case EffectId::kSuspensionFriction:
        line = Format("residual vs -sign(suspension rate): Z r = %.2f, pitch r = %.2f",
                      Correlation(all_ez, all_sign_z), Correlation(all_ep, all_sign_p));
        break;
      case EffectId::kInertialPitch:
        line = Format(
            "pitch residual vs a_x r = %.2f; RMS pitch residual %.2f/%.2f mrad accelerating/"
            "decelerating vs %.2f cruising",
            Correlation(all_ep, all_a), 1e3 * phase_rms("accelerate"),
            1e3 * phase_rms("decelerate"), 1e3 * phase_rms("cruise"));
        break;
      case EffectId::kMarkerOffset:
        line = Format("Z residual vs model pitch: slope %.3f m (r = %.2f)", Slope(all_mp, all_ez),
                      Correlation(all_mp, all_ez));
        break;
    }
    rep.evidence.push_back(line);
  }
  return rep;
}

}  // namespace pwsim::diagnose
