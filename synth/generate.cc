#include "synth/generate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "engine/atomic_file.h"
#include "engine/drive_profile.h"
#include "engine/number_format.h"

namespace pwsim {

MocapFormat ParseMocapFormat(const std::string& text) {
  if (text == "csv") return MocapFormat::kCsv;
  if (text == "qtm-6d-tsv") return MocapFormat::kQtm6dTsv;
  if (text == "both") return MocapFormat::kBoth;
  if (text == "alternate") return MocapFormat::kAlternate;
  throw std::invalid_argument("mocap format: expected csv, qtm-6d-tsv, both or alternate, got \"" +
                              text + "\"");
}

std::vector<MeasuredTrial> TrialSet::Measured() const {
  std::vector<MeasuredTrial> out;
  out.reserve(trials.size());
  for (const SyntheticTrial& trial : trials) out.push_back(trial.measured);
  return out;
}

namespace {

void Require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument("generate: " + message);
}

/// A per-trial seed that does not depend on the order of generation.
std::uint64_t TrialSeed(std::uint64_t seed, std::size_t index) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (index + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

Chair LabChair(const Chair& truth) {
  Chair chair = truth;
  chair.gm.reset();
  chair.lm.reset();
  return chair;
}

std::string Fixed2(double value) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(2);
  out << value;
  return out.str();
}

}  // namespace

std::string TrialName(const std::string& prefix, double speed, double load, bool cushion,
                      int repeat) {
  return prefix + "v" + Fixed2(speed) + "_m" +
         std::to_string(static_cast<long long>(std::lround(load))) + "_" +
         (cushion ? "cushion" : "flat") + "_r" + std::to_string(repeat);
}

