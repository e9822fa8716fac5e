// pwsim run [SCENE] [--out DIR]: simulates a scene and writes DIR/trial.csv and
// DIR/summary.json. Wiring only: the physics is in engine/.

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "app/commands.h"
#include "app/run_mca.h"
#include "app/run_render.h"
#include "app/scene_path.h"
#include "engine/atomic_file.h"
#include "engine/chair_simulator.h"
#include "engine/scene.h"
#include "engine/trial_table.h"

namespace pwsim::app {
namespace {

/// The engine's per-tick samples as the trial.csv columns of the foundation.
TrialTable ChairColumns(const Scene& scene, const std::vector<ChairSample>& samples) {
  const std::size_t rows = samples.size();
  TrialTable table(rows);
  auto column = [&](auto&& get) {
    std::vector<double> values(rows);
    for (std::size_t r = 0; r < rows; ++r) values[r] = get(samples[r]);
    return values;
  };
  table.Add("t_s", column([&](const ChairSample& s) { return scene.clock.TimeAt(s.tick); }));
  table.Add("x_m", column([](const ChairSample& s) { return s.drive.x; }));
  table.Add("v_mps", column([](const ChairSample& s) { return s.drive.v; }));
  table.Add("a_mps2", column([](const ChairSample& s) { return s.drive.a; }));
  for (int i = 0; i < scene.chair.wheel_count(); ++i) {
    table.Add("z_o" + std::to_string(i + 1) + "_m",
              column([i](const ChairSample& s) { return s.z_O[static_cast<std::size_t>(i)]; }));
  }
  table.Add("z_gm_m", column([](const ChairSample& s) { return s.gm.z; }));
  table.Add("pitch_gm_rad", column([](const ChairSample& s) { return s.gm.pitch; }));
  table.Add("z_m", column([](const ChairSample& s) { return s.lm.z; }));
  table.Add("pitch_rad", column([](const ChairSample& s) { return s.lm.pitch; }));
  table.Add("z_rate_mps", column([](const ChairSample& s) { return s.lm.z_rate; }));
  table.Add("pitch_rate_radps", column([](const ChairSample& s) { return s.lm.pitch_rate; }));
  table.Add("z_acc_mps2", column([](const ChairSample& s) { return s.lm_acc.z; }));
  table.Add("pitch_acc_radps2", column([](const ChairSample& s) { return s.lm_acc.pitch; }));
  table.Add("pitch_torque_nm", column([](const ChairSample& s) { return s.pitch_torque; }));
  return table;
}

/// Largest |value - reference| over the trial, with its time.
nlohmann::ordered_json Peak(const TrialTable& table, const std::string& name, const char* unit) {
  const auto& t = table.Column("t_s");
  const auto& values = table.Column(name);
  std::size_t best = 0;
  for (std::size_t r = 1; r < values.size(); ++r) {
    if (std::abs(values[r] - values[0]) > std::abs(values[best] - values[0])) best = r;
  }
  return {{"column", name},
          {std::string("value_") + unit, values[best]},
          {std::string("excursion_") + unit, values[best] - values[0]},
          {"t_s", t[best]}};
}

}  // namespace

const CommandSpec& RunSpec() {
  static const CommandSpec spec{
      "run",
      "pwsim run [SCENE] [options]",
      "Simulate a scene (default: scenes/speed_cushion.yaml) and write trial.csv and summary.json.",
      {
          {"out", "DIR", "-", "out/run", "output folder (created)"},
          {"decimate", "N", "ticks", "1", "write every N-th tick to trial.csv"},
          {"size", "WxH", "px", "1280x720", "image size (scene render.size; stereo: both eyes)"},
          {"fps", "N", "frames/s", "50", "video frame rate; must divide the clock rate"},
          {"stereo", "", "-", "", "render side-by-side HMD eyes (scene render.hmd)"},
          {"no-tilt-removal", "", "-", "", "keep the platform tilt in the view (to compare)"},
          {"png-frames", "", "-", "", "also write DIR/frames/frame_NNNNN.png"},
          {"lossless", "", "-", "", "also write DIR/video_lossless.mkv (exact pixels)"},
          {"no-video", "", "-", "off", "skip rendering (no video.mp4, frames.csv)"},
      },
      "SCENE  a pwsim-scene/1 YAML file (default: the paper's speed-cushion trial)"};
  return spec;
}

int RunCommand(const ParsedArgs& args) {
  if (args.positional().size() > 1) throw std::invalid_argument("expected at most one SCENE");
  const std::filesystem::path scene_path =
      args.positional().empty() ? DefaultScene() : std::filesystem::path(args.positional()[0]);
  const std::filesystem::path out_dir = args.Get("out");
  const long long decimate = args.GetInt("decimate");
  if (decimate < 1) throw std::invalid_argument("option --decimate: expected an integer >= 1");

  const Scene scene = LoadScene(scene_path);
  const std::vector<ChairSample> samples = SimulateScene(scene);
  TrialTable table = ChairColumns(scene, samples);

  nlohmann::ordered_json summary;
  summary["format"] = "pwsim-run-summary/1";
  summary["scene"] = {{"file", scene_path.string()}, {"name", scene.name}};
  summary["clock_rate_hz"] = scene.clock.rate_hz;
  summary["duration_s"] = table.Column("t_s").back();
  summary["ticks"] = samples.size();
  summary["load_kg"] = scene.load_kg;
  summary["speed_mps"] = scene.drive.speed;
  summary["peak_heave"] = Peak(table, "z_m", "m");
  summary["peak_pitch"] = Peak(table, "pitch_rad", "rad");
  AddMotionCueing(scene, samples, table, summary, out_dir);  // mca/: platform, visual, vestibular

  std::filesystem::create_directories(out_dir);
  table.WriteCsv(out_dir / "trial.csv", static_cast<int>(decimate));
  RenderTrial(scene, table, args, summary, out_dir);  // render/: video, frames.csv
  WriteFileAtomically(out_dir / "summary.json", summary.dump(2) + "\n");
  std::cout << "pwsim run: scene '" << scene.name << "' (" << scene_path.string() << "), "
            << samples.size() << " ticks at " << scene.clock.rate_hz << " Hz; wrote:\n";
  for (const char* name : {"trial.csv", "summary.json", "mca.png", "video.mp4", "video_lossless.mkv",
                           "frames.csv", "visual_check.csv", "visual_check.png"}) {
    if (std::filesystem::exists(out_dir / name)) std::cout << "  " << (out_dir / name).string() << "\n";
  }
  return 0;
}

}  // namespace pwsim::app
