// diagnose_bench: the confusion matrix of the diagnosis (hidden effect × named cause) and its
// fitness gains, on seeded synthetic trial sets (synth/synthetic_trials.h), and the
// time to diagnose a set of 30 trials. Plain executable (no Google Benchmark: one run of each
// diagnosis is the measurement).
//
//   build/bench/diagnose_bench [--seeds N] [--strengths 0.7,1.5] [--trials 8] [--timing-only]
//                              [--timing-rounds R] [--timing-trials 30]
//
// Prints Markdown tables (docs/diagnosis.md quotes them).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "sysid/diagnose/diagnose.h"
#include "synth/effect_truth_model.h"
#include "synth/synthetic_trials.h"
#include "synth/generate.h"
#include "sysid/measured/measured_trial.h"
#ifdef PWSIM_HAVE_INDEPENDENT_TRUTH
#include "tests/truth/independent_truth.h"
#endif

namespace {

using pwsim::diagnose::Diagnose;
using pwsim::diagnose::Diagnosis;
using pwsim::effects::EffectId;
using pwsim::effects::EffectName;

std::vector<double> ParseList(const std::string& text) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(std::atof(item.c_str()));
  return out;
}

/// The machine's 1-minute load average (/proc/loadavg), as text; "?" where unreadable.
std::string LoadAverage() {
  std::FILE* f = std::fopen("/proc/loadavg", "r");
  double load = 0.0;
  const bool ok = f && std::fscanf(f, "%lf", &load) == 1;
  if (f) std::fclose(f);
  return ok ? std::to_string(load).substr(0, 4) : std::string("?");
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 3;
  int trials = 8;
  int timing_trials = 30;
  int timing_rounds = 1;
  std::vector<double> strengths{0.7, 1.5};
  bool timing_only = false;
  bool matrix_only = false;
  std::string only;
  std::vector<double> paper_strengths;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
    if (arg == "--seeds") seeds = std::atoi(next().c_str());
    else if (arg == "--trials") trials = std::atoi(next().c_str());
    else if (arg == "--strengths") strengths = ParseList(next());
    else if (arg == "--timing-only") timing_only = true;
    else if (arg == "--matrix-only") matrix_only = true;
    else if (arg == "--only") only = next();
    else if (arg == "--timing-trials") timing_trials = std::atoi(next().c_str());
    else if (arg == "--timing-rounds") timing_rounds = std::max(1, std::atoi(next().c_str()));
    else if (arg == "--paper-case") paper_strengths = ParseList(next());
    else if (arg.rfind("--benchmark", 0) == 0) timing_only = true;  // scripts/run-benchmarks.sh
    else {
      std::fprintf(stderr, "usage: diagnose_bench [--seeds N] [--trials N] [--strengths a,b] "
                           "[--only EFFECT|none] [--timing-only] [--timing-rounds R] [--matrix-only]\n");
      return 2;
    }
  }

  // The paper's case: caster/tyre compliance in `pwsim generate`'s protocol (Table I chair,
  // speeds 0.6-2.4 m/s, loads 0/50/100 kg, over the cushion), base model identified first.
  for (double s : paper_strengths) {
    pwsim::GenerateConfig config;
    config.without_cushion = false;
    config.seed = 2024;
    config.truth_model = pwsim::effects::MakeEffectTruthModel(EffectId::kTyreCompliance, s, config.truth);
    const pwsim::TrialSet set = pwsim::GenerateTrialSet(config);
    const auto t0 = std::chrono::steady_clock::now();
    const Diagnosis d = Diagnose(pwsim::diagnose::RecordsFromMeasured(set.Measured()));
    std::printf("paper case: tyre_compliance strength %.2f: cause %s, held-out fit base Z %.1f %% "
                "pitch %.1f %% -> extended Z %.1f %% pitch %.1f %% (%s, %.1f s)\n",
                s, d.cause.c_str(), d.base_heldout.z, d.base_heldout.pitch, d.extended_heldout.z,
                d.extended_heldout.pitch, d.split.c_str(), Seconds(t0));
  }
  if (!paper_strengths.empty()) return 0;

  std::vector<std::optional<EffectId>> hidden{std::nullopt};
  for (EffectId id : pwsim::effects::AllEffects()) hidden.emplace_back(id);
  auto name = [](const std::optional<EffectId>& id) {
    return id ? std::string(EffectName(*id)) : std::string("none");
  };

  if (!timing_only) {
    std::map<std::string, std::map<std::string, int>> matrix;
    struct Gains {
      int runs{0};
      double base_z{0}, base_p{0}, ext_z{0}, ext_p{0}, gain{0}, seconds{0};
    };
    std::map<std::string, Gains> gains;
    std::printf("| hidden | strength | seed | named | base fit Z/pitch %% | extended fit Z/pitch %% | gain | ΔBIC | s |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& h : hidden) {
      if (!only.empty() && only != name(h)) continue;
      const std::vector<double> levels = h ? strengths : std::vector<double>{0.0};
      for (double s : levels) {
        for (int seed = 1; seed <= seeds; ++seed) {
          pwsim::effects::SyntheticConfig config;
          config.seed = static_cast<std::uint64_t>(seed * 1000 + static_cast<int>(s * 10));
          config.effect = h;
          config.strength = s;
          config.trials = trials;
          const pwsim::effects::SyntheticSet set = pwsim::effects::MakeSyntheticTrials(config);
          const auto t0 = std::chrono::steady_clock::now();
          const Diagnosis d = Diagnose(set.trials);
          const double secs = Seconds(t0);
          matrix[name(h)][d.cause]++;
          Gains& g = gains[name(h)];
          ++g.runs;
          g.base_z += d.base_heldout.z;
          g.base_p += d.base_heldout.pitch;
          g.ext_z += d.extended_heldout.z;
          g.ext_p += d.extended_heldout.pitch;
          g.seconds += secs;
          for (const auto& e : d.ranking)
            if (h && e.effect == *h) g.gain += e.heldout_gain.pct / 100.0;
          const auto& top = d.ranking.front();
          std::printf("| %s | %.1f | %d | %s | %.1f / %.1f | %.1f / %.1f | %.2f (%s) | %.0f | %.1f |\n",
                      name(h).c_str(), s, seed, d.cause.c_str(), d.base_heldout.z,
                      d.base_heldout.pitch, d.extended_heldout.z, d.extended_heldout.pitch,
                      top.heldout_gain.pct / 100.0, EffectName(top.effect), top.delta_bic, secs);
          if (!matrix_only) {
            for (const auto& e : d.ranking)
              std::printf("    %-22s gain %.3f dBIC %.0f earns %d\n", EffectName(e.effect),
                          e.heldout_gain.pct / 100.0, e.delta_bic, e.earns ? 1 : 0);
          }
          std::fflush(stdout);
        }
      }
    }
    std::printf("\nConfusion matrix (rows: hidden effect, columns: named cause)\n\n| hidden \\ named |");
    for (const auto& c : hidden) std::printf(" %s |", name(c).c_str());
    std::printf("\n|---|");
    for (std::size_t c = 0; c < hidden.size(); ++c) std::printf("---|");
    std::printf("\n");
    for (const auto& r : hidden) {
      if (!only.empty() && only != name(r)) continue;
      std::printf("| %s |", name(r).c_str());
      for (const auto& c : hidden) std::printf(" %d |", matrix[name(r)][name(c)]);
      std::printf("\n");
    }
    std::printf("\nHeld-out fitness (MATLAB compare, pooled over the held-out trials), mean over runs\n\n"
                "| hidden | runs | named correctly | base Z %% | base pitch %% | extended Z %% | "
                "extended pitch %% | held-out error removed by the true effect's extension | s per diagnosis |\n"
                "|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& r : hidden) {
      if (!only.empty() && only != name(r)) continue;
      const Gains& g = gains[name(r)];
      if (g.runs == 0) continue;
      const double n = g.runs;
      std::printf("| %s | %d | %d | %.1f | %.1f | %.1f | %.1f | %s | %.1f |\n", name(r).c_str(), g.runs,
                  matrix[name(r)][name(r)], g.base_z / n, g.base_p / n, g.ext_z / n, g.ext_p / n,
                  r ? (std::to_string(static_cast<int>(std::round(100.0 * g.gain / n))) + " %").c_str() : "-",
                  g.seconds / n);
    }
  }
  if (!matrix_only) {
    pwsim::effects::SyntheticConfig config;
    config.seed = 4242;
    config.effect = EffectId::kTyreCompliance;
    config.trials = timing_trials;
    config.speeds = {0.6, 0.9, 1.2, 1.5, 1.8, 2.1, 2.4, 1.0, 2.0, 1.4};
    const auto set = pwsim::effects::MakeSyntheticTrials(config);
    // On one thread and on two, interleaved over `timing_rounds` rounds: the candidate fits and
    // the simulations inside each run concurrently (DiagnoseOptions::threads), and every
    // diagnosis must agree with the first to the bit.
    std::optional<Diagnosis> first;
    bool same = true;
    for (int round = 0; round < timing_rounds; ++round) {
      double seconds[2] = {0.0, 0.0};
      const std::string load_before = LoadAverage();
      for (int threads : {1, 2}) {
        pwsim::diagnose::DiagnoseOptions options;
        options.threads = threads;
        const auto t0 = std::chrono::steady_clock::now();
        const Diagnosis d = Diagnose(set.trials, options);
        seconds[threads - 1] = Seconds(t0);
        if (!first) first = d;
        same = same && d.selected.effect_values == first->selected.effect_values &&
               d.selected.bic == first->selected.bic && d.ranking.size() == first->ranking.size();
        for (std::size_t k = 0; same && k < d.ranking.size(); ++k)
          same = d.ranking[k].parameters == first->ranking[k].parameters;
      }
      std::printf("\nTime to diagnose %zu trials: %.2f s on 2 threads, %.2f s on 1 (ratio %.2f; results %s) "
                  "(same-model generator, cause: %s, verdict: %s; load average before %s, after %s)\n",
                  set.trials.size(), seconds[1], seconds[0], seconds[0] / seconds[1],
                  same ? "identical" : "DIFFER", first->cause.c_str(),
                  pwsim::diagnose::VerdictName(first->verdict), load_before.c_str(), LoadAverage().c_str());
      std::fflush(stdout);
    }
#ifdef PWSIM_HAVE_INDEPENDENT_TRUTH
    // The same on 30 trials of the independent truth (tests/truth/), two effects hidden, the base
    // model identified from the trials first (as `pwsim diagnose` does for a chair without gm/lm):
    // once with effects that need no second GM, once with a marker lever (the GM identified again
    // under it, alternating with the fit).
    auto independent = [&](std::vector<std::string> effects, std::uint64_t seed) {
      pwsim::truth::TruthSetConfig tc;
      tc.effects = std::move(effects);
      tc.seed = seed;
      tc.speeds = {0.5, 0.7, 0.9, 1.1, 1.3, 1.5, 1.7, 1.9, 2.1, 2.3};
      const pwsim::truth::TruthSet truth_set = pwsim::truth::SimulateTruthSet(tc);
      const std::filesystem::path dir = std::filesystem::temp_directory_path() / "pwsim_diagnose_bench_truth";
      std::filesystem::remove_all(dir);
      pwsim::truth::WriteTruthSet(truth_set, dir);
      std::vector<pwsim::MeasuredTrial> measured;
      for (const std::string& trial : truth_set.names) measured.push_back(pwsim::ReadMeasuredTrial(dir / trial));
      const auto t1 = std::chrono::steady_clock::now();
      const auto records = pwsim::diagnose::RecordsFromMeasured(measured);
      const Diagnosis di = Diagnose(records);
      std::string causes;
      for (const auto& c : di.causes) causes += std::string(causes.empty() ? "" : "+") + EffectName(c.effect);
      std::printf("Time to diagnose %zu trials: %.2f s (independent truth, GM identified first; causes: %s, verdict: %s)\n",
                  measured.size(), Seconds(t1), causes.empty() ? "none" : causes.c_str(),
                  pwsim::diagnose::VerdictName(di.verdict));
      std::filesystem::remove_all(dir);
      std::filesystem::remove(dir.string() + ".truth.yaml");
    };
    independent({"inertial_pitch", "heave_pitch_coupling"}, 4243);
    independent({"inertial_pitch", "marker_offset"}, 4244);
#endif
  }
  return 0;
}