TrialSet GenerateTrialSet(const GenerateConfig& config) {
  Require(config.truth.gm.has_value() && config.truth.lm.has_value(),
          "the truth chair needs gm and lm");
  Require(!config.speeds.empty() && !config.loads.empty(), "speeds and loads must not be empty");
  for (double speed : config.speeds) Require(speed > 0.0 && speed <= 4.0, "speeds in (0, 4] m/s");
  for (double load : config.loads) Require(load >= 0.0 && load <= 300.0, "loads in [0, 300] kg");
  Require(config.with_cushion || config.without_cushion, "with and/or without cushion");
  Require(config.repeats >= 1, "repeats >= 1");
  Require(config.rate_hz >= 10.0 && config.rate_hz <= 2000.0, "rate in [10, 2000] Hz");
  Require(config.noise_position >= 0.0 && config.noise_pitch >= 0.0, "noise >= 0");
  Require(config.drop_fraction >= 0.0 && config.drop_fraction < 0.5, "drop fraction in [0, 0.5)");
  Require(config.accel > 0.0, "accel > 0");

  const std::shared_ptr<const TruthModel> truth_model =
      config.truth_model ? config.truth_model : std::make_shared<BaseTruthModel>();
  TrialSet set;
  set.truth = config.truth;
  set.truth_model_id = truth_model->Id();
  const Terrain flat{{-20.0, 40.0}, {0.0, 0.0}};
  // Extent of the obstacle and of the wheelbase.
  const Terrain& bump = config.cushion;
  Require(bump.x.size() >= 2 && bump.MaxHeight() > 0.0, "the cushion terrain must rise");
  double obstacle_begin = bump.x.back();
  double obstacle_end = bump.x.front();
  for (std::size_t k = 0; k + 1 < bump.x.size(); ++k) {
    if (bump.z[k] != 0.0 || bump.z[k + 1] != 0.0) {
      obstacle_begin = std::min(obstacle_begin, bump.x[k]);
      obstacle_end = std::max(obstacle_end, bump.x[k + 1]);
    }
  }
  const double front_x = config.truth.wheels.front().x;
  const double rear_x = config.truth.wheels.back().x;
  const Chair lab_chair = LabChair(config.truth);

  std::size_t index = 0;
  for (double speed : config.speeds) {
    for (double load : config.loads) {
      for (int with = 1; with >= 0; --with) {
        const bool cushion = with == 1;
        if (cushion ? !config.with_cushion : !config.without_cushion) continue;
        for (int repeat = 1; repeat <= config.repeats; ++repeat, ++index) {
          std::mt19937_64 rng(TrialSeed(config.seed, index));
          std::normal_distribution<double> gauss(0.0, 1.0);
          std::uniform_real_distribution<double> uniform(0.0, 1.0);

          SyntheticTrial trial;
          trial.speed = speed;
          trial.cushion = cushion;
          trial.repeat = repeat;
          trial.rate_hz = config.rate_max_hz > config.rate_hz
                              ? std::round(config.rate_hz +
                                           uniform(rng) * (config.rate_max_hz - config.rate_hz))
                              : config.rate_hz;
          switch (config.mocap_format) {
            case MocapFormat::kCsv: trial.write_csv = true; trial.write_tsv = false; break;
            case MocapFormat::kQtm6dTsv: trial.write_csv = false; trial.write_tsv = true; break;
            case MocapFormat::kBoth: trial.write_csv = true; trial.write_tsv = true; break;
            case MocapFormat::kAlternate:
              trial.write_tsv = index % 2 == 1;
              trial.write_csv = !trial.write_tsv;
              break;
          }

          // Cruise over the whole obstacle (the paper's protocol): start far enough back to
          // reach the speed before the front wheel meets it, stop after the rear wheel left.
          DriveProfile drive;
          drive.start_delay = config.still_time;
          drive.speed = speed * (1.0 + config.speed_spread * gauss(rng));
          drive.accel = config.accel;
          drive.decel = config.accel;
          const double ramp = drive.speed * drive.speed / (2.0 * config.accel);
          drive.start_x = obstacle_begin - front_x - config.run_in - ramp;
          drive.stop_x = obstacle_end - rear_x + drive.speed * config.run_out_time + ramp;
          const std::string problem = drive.Validate();
          Require(problem.empty(), "drive profile at " + Fixed2(speed) + " m/s: " + problem);
          const double duration = drive.StopTime() + config.still_time;
          const std::size_t frames =
              static_cast<std::size_t>(std::floor(duration * trial.rate_hz)) + 1;

          std::vector<double> t(frames), x(frames), v(frames), a(frames);
          for (std::size_t k = 0; k < frames; ++k) {
            t[k] = static_cast<double>(k) / trial.rate_hz;
            const Longitudinal state = EvaluateDrive(drive, t[k]);
            x[k] = state.x;
            v[k] = state.v;
            a[k] = state.a;
          }
          const Terrain& terrain = cushion ? config.cushion : flat;
          const TruthModelOutput truth = truth_model->Evaluate(
              TruthModelInput{config.truth, terrain, load, t, x, v, a});
          Require(truth.z.size() == frames && truth.pitch.size() == frames,
                  "truth model '" + truth_model->Id() + "' returned the wrong number of samples");

          const double lateral_phase = 6.283185307179586 * uniform(rng);
          MeasuredTrial& measured = trial.measured;
          measured.name = TrialName(config.name_prefix, speed, load, cushion, repeat);
          measured.chair = lab_chair;
          measured.terrain = terrain;
          measured.load_kg = load;
          measured.profile.speed = speed;
          measured.profile.accel = config.accel;
          measured.mocap_format = trial.write_tsv ? "qtm-6d-tsv" : "csv";
          measured.mocap_body = trial.write_tsv ? config.body : "";
          trial.frames.resize(frames);
          // Coloured / drifting / outlier noise drawn per channel beforehand; white noise frame
          // by frame (the draws of the white default unchanged).
          const bool white = config.noise_process.White();
          std::array<std::vector<double>, 4> coloured;  // x, y, z, pitch
          if (!white) {
            synth::NoiseProcess position = config.noise_process, angle = config.noise_process;
            position.sigma = config.noise_position;
            angle.sigma = config.noise_pitch;
            for (std::size_t c = 0; c < 4; ++c)
              coloured[c] = synth::DrawNoise(c < 3 ? position : angle, frames, trial.rate_hz, rng);
          }
          auto noise = [&](std::size_t channel, std::size_t k, double sigma) {
            return white ? sigma * gauss(rng) : coloured[channel][k];
          };
          for (std::size_t k = 0; k < frames; ++k) {
            MocapFrame& f = trial.frames[k];
            f.t = t[k];
            f.x = x[k] + noise(0, k, config.noise_position);
            f.y = 0.004 * std::sin(0.4 * t[k] + lateral_phase) + noise(1, k, config.noise_position);
            f.z = truth.z[k] + config.z_offset + noise(2, k, config.noise_position);
            f.pitch = truth.pitch[k] + noise(3, k, config.noise_pitch);
            const bool edge = k == 0 || k + 1 == frames;
            f.tracked = edge || !(uniform(rng) < config.drop_fraction);
            if (!f.tracked) {
              ++measured.track.untracked_frames;
              continue;
            }
            measured.track.t.push_back(f.t);
            measured.track.x.push_back(f.x);
            measured.track.y.push_back(f.y);
            measured.track.z.push_back(f.z);
            measured.track.pitch.push_back(f.pitch);
          }
          set.trials.push_back(std::move(trial));
        }
      }
    }
  }
  return set;
}

