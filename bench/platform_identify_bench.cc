// IDIM-LS of the real EMPS recording (24 841 samples): reading DATA_EMPS.mat through libmatio,
// filtering, differentiation, decimation, least squares with σ and cond. Compare with
// bench/platform_identify_scipy.py (the same chain in scipy) via scripts/bench-platform.sh.
// Data: $PWSIM_EMPS_DIR or ../shared/data/emps beside the source tree.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "sysid/platform/axis_recording.h"
#include "sysid/platform/idim.h"

namespace {

std::filesystem::path EmpsFile() {
  if (const char* env = std::getenv("PWSIM_EMPS_DIR")) return std::filesystem::path(env) / "DATA_EMPS.mat";
  const std::filesystem::path src(PWSIM_SOURCE_DIR);
  for (const auto& c : {src / ".." / "shared" / "data" / "emps", src / ".." / ".." / "shared" / "data" / "emps"})
    if (std::filesystem::exists(c / "DATA_EMPS.mat")) return c / "DATA_EMPS.mat";
  return {};
}

void BM_EmpsReadAndIdentify(benchmark::State& state) {
  const auto file = EmpsFile();
  if (file.empty()) {
    state.SkipWithError("EMPS data absent (set PWSIM_EMPS_DIR)");
    return;
  }
  for (auto _ : state) {
    const auto r = pwsim::sysid::platform::ReadAxisRecording(file);
    const auto fit = pwsim::sysid::platform::IdentifyPlatform({r}, {}, "");
    benchmark::DoNotOptimize(fit.ls.theta.data());
  }
}
BENCHMARK(BM_EmpsReadAndIdentify)->Unit(benchmark::kMillisecond);

void BM_EmpsIdentifyOnly(benchmark::State& state) {
  const auto file = EmpsFile();
  if (file.empty()) {
    state.SkipWithError("EMPS data absent (set PWSIM_EMPS_DIR)");
    return;
  }
  const auto r = pwsim::sysid::platform::ReadAxisRecording(file);
  for (auto _ : state) {
    const auto fit = pwsim::sysid::platform::IdentifyPlatform({r}, {}, "");
    benchmark::DoNotOptimize(fit.ls.theta.data());
  }
}
BENCHMARK(BM_EmpsIdentifyOnly)->Unit(benchmark::kMillisecond);

}  // namespace
