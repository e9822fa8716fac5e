#include "synth/synthetic_trials.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "engine/drive_profile.h"
#include "engine/number_format.h"
#include "synth/generate.h"

namespace pwsim::effects {
namespace {

double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

Chair RandomChair(std::mt19937_64& rng, bool randomize) {
  Chair chair = MakeTableOneChair();
  if (!randomize) return chair;
  const double spread = Uniform(rng, 0.33, 0.43);
  const double caster_radius = Uniform(rng, 0.075, 0.11);
  chair.wheels[0].x = spread;
  chair.wheels[2].x = -spread;
  chair.wheels[0].radius = caster_radius;
  chair.wheels[2].radius = caster_radius;
  chair.wheels[1].radius = Uniform(rng, 0.15, 0.19);
  chair.mass = Uniform(rng, 45.0, 65.0);
  chair.inertia = Uniform(rng, 8.0, 12.0);
  chair.cm_height = Uniform(rng, 0.38, 0.48);
  chair.lm->k_z *= Uniform(rng, 0.8, 1.2);
  chair.lm->c_z *= Uniform(rng, 0.8, 1.2);
  chair.lm->k_theta *= Uniform(rng, 0.8, 1.2);
  chair.lm->c_theta *= Uniform(rng, 0.8, 1.2);
  return chair;
}

}  // namespace

SyntheticSet MakeSyntheticTrials(const SyntheticConfig& config) {
  std::mt19937_64 rng(config.seed * 0x9E3779B97F4A7C15ULL + 17);
  SyntheticSet set;
  const Chair chair = RandomChair(rng, config.randomize_chair);
  const double start = Uniform(rng, 1.5, 2.2);
  const double height = Uniform(rng, 0.045, 0.075);
  const double ramp = Uniform(rng, 0.25, 0.40);
  const double plateau = Uniform(rng, 0.8, 1.6);
  const Terrain terrain = MakeSpeedCushion(start, height, ramp, plateau, 40.0);
  const double cushion_end = start + 2.0 * ramp + plateau;
  if (config.effect) set.truth = TruthEffect(*config.effect, config.strength, chair);

  // Conditions: every (speed, load) pair once, shuffled, the first `trials` kept; then sorted
  // so names come out in a stable order.
  std::vector<std::pair<double, double>> grid;
  for (double v : config.speeds)
    for (double m : config.loads) grid.emplace_back(v, m);
  std::shuffle(grid.begin(), grid.end(), rng);
  // Every speed at least once when there is room: first occurrences go to the front.
  {
    std::vector<std::pair<double, double>> first, rest;
    for (const auto& p : grid) {
      const bool seen = std::any_of(first.begin(), first.end(),
                                    [&](const auto& q) { return q.first == p.first; });
      (seen ? rest : first).push_back(p);
    }
    first.insert(first.end(), rest.begin(), rest.end());
    grid = first;
  }
  grid.resize(std::min<std::size_t>(grid.size(), static_cast<std::size_t>(config.trials)));
  std::sort(grid.begin(), grid.end());

  std::normal_distribution<double> unit(0.0, 1.0);
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const auto [speed, load] = grid[k];
    DriveProfile drive;
    drive.accel = Uniform(rng, 0.9, 1.3);
    drive.decel = Uniform(rng, 0.9, 1.3);
    drive.speed = speed;
    drive.start_delay = 0.4;
    const double front = chair.wheels.front().x + 0.25;
    const double rear = -chair.wheels.back().x + 0.25;
    drive.start_x = start - front - speed * speed / (2.0 * drive.accel) - 0.3;
    drive.stop_x = cushion_end + rear + speed * speed / (2.0 * drive.decel) + 0.3;
    const double end_t = drive.StopTime() + 0.5;

    TrialRecord rec;
    rec.name = TrialName("", speed, load, /*cushion=*/true, /*repeat=*/1);  // one per (speed, load)
    rec.chair = chair;
    rec.terrain = terrain;
    rec.load_kg = load;
    rec.speed = speed;
    std::vector<double> t, x, a;
    const double dt = 1.0 / config.rate_hz;
    const double t0 = Uniform(rng, 0.0, dt);
    for (double time = t0; time <= end_t; time += dt) {
      const Longitudinal l = EvaluateDrive(drive, time);
      t.push_back(time);
      x.push_back(l.x);
      a.push_back(l.a);
    }
    PreparedTrial truth = PrepareTrial(chair, terrain, load, t, x, a);
    truth.step = 1e-3;
    ExtendedParams params{*chair.lm, set.truth};
    const ModelOutput out = SimulateExtended(truth, params);
    const double z_offset = Uniform(rng, 0.3, 0.6);
    const double pitch_offset = Uniform(rng, -0.01, 0.01);
    rec.t = t;
    rec.x.resize(t.size());
    rec.z.resize(t.size());
    rec.pitch.resize(t.size());
    if (config.noise_process.White()) {
      for (std::size_t i = 0; i < t.size(); ++i) {
        rec.x[i] = x[i] + config.noise_xz * unit(rng);
        rec.z[i] = out.z[i] + z_offset + config.noise_xz * unit(rng);
        rec.pitch[i] = out.pitch[i] + pitch_offset + config.noise_pitch * unit(rng);
      }
    } else {
      synth::NoiseProcess position = config.noise_process, angle = config.noise_process;
      position.sigma = config.noise_xz;
      angle.sigma = config.noise_pitch;
      const double rate = config.rate_hz;
      const std::vector<double> nx = synth::DrawNoise(position, t.size(), rate, rng);
      const std::vector<double> nz = synth::DrawNoise(position, t.size(), rate, rng);
      const std::vector<double> np = synth::DrawNoise(angle, t.size(), rate, rng);
      for (std::size_t i = 0; i < t.size(); ++i) {
        rec.x[i] = x[i] + nx[i];
        rec.z[i] = out.z[i] + z_offset + nz[i];
        rec.pitch[i] = out.pitch[i] + pitch_offset + np[i];
      }
    }
    set.trials.push_back(std::move(rec));
  }
  return set;
}

}  // namespace pwsim::effects
