// qp_mpc_worst_case: the worst case of the MPC's QP (mca/mpc.h, the dual active set of
// mca/qp_active_set.h) over the shipped scenes, as `pwsim run SCENE --mca mpc` drives it: the
// scene simulated (chair, full chair on a circuit, or car), the head motion at the occupant's
// head, the scene's platform and mca: settings with the MPC chosen (held input, no preview: the
// live case), stepped tick by tick.
//
//   qp_mpc_worst_case [--repeats R] [SCENE.yaml ...]     (default: every scenes/*.yaml)
//
// Per scene, one line:
//   SCENE PLATFORM solves=S fallbacks=F steps_max=I (at t=T s) steps_mean=M
//         cpu_us p50=.. p99=.. max=.. wall_us_max=..
// steps: the solver's steps per solve (QpStatus::iterations: constraints added + dropped; the
// difference of MpcStats::iterations over the tick that solved). cpu_us: thread CPU time of the
// ticks that solved (the whole MpcCueing::Step: QP set-up, solve, limiter; the washout that runs
// beside it), per solve the minimum over R repeats of the trial (default 3; the iterations
// repeat exactly, the minimum removes other processes' interference), then its p50/p99/max over
// the solves; wall_us_max: the largest wall time of one such tick in any repeat, interference
// included. A last line gives the worst over all scenes per platform.

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "engine/input_error.h"
#include "engine/scene.h"
#include "engine/vehicle/car_scene.h"
#include "engine/yaml_reader.h"
#include "mca/config.h"
#include "mca/head_motion.h"
#include "mca/mpc.h"

