// Chair-model steps per second (goal: >= 10 million/s on one core of the CI machine).
// BM_LumpedStep: the exact LM propagator alone. BM_ChairStep: terrain lookup for every wheel,
// GM (1)-(2) and LM (3)-(5): one full engine tick of the chair over the speed cushion.

#include <benchmark/benchmark.h>

#include "engine/chair_simulator.h"
#include "engine/lumped_model.h"

namespace pwsim {
namespace {

void BM_LumpedStep(benchmark::State& state) {
  const Chair chair = MakeTableOneChair();
  const DiscreteLumpedModel model = Discretize(MakeLumpedModelParams(chair, 100.0), 1e-3);
  LumpedState lm;
  double u = 0.0;
  for (auto _ : state) {
    const double next_u = u + 1e-5;
    lm = Step(model, lm, {u, next_u, 0.5 * u, 0.5 * next_u, 0.0});
    u = next_u > 0.065 ? 0.0 : next_u;
    benchmark::DoNotOptimize(lm);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LumpedStep);

void BM_ChairStep(benchmark::State& state) {
  const Chair chair = MakeTableOneChair();
  const Terrain terrain = MakeSpeedCushion();
  ChairSimulator simulator(chair, terrain, 100.0, 1e-3);
  simulator.Start({0.0, 2.4, 0.0});
  double x = 0.0;
  for (auto _ : state) {
    x += 2.4e-3;
    if (x > 6.0) x = 0.0;
    benchmark::DoNotOptimize(simulator.Advance({x, 2.4, 0.0}));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ChairStep);

}  // namespace
}  // namespace pwsim
