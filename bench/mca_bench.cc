// MCA steps per second (goal of the per-axis limiter: >= 5 million/s on one core; the limiter in
// actuator space costs more on coupled legs, docs/mca.md "Benchmark").
// BM_McaStepPw4Dof: one ClassicalWashout::Step on the 4-DoF PW platform (heave, roll, pitch and
// yaw channels, pitch and roll tilt coordination, the turntable and four legs) over the head motion of the
// speed-cushion trial, replayed in a loop. BM_McaStepCar2Dof: the same on the 2-DoF car
// platform. BM_VestibularStep: otolith and canals on three axes each (analysis path).

#include <benchmark/benchmark.h>

#include <filesystem>
#include <vector>

#include "bench/speed_cushion_inputs.h"
#include "engine/scene.h"
#include "mca/head_motion.h"
#include "mca/platform.h"
#include "mca/vestibular.h"
#include "mca/washout.h"

namespace pwsim::mca {
namespace {

void RunWashout(benchmark::State& state, const PlatformSpec& platform) {
  const std::vector<HeadMotion>& inputs = SpeedCushionHeadMotion();
  ClassicalWashout mca(DefaultWashoutParams(), platform, 1e-3);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(mca.Step(inputs[k]));
    if (++k == inputs.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_McaStepPw4Dof(benchmark::State& state) { RunWashout(state, MakePw4DofPlatform()); }
BENCHMARK(BM_McaStepPw4Dof);

void BM_McaStepCar2Dof(benchmark::State& state) { RunWashout(state, MakeCar2DofPlatform()); }
BENCHMARK(BM_McaStepCar2Dof);

void BM_VestibularStep(benchmark::State& state) {
  const std::vector<HeadMotion>& inputs = SpeedCushionHeadMotion();
  VestibularModel model(VestibularParams{}, 1e-3);
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.Step(inputs[k]));
    if (++k == inputs.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_VestibularStep);

}  // namespace
}  // namespace pwsim::mca
