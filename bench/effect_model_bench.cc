// effect_model_bench: one simulation of the extended chair model (sysid/effects/effect_model.h,
// SimulateExtended) on a trial of the diagnosis' fits: the Table I chair driven at 0.6 m/s over
// the cushion (100 Hz samples, identification's 1 ms grid, input caches filled as the fits
// fill them), with the base model and with each effect family the diagnosis fits most often.
// The diagnosis' time is almost all in this function (30 trials: some 10⁴ calls).

#include <benchmark/benchmark.h>

#include "synth/synthetic_trials.h"
#include "sysid/diagnose/greybox_fit.h"

namespace {

using pwsim::effects::ExtendedParams;

const pwsim::diagnose::FitTrial& Trial() {
  static const pwsim::diagnose::FitTrial trial = [] {
    pwsim::effects::SyntheticConfig config;
    config.seed = 7;
    config.trials = 7;
    const auto set = pwsim::effects::MakeSyntheticTrials(config);
    const pwsim::effects::TrialRecord& slowest = set.trials.front();
    std::vector<pwsim::diagnose::FitTrial> one{pwsim::diagnose::MakeFitTrial(slowest, slowest.chair)};
    return pwsim::diagnose::WithFitStep(one, std::nullopt).front();
  }();
  return trial;
}

void Run(benchmark::State& state, const ExtendedParams& params) {
  const pwsim::diagnose::FitTrial& trial = Trial();
  for (auto _ : state) benchmark::DoNotOptimize(pwsim::effects::SimulateExtended(trial.prepared, params));
  state.counters["grid_steps"] = static_cast<double>(trial.prepared.x_grid.size());
}

ExtendedParams Base() {
  ExtendedParams p;
  p.lm = *Trial().prepared.chair.lm;
  return p;
}

void BM_SimulateBase(benchmark::State& state) { Run(state, Base()); }

void BM_SimulateTyres(benchmark::State& state) {
  ExtendedParams p = Base();
  p.fx.caster_tyre_period = 0.06;
  p.fx.drive_tyre_period = 0.05;
  p.fx.caster_tyre_compliance = 5e-5;
  p.fx.drive_tyre_compliance = 1e-5;
  Run(state, p);
}

void BM_SimulateStops(benchmark::State& state) {
  ExtendedParams p = Base();
  p.fx.heave_hardening = 0.3;
  p.fx.pitch_hardening = 0.3;
  p.fx.bump_gain = 1.0;
  p.fx.bump_gap = 0.004;
  p.fx.member.stops = pwsim::effects::StopSides::kBoth;
  Run(state, p);
}

void BM_SimulateFriction(benchmark::State& state) {
  ExtendedParams p = Base();
  p.fx.caster_friction = 10.0;
  p.fx.drive_friction = 40.0;
  Run(state, p);
}

BENCHMARK(BM_SimulateBase);
BENCHMARK(BM_SimulateTyres);
BENCHMARK(BM_SimulateStops);
BENCHMARK(BM_SimulateFriction);

}  // namespace
