// pwsim run [SCENE] [--out DIR]: simulates a scene and writes DIR/trial.csv and
// DIR/summary.json. Wiring only: the physics is in engine/. Every option and the scene are
// checked before anything is simulated or written; the outputs replace what the last pwsim
// command wrote into DIR (app/output_folder.h).

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "app/commands.h"
#include "app/output_folder.h"
#include "app/progress.h"
#include "app/scene_path.h"
#include "engine/atomic_file.h"
#include "engine/chair_simulator.h"
#include "engine/scene.h"
#include "engine/vehicle/car_scene.h"
#include "report/car_run.h"
#include "engine/trial_table.h"
#include "report/render_stage.h"
#include "report/run_circuit.h"
#include "report/run_mca.h"
#include "report/run_report.h"
#include "report/skill_score.h"

namespace pwsim::app {
namespace {

/// --size WxH (px), --fps N and the render flags, each number checked with its option's name.
report::RenderStageOptions RenderOptions(const ParsedArgs& args) {
  report::RenderStageOptions options;
  if (args.Has("size")) {
    const std::string text = args.Get("size");
    int width = 0, height = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &extra) != 3 || x != 'x' ||
        width < 16 || height < 16 || width > 16384 || height > 16384) {
      throw UsageError("option --size: expected WxH in px, each 16..16384 (e.g. 1280x720), got '" +
                                  text + "'");
    }
    options.width_px = width;
    options.height_px = height;
  }
  if (args.Has("fps")) {
    const long long fps = args.GetInt("fps");
    if (fps < 1 || fps > 1000) throw UsageError("option --fps: expected 1..1000");
    options.fps = static_cast<int>(fps);
  }
  options.stereo = args.Flag("stereo");
  options.no_tilt_removal = args.Flag("no-tilt-removal");
  options.no_video = args.Flag("no-video");
  options.lossless = args.Flag("lossless");
  options.png_frames = args.Flag("png-frames");
  return options;
}

/// --fps against the scene's clock, before anything is simulated or written: frame k is tick
/// k·N, so the frame rate must divide the clock rate (with --no-video too: a wrong value is
/// refused, never ignored).
void CheckFps(const ParsedArgs& args, int clock_rate_hz) {
  if (!args.Has("fps")) return;
  const long long fps = args.GetInt("fps");
  if (clock_rate_hz % fps != 0) {
    throw UsageError("option --fps: expected a divisor of the clock rate " + std::to_string(clock_rate_hz) +
                     " Hz of the scene (frame k is tick k*N exactly, e.g. 25, 50, 100), got " + args.Get("fps"));
  }
}

}  // namespace

const CommandSpec& RunSpec() {
  static const CommandSpec spec{
      "run",
      "pwsim run [SCENE] [options]",
      "Simulate a scene (default: scenes/speed_cushion.yaml) and write trial.csv and summary.json.",
      {
          OutOption("run", "trial.csv, summary.json, mca.*, video.mp4, ..."),
          {"decimate", "N", "ticks", "1", "write every N-th tick to trial.csv"},
          {"size", "WxH", "px", "1280x720", "image size (scene render.size; stereo: both eyes)"},
          {"fps", "N", "frames/s", "50", "video frame rate; must divide the clock rate"},
          {"stereo", "", "-", "", "render side-by-side HMD eyes (scene render.hmd)"},
          {"no-tilt-removal", "", "-", "", "keep the platform tilt in the view (to compare)"},
          {"png-frames", "", "-", "", "also write DIR/frames/frame_NNNNN.png"},
          {"lossless", "", "-", "", "also write DIR/video_lossless.mkv (exact pixels)"},
          {"no-video", "", "-", "off", "skip rendering (no video.mp4, frames.csv)"},
          {"mca", "washout|mpc|offline", "-", "", "motion cueing: the washout, the MPC, or the offline ceiling (the whole trial optimised at once); overrides the scene's mca.algorithm"},
          {"mca-preview", "", "-", "", "the MPC previews the trial ahead (mca.mpc.preview)"},
          {"no-mca-compare", "", "-", "", "skip summary.json's mca.comparison (the trial through the washout, the MPC and the offline ceiling)"},
          {"platform", "FILE", "-", "", "a pwsim-platform/1 file instead of the scene's platform (scenes/platforms/*.yaml)"},
          QuietOption(),
      },
      "SCENE  a pwsim-scene/1 YAML file (default: the paper's speed-cushion trial); kind: car runs seed 001's car; a circuit: section runs the full-DoF chair through it"};
  return spec;
}

