#pragma once
// Synthetic measured trials following the paper's protocol (seed 000 §IV-2): a power module
// profile (accelerate on the flat floor, cruise over the speed cushion, decelerate) at speeds
// 0.6-2.4 m/s, loads 0/50/100 kg, with and without the cushion, repeats; the chair's true Z,θ
// from a TruthModel (default: the base GM+LM model); mocap noise, dropped frames, 100-250 Hz.
// Written in exactly the folder format of measured-trials.md, in either mocap format.
//
//   GenerateConfig config;                 // Table I chair, the full protocol
//   TrialSet set = GenerateTrialSet(config);
//   WriteTrialSet(set, "out/trials");      // one folder per trial; out/trials.truth-chair.yaml beside

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "sysid/measured/measured_trial.h"
#include "sysid/measured/mocap.h"
#include "synth/measurement_noise.h"
#include "synth/truth_model.h"
#include "engine/terrain.h"

namespace pwsim {

enum class MocapFormat { kCsv, kQtm6dTsv, kBoth, kAlternate };
/// "csv", "qtm-6d-tsv", "both" (both files, trial.yaml names the TSV) or "alternate".
MocapFormat ParseMocapFormat(const std::string& text);  ///< @throws std::invalid_argument

struct GenerateConfig {
  Chair truth = MakeTableOneChair();  ///< the chair that "really" drives (gm and lm set)
  std::shared_ptr<const TruthModel> truth_model;  ///< null: BaseTruthModel
  std::vector<double> speeds{0.6, 1.2, 1.8, 2.4};  ///< [m/s] programmed cruise speeds
  std::vector<double> loads{0.0, 50.0, 100.0};     ///< [kg] M_u
  bool with_cushion{true};     ///< trials over the speed cushion
  bool without_cushion{true};  ///< trials on the flat floor
  int repeats{1};
  double accel{0.8};            ///< [m/s^2] programmed acceleration and deceleration
  double speed_spread{0.01};    ///< relative random error of the reached speed [-]
  double run_in{0.3};           ///< [m] cruise before the front wheel meets the obstacle
  double run_out_time{1.0};     ///< [s] cruise after the rear wheel leaves it
  double still_time{0.5};       ///< [s] at rest before starting and after stopping
  Terrain cushion = MakeSpeedCushion();  ///< the obstacle (the paper's speed cushion)
  double rate_hz{100.0};        ///< [Hz] mocap frame rate (rate_max_hz > rate_hz: random per trial)
  double rate_max_hz{0.0};      ///< [Hz] upper end of a random rate; ≤ rate_hz: fixed rate
  double noise_position{0.3e-3};  ///< [m] std of mocap position noise (x, y, z)
  double noise_pitch{0.5e-3};     ///< [rad] std of mocap pitch noise
  /// Colour, drift and outliers of the mocap noise (measurement_noise.h; its sigma is taken from
  /// noise_position / noise_pitch). White (the default): Gaussian noise drawn frame by frame.
  synth::NoiseProcess noise_process;
  double drop_fraction{0.0};      ///< [-] share of frames where the body is not tracked
  double z_offset{0.0};           ///< [m] altitude of the tracked origin at rest on flat floor
  std::uint64_t seed{1};
  MocapFormat mocap_format{MocapFormat::kCsv};
  std::string body{"wheelchair"};
  std::string name_prefix;      ///< prepended to every trial folder name
};

/// One generated trial: as a reader would return it, plus what the files hold.
struct SyntheticTrial {
  MeasuredTrial measured;          ///< chair without gm/lm (what a lab knows), noisy track
  std::vector<MocapFrame> frames;  ///< every frame, untracked ones marked
  double speed{0.0};               ///< [m/s] programmed
  bool cushion{true};
  int repeat{1};
  double rate_hz{100.0};
  bool write_tsv{false};
  bool write_csv{true};
};

struct TrialSet {
  Chair truth;
  std::string truth_model_id;
  std::vector<SyntheticTrial> trials;

  /// The measured trials alone (copies), e.g. for IdentifyChair.
  std::vector<MeasuredTrial> Measured() const;
};

/// The name of a generated trial, the same for trial folders and in-memory sets:
/// PREFIXv<speed, 2 decimals>_m<load, kg>_<cushion|flat>_r<repeat>, e.g. "v1.20_m100_cushion_r1".
std::string TrialName(const std::string& prefix, double speed, double load, bool cushion,
                      int repeat);

/// Generates every trial of the protocol (speeds × loads × cushion × repeats) in memory.
/// Deterministic for a given config (seeded RNG per trial). @throws std::invalid_argument for
/// an inconsistent config (the message names the field).
TrialSet GenerateTrialSet(const GenerateConfig& config);

/// Writes one folder per trial under `out` (trial.yaml, chair.yaml, terrain.yaml, mocap
/// file(s)), each file atomically, and the truth BESIDE the set: `<out>.truth-chair.yaml` and
/// `<out>.truth.yaml` (truth model id, per-trial rate and untracked frames). Nothing else is
/// written at the top of `out`, so `out/*` lists trial folders only, and no trial folder holds
/// anything a lab would not have measured.
void WriteTrialSet(const TrialSet& set, const std::filesystem::path& out);

/// `<set_dir>.<suffix>`: where a generated set's truth lives (beside the set's folder).
std::filesystem::path TruthFileBeside(const std::filesystem::path& set_dir, const std::string& suffix);

}  // namespace pwsim
