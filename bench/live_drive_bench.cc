// The in-process part of the joystick -> platform / HMD latency of a live drive (docs/hardware.md,
// "Joystick latency"): CPU time of reading the joystick and computing what the next drive cycle
// and frame send. Run: build/bench/live_drive_bench. The whole path (with the links and the
// step schedule) is measured by `pwsim drive --can ...` into report.json.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <optional>

#include "hardware/car_drive_source.h"
#include "hardware/chair_drive_source.h"
#include "hardware/input_latency.h"
#include "hardware/rnet_joystick.h"
#include "hardware/session_streams.h"
#include "hardware/udp_socket.h"

namespace pwsim::hw {
namespace {

const std::filesystem::path kSource = PWSIM_SOURCE_DIR;

// One R-Net frame: classify, take, sample with the watchdog.
void BM_RnetFrameToSample(benchmark::State& state) {
  const RnetJoystickParams params{-1, 100};
  RnetJoystickState s;
  const CanFrame f = EncodeRnetJoystick(0, 30, 60);
  std::int64_t tick = 0;
  for (auto _ : state) {
    RnetOnFrame(params, &s, f, tick, tick);
    benchmark::DoNotOptimize(RnetSample(params, &s, tick));
    ++tick;
  }
}
BENCHMARK(BM_RnetFrameToSample);

// One drive cycle of the car's live drive (4 engine ticks at 1 kHz): poll the joystick (the
// shipped R-Net log), step the car and the MCA four times, hand the setpoint and the eye pose.
void BM_CarDriveCycle(benchmark::State& state) {
  const vehicle::CarScene scene = vehicle::LoadCarScene(kSource / "scenes/car_launch.yaml");
  const std::vector<CandumpRecord> records = ReadCandumpFile(kSource / "assets/rnet/joystick_synthetic.log");
  RnetLogJoystick joystick(records, scene.clock.rate_hz, {-1, 100}, "log");
  const mca::McaConfig mca = mca::LoadCarMcaConfig(scene);
  std::optional<CarDriveSource> source(std::in_place, scene, mca, joystick);
  SessionInputs in;
  std::int64_t tick = 0;
  for (auto _ : state) {
    tick += 4;
    if (tick > 3000) {  // keep the car on the log's drive (restart off the clock)
      state.PauseTiming();
      joystick = RnetLogJoystick(records, scene.clock.rate_hz, {-1, 100}, "log");
      source.emplace(scene, mca, joystick);
      tick = 4;
      state.ResumeTiming();
    }
    source->Fill(tick, true, tick % 10 == 0, tick * 1'000'000, &in);
    benchmark::DoNotOptimize(in.setpoint);
  }
}
BENCHMARK(BM_CarDriveCycle);

// One drive cycle of the chair's live drive through circuit_course (4 engine ticks at 1 kHz):
// poll the joystick (the shipped R-Net log), step the full-DoF chair through the circuit and both
// washouts four times, hand the setpoint and the head pose.
void BM_ChairDriveCycle(benchmark::State& state) {
  const Scene scene = LoadScene(kSource / "scenes/circuit_course.yaml");
  const std::vector<CandumpRecord> records = ReadCandumpFile(kSource / "assets/rnet/joystick_synthetic.log");
  RnetLogJoystick joystick(records, scene.clock.rate_hz, {-1, 100}, "log");
  const mca::McaConfig mca = SessionMcaConfig(scene, std::nullopt, nullptr);  // the scene's own cueing on pw4dof
  std::optional<ChairDriveSource> source(std::in_place, scene, joystick, 3000, mca);
  SessionInputs in;
  std::int64_t tick = 0;
  for (auto _ : state) {
    tick += 4;
    if (tick > 3000) {  // keep the chair on the log's drive (restart off the clock)
      state.PauseTiming();
      joystick = RnetLogJoystick(records, scene.clock.rate_hz, {-1, 100}, "log");
      source.emplace(scene, joystick, 3000, mca);
      tick = 4;
      state.ResumeTiming();
    }
    source->Fill(tick, true, tick % 10 == 0, tick * 1'000'000, &in);
    benchmark::DoNotOptimize(in.setpoint);
  }
}
BENCHMARK(BM_ChairDriveCycle);

// Recording one latency sample (the runner does this after each send).
void BM_InputLatencyRecord(benchmark::State& state) {
  InputLatency latency(1U << 22);
  std::uint64_t seq = 0;
  for (auto _ : state) {
    ++seq;
    latency.OnOutput({seq, 1000}, 2000);
    if (seq == (1U << 22)) {
      state.PauseTiming();
      latency = InputLatency(1U << 22);
      seq = 0;
      state.ResumeTiming();
    }
  }
}
BENCHMARK(BM_InputLatencyRecord);

}  // namespace
}  // namespace pwsim::hw
