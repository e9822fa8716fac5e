// Chair-model steps per second (goals: sagittal >= 30 million/s, full-DoF >= 10 million/s, one core).
// BM_LumpedStep: the exact LM propagator alone. BM_ChairStep: terrain lookup for every wheel,
// GM (1)-(2) and LM (3)-(5): one full engine tick of the chair over the speed cushion.
// On a shared machine compare two builds by interleaving them, e.g.
//   for r in 1 2 3; do for b in A/bench/chair_model_bench B/bench/chair_model_bench; do
//     nice -n 10 $b --benchmark_filter=FullChair --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//   done; done
// and count instructions, which do not depend on the load, with valgrind --tool=callgrind.

#include <benchmark/benchmark.h>

#include "engine/chair_simulator.h"
#include "engine/full_chair.h"
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

namespace pwsim {
namespace {

/// The Table I chair with its default planar layout on a floor with a cross-slope, a one-side
/// bump and the cushion profile: four features to evaluate per contact.
struct FullChairRig {
  Chair chair = MakeTableOneChair();
  PlanarLayout layout = DefaultPlanarLayout(chair);
  FloorMap floor;
  FullChairRig() {
    floor.profile = MakeSpeedCushion();
    floor.features = {PlaneFeature(8.0, 14.0, -4.0, 4.0, 0.0, 0.05, 1.0), BumpFeature(3.0, 3.4, 0.05, 2.0, 0.03, 0.1)};
  }
};

// One full-DoF tick driven by the joystick: controller, drive loops, six wheels with four
// casters (implicit swivel), constrained planar dynamics, 6 floor lookups, GM + 3-axis LM, loads.
void BM_FullChairStep(benchmark::State& state) {
  const FullChairRig rig;
  RollTorqueParams roll;  // the circuits' rigid load: Γ_φ = M d (g sin φ + a_y)
  roll.gravity_lever = MovingMass(rig.chair, 100.0) * rig.chair.cm_height;
  roll.per_lateral_accel = roll.gravity_lever;
  FullChairSimulator simulator(rig.chair, rig.layout, rig.floor, 100.0, 1e-3, {}, roll);
  simulator.Start({});
  std::int64_t k = 0;
  for (auto _ : state) {
    const double turn = (k / 4000) % 2 == 0 ? 0.4 : -0.4;  // weave every 4 s
    benchmark::DoNotOptimize(simulator.Advance({0.7, turn}));
    if (++k == 40000) {
      k = 0;
      simulator.Start({});
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FullChairStep);

// How the tick's cost grows: a gentler weave than BM_FullChairStep's on a level floor with N
// bumps (3 cm tall, tapered over 1 cm, 0.4 m deep) across the path every 1.5 m from x = 2 m (0:
// a level floor; 20 s of driving covers about 22 m), with the 6-wheel chair (arg 1 = 6) or a 4-wheel rear-drive chair (arg 1 = 4),
// and with the rolling envelope and tyres off (arg 2 = 0: point contacts).
void BM_FullChairStepScaling(benchmark::State& state) {
  const int bumps = static_cast<int>(state.range(0));
  const bool six = state.range(1) == 6;
  Chair chair = MakeTableOneChair();
  if (!six) {
    chair.name = "pw4_rear";
    chair.mass = 60.0;
    chair.inertia = 8.0;
    chair.cm_height = 0.5;
    chair.wheels = {{"front_caster", 0.30, 0.1}, {"drive", -0.15, 0.17}};
    chair.gm = GeometricParams{{0.3, 0.7}, {{0, 1, 1.0}}};
    chair.lm = LumpedParams{};
  }
  PlanarLayout layout = DefaultPlanarLayout(chair);
  layout.rolling_envelope = state.range(2) != 0;
  FloorMap floor;
  for (int k = 0; k < bumps; ++k) {
    const double x = 2.0 + 1.5 * k;
    floor.features.push_back(BumpFeature(x, x + 0.4, -30.0, 30.0, 0.03, 0.01));
  }
  RollTorqueParams roll;
  roll.gravity_lever = MovingMass(chair, 100.0) * chair.cm_height;
  roll.per_lateral_accel = roll.gravity_lever;
  FullChairSimulator simulator(chair, layout, floor, 100.0, 1e-3, {}, roll);
  simulator.Start({});
  std::int64_t k = 0;
  for (auto _ : state) {
    const double turn = (k / 4000) % 2 == 0 ? 0.2 : -0.2;
    benchmark::DoNotOptimize(simulator.Advance({0.7, turn}));
    if (++k == 20000) {
      k = 0;
      simulator.Start({});
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FullChairStepScaling)
    ->Args({0, 6, 1})->Args({4, 6, 1})->Args({16, 6, 1})->Args({0, 4, 1})->Args({16, 4, 1})
    ->Args({0, 6, 0})->Args({16, 6, 0});

// The full-DoF chair on the sagittal straight run (AdvanceAlong), for comparison.
void BM_FullChairAlongStep(benchmark::State& state) {
  const Chair chair = MakeTableOneChair();
  const FloorMap floor = FloorFromTerrain(MakeSpeedCushion());
  FullChairSimulator simulator(chair, DefaultPlanarLayout(chair), floor, 100.0, 1e-3);
  simulator.StartAlong({}, {0.0, 2.4, 0.0});
  double x = 0.0;
  for (auto _ : state) {
    x += 2.4e-3;
    if (x > 6.0) x = 0.0;
    benchmark::DoNotOptimize(simulator.AdvanceAlong({x, 2.4, 0.0}));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FullChairAlongStep);

}  // namespace
}  // namespace pwsim
