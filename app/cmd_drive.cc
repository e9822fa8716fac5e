// pwsim drive SCENE [--wheel] [--device NAME] [--duration S] [--out DIR] [--no-realtime]:
// drives a car scene live at its clock rate: the controls come from a real steering wheel and
// pedals (SDL2, --wheel; mapping from the scene's session.controls) or from the scene itself;
// each tick steps the car and the MCA (hardware/car_live.h) and logs the platform command.
// Writes DIR/drive.csv. Wiring only.

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include "app/commands.h"
#include "app/stop_signal.h"
#include "engine/trial_table.h"
#include "engine/vehicle/car_scene.h"
#include "hardware/car_live.h"
#include "hardware/sdl/sdl_input.h"

namespace pwsim::app {

const CommandSpec& DriveSpec() {
  static const CommandSpec spec{
      "drive",
      "pwsim drive SCENE [options]",
      "Drive a car scene live (real steering wheel and pedals with --wheel), car + MCA per tick.",
      {
          {"wheel", "", "-", "", "read the controls from an SDL2 joystick (wheel, pedals, shifter)"},
          {"device", "NAME", "-", "", "part of the joystick's name (default: session.controls.device or the first)"},
          {"duration", "S", "s", "", "drive time (default: the scene's duration_s)"},
          {"no-realtime", "", "-", "", "step as fast as possible instead of at the clock rate"},
          {"out", "DIR", "-", "out/drive", "output folder (drive.csv)"},
      },
      "SCENE  a pwsim-scene/1 YAML file with kind: car"};
  return spec;
}

int DriveCommand(const ParsedArgs& args) {
  if (args.positional().size() != 1) throw UsageError("expected one SCENE (kind: car)");
  const std::filesystem::path scene_path = args.positional()[0];
  if (vehicle::SceneKind(scene_path) != "car") throw UsageError("pwsim drive needs a car scene (kind: car)");
  const vehicle::CarScene scene = vehicle::LoadCarScene(scene_path);
  hw::ControlMapping mapping;
  if (const SceneSection* s = scene.section("session")) {
    YamlMap map(s->node, s->file, "session", s->line);
    if (map.Has("controls")) {
      YamlMap controls = map.Map("controls");
      mapping = hw::ParseControlMapping(controls);
      controls.Finish();
    }
    map.Finish();
  }
  if (args.Has("device")) mapping.device = args.Get("device");
  const double duration = args.Has("duration") ? args.GetDouble("duration") : scene.duration;
  if (!(duration > 0.0 && duration <= 3600.0)) throw UsageError("option --duration: expected (0, 3600] s");
  const std::int64_t ticks = scene.clock.TicksFor(duration);

  std::unique_ptr<hw::SdlWheel> wheel;
  std::vector<vehicle::CarSample> scripted;
  if (args.Flag("wheel")) {
    wheel = std::make_unique<hw::SdlWheel>(mapping);
    std::cout << "pwsim drive: wheel '" << wheel->name() << "'\n";
  } else {
    scripted = vehicle::SimulateCarScene(scene);  // the scene's own controls
  }
  hw::CarLiveLoop loop(scene, mca::LoadMcaConfig(scene.section("platform"), scene.section("mca"), mca::CarMcaDefaults()));
  const std::size_t rows = static_cast<std::size_t>(ticks) + 1;
  std::vector<double> t(rows), x(rows), y(rows), yaw(rows), v(rows), rpm(rows), gear(rows), throttle(rows),
      brake(rows), clutch(rows), steer(rows), rail(rows), turn(rows), cue_x(rows), cue_y(rows), late(rows);
  InstallStopSignalHandlers();
  const auto start = std::chrono::steady_clock::now();
  const auto period = std::chrono::nanoseconds(1000000000LL / scene.clock.rate_hz);
  std::size_t done = 0;
  for (std::int64_t k = 0; k <= ticks && !StopRequested().load(); ++k) {
    const auto due = start + k * period;
    if (!args.Flag("no-realtime")) std::this_thread::sleep_until(due);
    late[done] = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - due).count();
    const hw::CarLiveTick& tick =
        k == 0 ? loop.last()
               : loop.Step(wheel ? wheel->Poll()
                                 : scripted[std::min(static_cast<std::size_t>(k), scripted.size() - 1)].input);
    const vehicle::CarSample& s = tick.sample;
    t[done] = scene.clock.TimeAt(k);
    x[done] = s.state.x;
    y[done] = s.state.y;
    yaw[done] = s.state.yaw;
    v[done] = vehicle::Speed(s.state);
    rpm[done] = vehicle::EngineRpm(s.state);
    gear[done] = s.input.gear;
    throttle[done] = s.input.throttle;
    brake[done] = s.input.brake;
    clutch[done] = s.input.clutch;
    steer[done] = s.input.steer;
    rail[done] = tick.command.pose[mca::Index(mca::Dof::kSurge)];
    turn[done] = tick.command.pose[mca::Index(mca::Dof::kYaw)];
    cue_x[done] = tick.false_cue_surge;
    cue_y[done] = tick.false_cue_sway;
    ++done;
    if (k % scene.clock.rate_hz == 0) {
      std::cout << "  t " << t[done - 1] << " s  " << std::lround(v[done - 1] * 3.6) << " km/h  "
                << std::lround(rpm[done - 1]) << " rpm  gear " << s.input.gear << "  rail " << rail[done - 1]
                << " m  yaw " << turn[done - 1] << " rad\n" << std::flush;
    }
  }
  TrialTable table(done);
  auto cut = [&](std::vector<double>& c) { c.resize(done); return c; };
  table.Add("t_s", cut(t));
  table.Add("x_m", cut(x));
  table.Add("y_m", cut(y));
  table.Add("yaw_rad", cut(yaw));
  table.Add("v_mps", cut(v));
  table.Add("engine_rpm", cut(rpm));
  table.Add("gear", cut(gear));
  table.Add("throttle", cut(throttle));
  table.Add("brake", cut(brake));
  table.Add("clutch", cut(clutch));
  table.Add("steer_rad", cut(steer));
  table.Add("plat_surge_m", cut(rail));
  table.Add("plat_yaw_rad", cut(turn));
  table.Add("false_cue_surge_mps2", cut(cue_x));
  table.Add("false_cue_sway_mps2", cut(cue_y));
  table.Add("tick_lateness_us", cut(late));
  const std::filesystem::path out = args.Get("out");
  std::filesystem::create_directories(out);
  table.WriteCsv(out / "drive.csv");
  std::cout << "pwsim drive: " << done << " ticks" << (StopRequested().load() ? " (stopped)" : "") << "; wrote "
            << (out / "drive.csv").string() << "\n";
  return 0;
}

}  // namespace pwsim::app