namespace {

namespace fs = std::filesystem;
using namespace pwsim;

double ThreadCpuMicros() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

struct Trial {
  std::string name;
  mca::McaConfig config;
  double dt{0.0};
  std::vector<mca::HeadMotion> head;
};

/// The scene's head motion and MCA configuration, as `pwsim run` builds them.
Trial LoadTrial(const fs::path& file) {
  Trial trial;
  const YamlDocument document = LoadYamlFile(file);
  if (vehicle::SceneKind(document) == "car") {
    const vehicle::CarScene scene = vehicle::ParseCarScene(document);
    trial.name = scene.name;
    trial.config = mca::LoadCarMcaConfig(scene);
    trial.dt = scene.clock.dt();
    for (const vehicle::CarSample& s : vehicle::SimulateCarScene(scene)) {
      const vehicle::CarHeadMotion m = vehicle::HeadMotionOfCar(s, scene.head_offset);
      mca::HeadMotion h;
      h.fs = m.fs;
      h.w = m.w;
      trial.head.push_back(h);
    }
  } else {
    const Scene scene = ParseScene(document);
    trial.name = scene.name;
    trial.config = mca::LoadMcaConfig(scene);
    trial.dt = scene.clock.dt();
    if (scene.is_circuit()) {  // report/run_circuit.cc: X_WV per tick, then the head's motion
      std::vector<mca::DofArray> body;
      for (const FullChairSample& s : SimulateCircuitScene(scene)) {
        body.push_back({s.planar.x, s.planar.y, s.lm.z, s.roll, s.lm.pitch, s.planar.yaw});
      }
      trial.head = mca::HeadMotionFromBodyTrack(body, scene.occupant.head_offset, trial.dt);
    } else {
      for (const ChairSample& s : SimulateScene(scene)) {
        trial.head.push_back(mca::HeadMotionFromChair(s, scene.occupant.head_offset));
      }
    }
  }
  mca::ChooseAlgorithm(mca::McaAlgorithm::kMpc, trial.config);
  return trial;
}

struct Worst {
  std::int64_t solves{0}, fallbacks{0};
  int steps_max{0};
  double steps_max_t{0.0};
  double steps_mean{0.0};
  double cpu_p50{0.0}, cpu_p99{0.0}, cpu_max{0.0}, wall_max{0.0};
};

double Quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

Worst Measure(const Trial& trial, int repeats) {
  Worst w;
  std::vector<double> cpu_min;  // per solve, the minimum over repeats
  for (int r = 0; r < repeats; ++r) {
    mca::MpcCueing mpc(trial.config.mpc, trial.config.washout, trial.config.vestibular, trial.config.platform,
                       trial.dt);
    std::size_t solve = 0;
    std::int64_t steps_sum = 0;
    for (std::size_t k = 0; k < trial.head.size(); ++k) {
      const std::int64_t solves_before = mpc.stats().solves, iterations_before = mpc.stats().iterations;
      const auto wall_start = std::chrono::steady_clock::now();
      const double cpu_start = ThreadCpuMicros();
      mpc.Step(trial.head[k]);
      const double cpu = ThreadCpuMicros() - cpu_start;
      const double wall = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - wall_start).count();
      if (mpc.stats().solves == solves_before) continue;
      const int steps = static_cast<int>(mpc.stats().iterations - iterations_before);
      steps_sum += steps;
      if (r == 0) {
        cpu_min.push_back(cpu);
        if (steps > w.steps_max) {
          w.steps_max = steps;
          w.steps_max_t = static_cast<double>(k) * trial.dt;
        }
      } else {
        cpu_min[solve] = std::min(cpu_min[solve], cpu);
      }
      w.wall_max = std::max(w.wall_max, wall);
      ++solve;
    }
    w.solves = mpc.stats().solves;
    w.fallbacks = mpc.stats().fallbacks;
    w.steps_mean = w.solves > 0 ? static_cast<double>(steps_sum) / static_cast<double>(w.solves) : 0.0;
  }
  if (!cpu_min.empty()) {
    w.cpu_p50 = Quantile(cpu_min, 0.5);
    w.cpu_p99 = Quantile(cpu_min, 0.99);
    w.cpu_max = *std::max_element(cpu_min.begin(), cpu_min.end());
  }
  return w;
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 3;
  std::vector<fs::path> scenes;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--repeats" && k + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++k]));
    } else if (!arg.empty() && arg[0] != '-') {
      scenes.emplace_back(arg);
    } else {
      std::cerr << "usage: qp_mpc_worst_case [--repeats R] [SCENE.yaml ...]\n";
      return 2;
    }
  }
  if (scenes.empty()) {
    for (const auto& entry : fs::directory_iterator(fs::path(PWSIM_SOURCE_DIR) / "scenes")) {
      if (entry.is_regular_file() && entry.path().extension() == ".yaml") scenes.push_back(entry.path());
    }
    std::sort(scenes.begin(), scenes.end());
  }
  std::printf("# qp_mpc_worst_case: the MPC (held input) on %zu scenes, %d repeats; steps = QP steps per solve,"
              " cpu_us = thread CPU time of a solving tick (min over repeats)\n",
              scenes.size(), repeats);
  std::map<std::string, Worst> per_platform;
  for (const fs::path& file : scenes) {
    Trial trial;
    try {
      trial = LoadTrial(file);
    } catch (const std::exception& e) {  // InputError, or the MPC cannot start on this platform
      std::printf("%s skipped: %s\n", file.filename().string().c_str(), e.what());
      continue;
    }
    const Worst w = Measure(trial, repeats);
    const std::string platform = trial.config.platform.name;
    std::printf("%s %s ticks=%zu solves=%lld fallbacks=%lld steps_max=%d (at t=%.2f s) steps_mean=%.2f "
                "cpu_us p50=%.1f p99=%.1f max=%.1f wall_us_max=%.1f\n",
                file.filename().string().c_str(), platform.c_str(), trial.head.size(),
                static_cast<long long>(w.solves), static_cast<long long>(w.fallbacks), w.steps_max, w.steps_max_t,
                w.steps_mean, w.cpu_p50, w.cpu_p99, w.cpu_max, w.wall_max);
    Worst& all = per_platform[platform];
    all.solves += w.solves;
    all.fallbacks += w.fallbacks;
    all.steps_max = std::max(all.steps_max, w.steps_max);
    all.cpu_p99 = std::max(all.cpu_p99, w.cpu_p99);
    all.cpu_max = std::max(all.cpu_max, w.cpu_max);
    all.wall_max = std::max(all.wall_max, w.wall_max);
    std::fflush(stdout);
  }
  for (const auto& [platform, w] : per_platform) {
    std::printf("worst %s solves=%lld fallbacks=%lld steps_max=%d cpu_us p99_max=%.1f max=%.1f wall_us_max=%.1f\n",
                platform.c_str(), static_cast<long long>(w.solves), static_cast<long long>(w.fallbacks), w.steps_max,
                w.cpu_p99, w.cpu_max, w.wall_max);
  }
  return 0;
}