int RunCommand(const ParsedArgs& args) {
  if (args.positional().size() > 1) throw UsageError("expected at most one SCENE");
  const std::filesystem::path scene_path =
      args.positional().empty() ? DefaultScene() : std::filesystem::path(args.positional()[0]);
  const std::filesystem::path out_dir = OutDir(args);
  const long long decimate = args.GetInt("decimate");
  if (decimate < 1) throw UsageError("option --decimate: expected an integer >= 1");

  report::RenderStageOptions render_options = RenderOptions(args);
  Progress progress("pwsim run", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  render_options.progress = progress.callback();
  report::McaChoice mca_choice;
  if (args.Has("mca")) {
    const std::string name = args.Get("mca");
    if (name != "washout" && name != "mpc" && name != "offline") {
      throw UsageError("option --mca: expected washout, mpc or offline, got '" + name + "'");
    }
    mca_choice.algorithm = name == "washout" ? mca::McaAlgorithm::kWashout : mca::McaAlgorithm::kMpc;
    mca_choice.offline = name == "offline";
  }
  mca_choice.preview = args.Flag("mca-preview");
  mca_choice.compare = !args.Flag("no-mca-compare");
  if (args.Has("platform")) mca_choice.platform = std::filesystem::path(args.Get("platform"));

  // Read once: the scene may come from a pipe (a sweep task reads its scene from a FIFO).
  const YamlDocument scene_document = LoadYamlFile(scene_path);
  if (vehicle::SceneKind(scene_document) == "car") {  // seed 001's car on the rail + yaw platform
    const vehicle::CarScene car_scene = vehicle::ParseCarScene(scene_document);
    CheckFps(args, car_scene.clock.rate_hz);
    report::CarRunOptions car;
    car.decimate = static_cast<int>(decimate);
    car.video = !render_options.no_video;
    car.width = render_options.width_px;
    car.height = render_options.height_px;
    car.fps = render_options.fps;
    car.mca = mca_choice;
    car.progress = progress.callback();
    OutputFolder folder(out_dir, "run");  // replaces what the last command wrote there
    progress.Stage("simulate the car and its motion cueing");
    report::RunCarScene(car_scene, scene_path, car, out_dir);
    progress.Finish();
    std::cout << "pwsim run: car scene '" << car_scene.name << "' (" << scene_path.string() << "), "
              << car_scene.tick_count() << " ticks at " << car_scene.clock.rate_hz << " Hz\n";
    folder.Print(std::cout, "pwsim run");
    return 0;
  }

  const Scene scene = ParseScene(scene_document);
  CheckFps(args, scene.clock.rate_hz);
  report::CheckRenderSetup(scene, render_options);  // the scene's render: section, before any output
  (void)report::SkillOf(scene);  // a skill item's skill: section, before any output
  OutputFolder folder(out_dir, "run");  // replaces what the last command wrote there
  if (scene.is_circuit()) {  // the full-DoF chair through a circuit, every platform axis
    progress.Stage("simulate the chair through the circuit and its motion cueing");
    std::string skill_line;  // a skill item's score (report/skill_score.h)
    report::RunCircuitScene(scene, scene_path.string(), static_cast<int>(decimate), render_options, out_dir,
                            mca_choice, &skill_line);
    progress.Finish();
    std::cout << "pwsim run: circuit scene '" << scene.name << "' (" << scene_path.string() << "), "
              << scene.tick_count() << " ticks at " << scene.clock.rate_hz << " Hz\n";
    if (!skill_line.empty()) std::cout << "  " << skill_line << "\n";
    folder.Print(std::cout, "pwsim run");
    return 0;
  }
  progress.Stage("simulate the chair");
  const std::vector<ChairSample> samples = SimulateScene(scene);
  TrialTable table = report::ChairColumns(scene, samples);
  nlohmann::ordered_json summary = report::RunSummary(scene, scene_path.string(), table);
  progress.Stage("motion cueing");
  report::AddMotionCueing(scene, samples, table, summary, out_dir, mca_choice);  // platform, visual, vestibular

  std::filesystem::create_directories(out_dir);
  table.WriteCsv(out_dir / "trial.csv", static_cast<int>(decimate));
  report::RenderTrial(scene, table, render_options, summary, out_dir);  // video, frames.csv
  WriteFileAtomically(out_dir / "summary.json", summary.dump(2) + "\n");
  progress.Finish();
  std::cout << "pwsim run: scene '" << scene.name << "' (" << scene_path.string() << "), "
            << samples.size() << " ticks at " << scene.clock.rate_hz << " Hz\n";
  folder.Print(std::cout, "pwsim run");
  return 0;
}

}  // namespace pwsim::app
