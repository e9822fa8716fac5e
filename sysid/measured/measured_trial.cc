#include "sysid/measured/measured_trial.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"
#include "engine/interpolate.h"
#include "engine/geometric_model.h"
#include "engine/input_error.h"
#include "engine/lumped_model.h"
#include "engine/yaml_reader.h"

namespace pwsim {

double MeasuredTrial::NominalSpeed() const {
  if (profile.speed) return *profile.speed;
  // Peak speed over 0.2 s spans, so that mocap noise does not inflate it.
  double peak = 0.0;
  std::size_t begin = 0;
  for (std::size_t k = 1; k < track.size(); ++k) {
    while (begin + 1 < k && track.t[k] - track.t[begin + 1] >= 0.2) ++begin;
    const double span = track.t[k] - track.t[begin];
    if (span >= 0.2 || begin == 0) {
      peak = std::max(peak, std::abs(track.x[k] - track.x[begin]) / span);
    }
  }
  return peak;
}

MeasuredTrial ReadMeasuredTrial(const std::filesystem::path& folder_or_file,
                                const MocapReadOptions& options) {
  MeasuredTrial trial;
  const bool is_folder = std::filesystem::is_directory(folder_or_file);
  trial.trial_file = is_folder ? folder_or_file / "trial.yaml" : folder_or_file;
  trial.folder = trial.trial_file.parent_path();
  std::filesystem::path named = is_folder ? folder_or_file : trial.folder;
  if (named.filename().empty()) named = named.parent_path();  // "dir/" -> "dir"
  trial.name = named.filename().string();
  if (trial.name.empty() || trial.name == ".") {
    trial.name = std::filesystem::absolute(named).lexically_normal().filename().string();
  }

  const YamlDocument document = LoadYamlFile(trial.trial_file);
  YamlMap root(document.root, document.file, "");
  root.RequireFormat("pwsim-trial/1");
  trial.chair_file = ResolveRelative(trial.trial_file, root.String("chair"));
  trial.terrain_file = ResolveRelative(trial.trial_file, root.String("terrain"));
  trial.load_kg = root.Number("load_kg", Range::Closed(0.0, 500.0, "kg"));
  if (root.Has("profile")) {
    YamlMap profile = root.Map("profile");
    if (profile.Has("speed_mps")) {
      trial.profile.speed = profile.Number("speed_mps", Range::Positive(10.0, "m/s"));
    }
    if (profile.Has("accel_mps2")) {
      trial.profile.accel = profile.Number("accel_mps2", Range::Positive(20.0, "m/s^2"));
    }
    profile.Finish();
  }
  YamlMap mocap = root.Map("mocap");
  const std::string mocap_file = mocap.String("file");
  trial.mocap_format = mocap.Choice("format", {"csv", "qtm-6d-tsv"});
  if (trial.mocap_format == "qtm-6d-tsv") {
    trial.mocap_body = mocap.String("body");
  } else {
    trial.mocap_body = mocap.StringOr("body", "");
  }
  mocap.Finish();
  root.Finish();

  trial.chair = ReadChairFile(trial.chair_file);
  trial.terrain = ReadTerrainFile(trial.terrain_file);
  trial.track = ReadMocapFile(ResolveRelative(trial.trial_file, mocap_file), trial.mocap_format,
                              trial.mocap_body, options);
  return trial;
}

std::size_t GridSize(std::span<const double> t, double dt) {
  PWSIM_DEMAND(t.size() >= 2 && dt > 0.0);
  return static_cast<std::size_t>(std::ceil((t.back() - t.front()) / dt - 1e-9)) + 1;
}

std::vector<double> InterpolateOnGrid(std::span<const double> t, std::span<const double> x,
                                      double dt) {
  return ResampleOnUniformGrid(t, x, dt, GridSize(t, dt));
}

std::vector<double> SampleGrid(std::span<const double> grid, double t0, double dt,
                               std::span<const double> t) {
  std::vector<double> out(t.size());
  for (std::size_t s = 0; s < t.size(); ++s) out[s] = SampleUniformGrid(grid, t0, dt, t[s]);
  return out;
}

std::vector<std::vector<double>> TraceContactHeights(const Chair& chair, const Terrain& terrain,
                                                     std::span<const double> t,
                                                     std::span<const double> x,
                                                     const SimulationOptions& options,
                                                     std::span<const double> height_scale) {
  PWSIM_DEMAND(height_scale.empty() || height_scale.size() == chair.wheels.size());
  const std::vector<double> x_grid = InterpolateOnGrid(t, x, options.dt);
  std::vector<std::vector<double>> heights(chair.wheels.size(),
                                           std::vector<double>(x_grid.size()));
  for (std::size_t i = 0; i < chair.wheels.size(); ++i) {
    const double scale = height_scale.empty() ? 1.0 : height_scale[i];
    for (std::size_t k = 0; k < x_grid.size(); ++k) {
      heights[i][k] = terrain.HeightAt(x_grid[k] + chair.wheels[i].x) * scale;
    }
  }
  return heights;
}

GeometricTrace TraceGeometricModel(const Chair& chair, const Terrain& terrain,
                                   std::span<const double> t, std::span<const double> x,
                                   const SimulationOptions& options,
                                   std::span<const double> height_scale) {
  PWSIM_DEMAND(height_scale.empty() || height_scale.size() == chair.wheels.size());
  const GeometricModel gm(chair);
  const std::vector<double> x_grid = InterpolateOnGrid(t, x, options.dt);
  GeometricTrace trace;
  trace.t0 = t.front();
  trace.dt = options.dt;
  trace.z_gm.resize(x_grid.size());
  trace.pitch_gm.resize(x_grid.size());
  std::array<double, kMaxWheels> z_O{};
  const std::size_t wheels = static_cast<std::size_t>(gm.wheel_count());
  for (std::size_t k = 0; k < x_grid.size(); ++k) {
    gm.ContactHeights(terrain, x_grid[k], std::span<double>(z_O.data(), wheels));
    for (std::size_t i = 0; i < height_scale.size(); ++i) z_O[i] *= height_scale[i];
    const GeometricOutput out = gm.Evaluate(std::span<const double>(z_O.data(), wheels));
    trace.z_gm[k] = out.z;
    trace.pitch_gm[k] = out.pitch;
  }
  return trace;
}

std::vector<double> SimulateAxisOnGrid(double inertia, double damping, double stiffness,
                                       std::span<const double> input, double t0, double dt,
                                       std::span<const double> t) {
  PWSIM_DEMAND(!input.empty());
  const AxisPropagator propagator = MakeAxisPropagator({inertia, damping, stiffness}, dt);
  const double inv_dt = 1.0 / dt;
  std::vector<double> q(input.size());
  double value = input[0];
  double rate = 0.0;
  q[0] = value;
  for (std::size_t k = 0; k + 1 < input.size(); ++k) {
    AdvanceAxis(propagator, value, rate, input[k], (input[k + 1] - input[k]) * inv_dt, 0.0);
    q[k + 1] = value;
  }
  return SampleGrid(q, t0, dt, t);
}

ModelOutput SimulateMeasuredTrial(const Chair& chair, const Terrain& terrain, double load_kg,
                                  std::span<const double> t, std::span<const double> x,
                                  const SimulationOptions& options) {
  PWSIM_DEMAND(chair.gm.has_value() && chair.lm.has_value());
  const GeometricTrace trace = TraceGeometricModel(chair, terrain, t, x, options);
  const LumpedModelParams params = MakeLumpedModelParams(chair, load_kg);
  ModelOutput out;
  out.z = SimulateAxisOnGrid(params.heave.inertia, params.heave.damping, params.heave.stiffness,
                             trace.z_gm, trace.t0, trace.dt, t);
  out.pitch = SimulateAxisOnGrid(params.pitch.inertia, params.pitch.damping,
                                 params.pitch.stiffness, trace.pitch_gm, trace.t0, trace.dt, t);
  return out;
}

ModelOutput SimulateMeasuredTrial(const MeasuredTrial& trial, const Chair* chair,
                                  const SimulationOptions& options) {
  return SimulateMeasuredTrial(chair ? *chair : trial.chair, trial.terrain, trial.load_kg,
                               trial.track.t, trial.track.x, options);
}

double InitialOffset(std::span<const double> t, std::span<const double> measured,
                     std::span<const double> model, double window) {
  PWSIM_DEMAND(!t.empty() && measured.size() == t.size() && model.size() == t.size());
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < t.size() && (count == 0 || t[k] - t.front() <= window); ++k) {
    sum += measured[k] - model[k];
    ++count;
  }
  return sum / static_cast<double>(count);
}

}  // namespace pwsim
