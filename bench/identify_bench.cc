// identify_bench: times `IdentifyChair` on 30 generated trials (goal < 2 s) and the output-error
// stage alone, and exports that stage's exact problem (GM traces on the 1 kHz grid, measured
// outputs, inertias, the linear start) so that bench/identify_scipy.py can solve the same
// problem with scipy.optimize.least_squares. Driven by scripts/bench-identify.sh.
//
//   identify_bench [--export DIR] [--repeats N]
// (Google Benchmark flags such as --benchmark_min_time are accepted and ignored, so that
// scripts/run-benchmarks.sh can run it with the others.)

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "sysid/identify/identify.h"
#include "synth/generate.h"

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point begin) {
  return std::chrono::duration<double>(Clock::now() - begin).count();
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

void WriteDoubles(const std::filesystem::path& file, const std::vector<double>& values) {
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(double)));
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path export_dir;
  int repeats = 5;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--export" && k + 1 < argc) export_dir = argv[++k];
    else if (arg == "--repeats" && k + 1 < argc) repeats = std::max(1, std::stoi(argv[++k]));
  }

  // 30 trials: 5 speeds × 3 loads × 2 repeats over the cushion, 100 Hz, realistic noise.
  pwsim::GenerateConfig config;
  config.speeds = {0.6, 1.05, 1.5, 1.95, 2.4};
  config.loads = {0.0, 50.0, 100.0};
  config.without_cushion = false;
  config.repeats = 2;
  config.rate_hz = 100.0;
  config.seed = 30;
  const pwsim::TrialSet set = pwsim::GenerateTrialSet(config);
  const std::vector<pwsim::MeasuredTrial> trials = set.Measured();
  // Every trial is used: the slowest for the GM, all the others for the LM.
  std::vector<pwsim::TrialRole> roles;
  std::size_t samples = 0;
  for (const pwsim::MeasuredTrial& trial : trials) {
    roles.push_back(*trial.profile.speed < 0.7 ? pwsim::TrialRole::kGeometric
                                               : pwsim::TrialRole::kLumped);
    samples += trial.track.size();
  }

  const pwsim::IdentifyOptions options;
  std::vector<double> full_times;
  pwsim::IdentifyResult result;
  for (int r = 0; r < repeats; ++r) {
    const auto begin = Clock::now();
    result = pwsim::IdentifyChair(trials, roles, options);
    full_times.push_back(Seconds(begin));
  }

  // The output-error stage alone, from the linear start, with the identified GM.
  std::vector<const pwsim::MeasuredTrial*> lm_trials;
  for (std::size_t k = 0; k < trials.size(); ++k) {
    if (roles[k] == pwsim::TrialRole::kLumped) lm_trials.push_back(&trials[k]);
  }
  pwsim::Chair chair = result.chair;
  chair.lm.reset();
  const pwsim::LinearEstimate start = pwsim::EstimateLumpedLinear(lm_trials, chair, options);
  std::vector<double> oe_times;
  pwsim::LumpedFitResult oe;
  for (int r = 0; r < repeats; ++r) {
    const auto begin = Clock::now();
    oe = pwsim::IdentifyLumped(lm_trials, chair, start.lm, options);
    oe_times.push_back(Seconds(begin));
  }

  const double full = Median(full_times);
  const double oe_time = Median(oe_times);
  std::cout << "pwsim identify, " << trials.size() << " trials (" << samples
            << " mocap frames, 1 kHz internal LM step): " << full * 1e3 << " ms (median of "
            << repeats << ")\n";
  std::cout << "  K_z " << result.chair.lm->k_z << "  C_z " << result.chair.lm->c_z
            << "  K_theta " << result.chair.lm->k_theta << "  C_theta "
            << result.chair.lm->c_theta << "  (truth 41800 2240 10400 560)\n";
  std::cout << "pwsim output-error stage (Ceres LM, " << lm_trials.size() << " trials, "
            << oe.iterations << " iterations): " << oe_time * 1e3 << " ms\n";

  if (!export_dir.empty()) {
    std::filesystem::create_directories(export_dir);
    nlohmann::ordered_json meta;
    meta["format"] = "pwsim-identify-bench/1";
    meta["start"] = {start.lm.k_z, start.lm.c_z, start.lm.k_theta, start.lm.c_theta};
    meta["pwsim_result"] = {oe.lm.k_z, oe.lm.c_z, oe.lm.k_theta, oe.lm.c_theta};
    meta["pwsim_oe_seconds"] = oe_time;
    meta["pwsim_full_seconds"] = full;
    meta["offset_window_s"] = options.offset_window;
    meta["trials"] = nlohmann::ordered_json::array();
    for (std::size_t r = 0; r < lm_trials.size(); ++r) {
      const pwsim::MeasuredTrial& trial = *lm_trials[r];
      const pwsim::GeometricTrace trace = pwsim::TraceGeometricModel(
          chair, trial.terrain, trial.track.t, trial.track.x, options.simulation);
      const std::string stem = "trial" + std::to_string(r);
      WriteDoubles(export_dir / (stem + "_z_gm.bin"), trace.z_gm);
      WriteDoubles(export_dir / (stem + "_pitch_gm.bin"), trace.pitch_gm);
      WriteDoubles(export_dir / (stem + "_t.bin"), trial.track.t);
      WriteDoubles(export_dir / (stem + "_z.bin"), trial.track.z);
      WriteDoubles(export_dir / (stem + "_pitch.bin"), trial.track.pitch);
      meta["trials"].push_back({{"stem", stem},
                                {"t0", trace.t0},
                                {"dt", trace.dt},
                                {"mass", pwsim::MovingMass(chair, trial.load_kg)},
                                {"inertia", pwsim::PitchInertia(chair, trial.load_kg)}});
    }
    std::ofstream(export_dir / "problem.json") << meta.dump(1) << "\n";
    std::cout << "exported the output-error problem to " << export_dir.string() << "\n";
  }
  return 0;
}
