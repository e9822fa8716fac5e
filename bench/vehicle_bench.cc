// Car-model steps per second (goal: >= 1 million/s on one core, i.e. > 1000x headroom for a
// 1 kHz session). BM_VehicleStep: one full tick of the car of assets/cars/midsize.yaml while
// cornering in third with the clutch locked (four combined-slip tyres, load transfer,
// powertrain). BM_VehicleLaunch: ticks of a launch (clutch slipping, idle control).
// BM_CombinedSlipForce: one tyre force alone.

#include <benchmark/benchmark.h>

#include <cmath>

#include "engine/vehicle/vehicle_model.h"

namespace pwsim::vehicle {
namespace {

Vehicle Car() { return ReadVehicleFile(PWSIM_SOURCE_DIR "/assets/cars/midsize.yaml"); }

void BM_VehicleStep(benchmark::State& state) {
  const Vehicle car = Car();
  VehicleState s = InitialState(car);
  s.u = 15.0;
  for (double& w : s.omega) w = 15.0 / car.tyre.radius;
  s.engine_speed = car.GearRatio(3) * car.gearbox.final_drive * s.omega[0];
  s.clutch_locked = true;
  DriverInput in;
  in.gear = 3;
  in.throttle = 0.3;
  in.steer = 0.6;
  for (auto _ : state) {
    s = StepVehicle(car, s, in, 1e-3);
    benchmark::DoNotOptimize(s);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_VehicleStep);

void BM_VehicleLaunch(benchmark::State& state) {
  const Vehicle car = Car();
  const VehicleState start = InitialState(car);
  VehicleState s = start;
  long k = 0;
  for (auto _ : state) {
    DriverInput in;
    in.gear = 1;
    in.throttle = 0.5;
    in.clutch = 0.7 * (1.0 - static_cast<double>(k) / 2000.0);
    s = StepVehicle(car, s, in, 1e-3);
    if (++k == 2000) {
      k = 0;
      s = start;
    }
    benchmark::DoNotOptimize(s);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_VehicleLaunch);

void BM_CombinedSlipForce(benchmark::State& state) {
  const TyreParams tyre = Car().tyre;
  double kappa = -0.2;
  for (auto _ : state) {
    kappa = kappa > 0.2 ? -0.2 : kappa + 1e-4;
    benchmark::DoNotOptimize(CombinedSlipForce(tyre, kappa, 0.05, 4000.0));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_CombinedSlipForce);

}  // namespace
}  // namespace pwsim::vehicle
