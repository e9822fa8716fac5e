#pragma once
// In-memory synthetic "measured" trial sets with an optional hidden effect, for the diagnosis
// tests and the confusion-matrix benchmark: seeded random chair, speed cushion, speeds, loads
// and mocap noise; the paper's protocol (accelerate on the flat, cruise over the cushion,
// decelerate). The truth is the extended model (effect_model.h) driven by the exact drive
// profile with 1 ms steps; the "measurements" are sampled at `rate_hz` with Gaussian noise.

#include <cstdint>
#include <optional>
#include <vector>

#include "sysid/effects/effect_catalog.h"
#include "sysid/effects/effect_model.h"
#include "synth/measurement_noise.h"

namespace pwsim::effects {

struct SyntheticConfig {
  std::uint64_t seed{1};
  std::optional<EffectId> effect;  ///< hidden effect (none when empty)
  double strength{1.0};            ///< 1 = moderate (TruthEffect)
  int trials{8};                   ///< drawn without repeats from speeds × loads
  std::vector<double> speeds{0.6, 1.2, 1.8, 2.4};  ///< [m/s]
  std::vector<double> loads{0.0, 50.0, 100.0};     ///< [kg]
  double rate_hz{100.0};
  double noise_xz{3e-4};     ///< [m] position noise (x and z), 1σ
  double noise_pitch{6e-4};  ///< [rad], 1σ
  bool randomize_chair{true};  ///< perturb Table I chair (geometry, masses, K, C)
  /// The noise's colour, drift and outliers (measurement_noise.h; sigma taken from noise_xz /
  /// noise_pitch). White (the default): Gaussian noise drawn as before.
  synth::NoiseProcess noise_process;
};

struct SyntheticSet {
  std::vector<TrialRecord> trials;  ///< chair carries the truth gm and lm
  EffectParams truth;               ///< the hidden effect's parameters
};

SyntheticSet MakeSyntheticTrials(const SyntheticConfig& config);

}  // namespace pwsim::effects