void WriteTrialSet(const TrialSet& set, const std::filesystem::path& out) {
  for (const SyntheticTrial& trial : set.trials) {
    const MeasuredTrial& m = trial.measured;
    const std::filesystem::path folder = out / m.name;
    std::filesystem::create_directories(folder);
    std::string yaml = "format: pwsim-trial/1\n";
    yaml += "chair: chair.yaml\n";
    yaml += "terrain: terrain.yaml\n";
    yaml += "load_kg: " + FormatDouble(m.load_kg) + "\n";
    yaml += "profile:\n";
    yaml += "  speed_mps: " + FormatDouble(trial.speed) + "\n";
    yaml += "  accel_mps2: " + FormatDouble(m.profile.accel.value_or(0.8)) + "\n";
    yaml += "mocap:\n";
    if (trial.write_tsv) {
      yaml += "  file: mocap.tsv\n  format: qtm-6d-tsv\n  body: " + m.mocap_body + "\n";
    } else {
      yaml += "  file: mocap.csv\n  format: csv\n";
    }
    WriteFileAtomically(folder / "chair.yaml", ChairToYaml(m.chair));
    WriteTerrainFile(m.terrain, folder / "terrain.yaml");
    if (trial.write_csv) WriteMocapCsv(trial.frames, folder / "mocap.csv");
    if (trial.write_tsv) {
      WriteQtm6dTsv(trial.frames, m.mocap_body.empty() ? "wheelchair" : m.mocap_body,
                    trial.rate_hz, folder / "mocap.tsv");
    }
    // trial.yaml last: a folder without it is not a trial, so a crash never leaves a trial
    // that looks complete.
    WriteFileAtomically(folder / "trial.yaml", yaml);
  }
  // The truth sits beside the set, never inside a trial folder (measured-trials.md): trial
  // folders hold only what a lab would have measured.
  WriteFileAtomically(TruthFileBeside(out, "truth-chair.yaml"), ChairToYaml(set.truth));
  std::string truth_yaml = "# Generated by pwsim generate: what produced the synthetic trials of " +
                           out.filename().string() + ".\n";
  truth_yaml += "truth_model: " + set.truth_model_id + "\n";
  truth_yaml += "trials:\n";
  for (const SyntheticTrial& trial : set.trials) {
    truth_yaml += "  " + trial.measured.name + ": {rate_hz: " + FormatDouble(trial.rate_hz) +
                  ", untracked_frames: " + std::to_string(trial.measured.track.untracked_frames) + "}\n";
  }
  WriteFileAtomically(TruthFileBeside(out, "truth.yaml"), truth_yaml);
}

std::filesystem::path TruthFileBeside(const std::filesystem::path& set_dir, const std::string& suffix) {
  std::filesystem::path dir = set_dir;
  if (dir.filename().empty()) dir = dir.parent_path();
  return dir.string() + "." + suffix;
}

}  // namespace pwsim
