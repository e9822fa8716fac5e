// Throughput of the hardware wire codecs and of the per-cycle safety work.
// Run: build/bench/can_codec_bench; figures are quoted in docs/hardware.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "hardware/candump_log.h"
#include "hardware/canopen.h"
#include "hardware/cia402_master.h"
#include "hardware/hmd_protocol.h"
#include "hardware/safety_supervisor.h"

namespace pwsim::hw {
namespace {

std::vector<CanFrame> CycleFrames() {
  return {canopen::EncodeCspCommand(1, {0x0F, 123456}), canopen::EncodeCspCommand(2, {0x0F, -654321}),
          canopen::EncodeSync(17), canopen::EncodeCspStatus(1, {0x0237, 123400}),
          canopen::EncodeCspStatus(2, {0x0237, -654300}), canopen::EncodeCspFeedback(1, {1000, 12}),
          canopen::EncodeCspFeedback(2, {-2000, -40}), canopen::EncodeHeartbeat(0x7F, canopen::NmtState::kOperational)};
}

void BM_CannelloniEncode(benchmark::State& state) {
  const auto frames = CycleFrames();
  std::vector<std::uint8_t> out(256);
  const auto n = static_cast<std::size_t>(state.range(0));
  std::uint8_t seq = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(EncodeCannelloni(seq++, std::span<const CanFrame>(frames.data(), n), out));
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_CannelloniEncode)->Arg(1)->Arg(8);

void BM_CannelloniDecode(benchmark::State& state) {
  const auto frames = CycleFrames();
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<std::uint8_t> bytes(256);
  bytes.resize(EncodeCannelloni(3, std::span<const CanFrame>(frames.data(), n), bytes));
  std::vector<CanFrame> decoded;
  decoded.reserve(16);
  std::uint8_t seq = 0;
  for (auto _ : state) {
    decoded.clear();
    benchmark::DoNotOptimize(DecodeCannelloni(bytes, &seq, &decoded));
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_CannelloniDecode)->Arg(1)->Arg(8);

void BM_RawFrameRoundTrip(benchmark::State& state) {
  const CanFrame f = canopen::EncodeCspCommand(1, {0x0F, 123456});
  std::array<std::uint8_t, kRawFrameSize> raw{};
  CanFrame back;
  for (auto _ : state) {
    EncodeRawFrame(f, raw);
    benchmark::DoNotOptimize(DecodeRawFrame(raw, &back));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RawFrameRoundTrip);

void BM_CandumpLineFormat(benchmark::State& state) {
  CandumpRecord r{1700000000123456, "can0", canopen::EncodeCspCommand(1, {0x0F, 123456})};
  for (auto _ : state) benchmark::DoNotOptimize(FormatCandumpLine(r));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_CandumpLineFormat);

void BM_CandumpLineParse(benchmark::State& state) {
  const std::string line = "(1700000000.123456) can0 201#0F0040E20100";
  CandumpRecord r;
  for (auto _ : state) benchmark::DoNotOptimize(ParseCandumpLine(line, &r));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_CandumpLineParse);

void BM_CanopenClassifyDecode(benchmark::State& state) {
  const auto frames = CycleFrames();
  std::size_t i = 0;
  for (auto _ : state) {
    const CanFrame& f = frames[i++ % frames.size()];
    std::uint8_t node = 0;
    canopen::CspStatus s;
    benchmark::DoNotOptimize(canopen::Classify(f, &node));
    benchmark::DoNotOptimize(canopen::DecodeCspStatus(f, &node, &s));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_CanopenClassifyDecode);

void BM_HmdCameraPoseEncodeDecode(benchmark::State& state) {
  HmdMessage m;
  m.header.type = HmdType::kCameraPose;
  m.body = CameraPoseMsg{100, 10, Pose{{1, 2, 3}, {0, 0, 0, 1}}, {0.1, 0.2}};
  std::array<std::uint8_t, kHmdMaxSize> out{};
  HmdMessage back;
  for (auto _ : state) {
    const std::size_t n = EncodeHmd(m, out);
    benchmark::DoNotOptimize(DecodeHmd(std::span<const std::uint8_t>(out.data(), n), &back));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_HmdCameraPoseEncodeDecode);

void BM_SafetySupervisorCycle(benchmark::State& state) {
  SafetySupervisor sup;
  SafetyInputs in;
  in.drives_ready = true;
  std::int64_t cycle = 0;
  for (auto _ : state) {
    const double t = static_cast<double>(cycle) * 0.004;
    in.setpoint = AxisValues{0.2 * std::sin(0.8 * t), 0.3 * std::sin(1.3 * t)};
    benchmark::DoNotOptimize(sup.Step(cycle++, in));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SafetySupervisorCycle);

void BM_MasterCycle(benchmark::State& state) {
  Cia402Master master;
  std::vector<CanFrame> out;
  out.reserve(16);
  std::int64_t cycle = 0;
  for (auto _ : state) {
    out.clear();
    master.Cycle(cycle++, AxisValues{0.1, 0.2}, &out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MasterCycle);

}  // namespace
}  // namespace pwsim::hw
