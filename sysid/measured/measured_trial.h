#pragma once
// A measured trial (measured-trials.md): a folder with trial.yaml (format pwsim-trial/1), the
// chair, the terrain and the mocap track, read and checked at load time; and the model of
// seed 000 driven by the trial's measured x(t) (Fig. 6b):
//   measured x(t) -> terrain -> wheel contact heights -> GM (eq. 1-2) -> LM (eq. 3-5)
//   -> Z and θ at the mocap timestamps.
//
//   MeasuredTrial trial = ReadMeasuredTrial("assets/trials-demo/s1.20_l100_c1_r1");
//   ModelOutput model = SimulateMeasuredTrial(trial.chair, trial.terrain, trial.load_kg,
//                                             trial.track.t, trial.track.x);

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "sysid/measured/mocap.h"
#include "engine/terrain.h"

namespace pwsim {

/// The programmed power-module profile (informative only).
struct ProgrammedProfile {
  std::optional<double> speed;  ///< [m/s]
  std::optional<double> accel;  ///< [m/s^2]
};

struct MeasuredTrial {
  std::string name;               ///< the folder name (fit.json's "trial")
  std::filesystem::path folder;
  std::filesystem::path trial_file;  ///< .../trial.yaml
  std::filesystem::path chair_file;
  std::filesystem::path terrain_file;
  Chair chair;
  Terrain terrain;
  double load_kg{0.0};            ///< M_u [kg]
  ProgrammedProfile profile;
  std::string mocap_format;       ///< "csv" or "qtm-6d-tsv"
  std::string mocap_body;         ///< qtm-6d-tsv body name
  MocapTrack track;
  /// Per wheel, the height the wheel meets over the terrain file's (an obstacle yielding under
  /// it by that share, as a diagnosis found it: effects::CushionHeightFactors); empty: 1. Not
  /// read from the folder: set by code that knows it, and used by identification.
  std::vector<double> contact_height_scale;

  /// The programmed speed if given, else the peak measured speed [m/s].
  double NominalSpeed() const;
};

/// Reads a trial folder (or its trial.yaml directly). @throws InputError.
MeasuredTrial ReadMeasuredTrial(const std::filesystem::path& folder_or_file,
                                const MocapReadOptions& options = {});

/// The model's Z and θ at the requested times.
/// A model's output at the trial's sample times: the measured channels, and the geometric
/// model's own output where the model computes it (the extended models of sysid/effects/ do;
/// the base model's simulation leaves them empty).
struct ModelOutput {
  std::vector<double> z;         ///< Z_M [m] (0 = the GM altitude of flat ground)
  std::vector<double> pitch;     ///< θ_M [rad]
  std::vector<double> z_gm;      ///< [m] GM output (effective contacts); may be empty
  std::vector<double> pitch_gm;  ///< [rad]; may be empty
};

struct SimulationOptions {
  double dt{1e-3};  ///< [s] fixed internal step of the exact LM
};

/// The GM output on the internal grid t0 + k dt, with x(t) interpolated linearly between the
/// samples (across dropped frames as well). The grid covers [t.front(), t.back()].
struct GeometricTrace {
  double t0{0.0};
  double dt{1e-3};
  std::vector<double> z_gm;      ///< [m]
  std::vector<double> pitch_gm;  ///< [rad]
};

/// Contact heights and GM output along a measured x(t), each wheel's height times
/// `height_scale[i]` where given (MeasuredTrial::contact_height_scale). @pre t strictly
/// increasing, chair.gm.
GeometricTrace TraceGeometricModel(const Chair& chair, const Terrain& terrain,
                                   std::span<const double> t, std::span<const double> x,
                                   const SimulationOptions& options = {},
                                   std::span<const double> height_scale = {});

/// Contact heights Z_Oi on the internal grid (one vector per wheel) for regressions on α, β,
/// scaled as TraceGeometricModel's.
std::vector<std::vector<double>> TraceContactHeights(const Chair& chair, const Terrain& terrain,
                                                     std::span<const double> t,
                                                     std::span<const double> x,
                                                     const SimulationOptions& options = {},
                                                     std::span<const double> height_scale = {});

/// Points of the internal grid t0 + k dt that cover [t.front(), t.back()].
std::size_t GridSize(std::span<const double> t, double dt);

/// x at each grid time t0 + k dt, linear between the samples, held at the ends.
std::vector<double> InterpolateOnGrid(std::span<const double> t, std::span<const double> x,
                                      double dt);

/// A grid signal (t0 + k dt) at the times t, linear between grid points, held at the ends.
std::vector<double> SampleGrid(std::span<const double> grid, double t0, double dt,
                               std::span<const double> t);

/// One axis of the LM (inertia, damping, stiffness) run exactly on `input` (a grid signal,
/// first-order hold), starting at rest in equilibrium, sampled at `t` by linear
/// interpolation between grid points.
std::vector<double> SimulateAxisOnGrid(double inertia, double damping, double stiffness,
                                       std::span<const double> input, double t0, double dt,
                                       std::span<const double> t);

/// The full model (GM + LM with the chair's gm and lm) driven by the measured x(t) and
/// sampled at the same times t. @pre chair.gm and chair.lm, t strictly increasing, t.size() ≥ 2.
ModelOutput SimulateMeasuredTrial(const Chair& chair, const Terrain& terrain, double load_kg,
                                  std::span<const double> t, std::span<const double> x,
                                  const SimulationOptions& options = {});

/// Convenience: the model for a read trial (uses trial.chair, or `chair` when given).
ModelOutput SimulateMeasuredTrial(const MeasuredTrial& trial, const Chair* chair = nullptr,
                                  const SimulationOptions& options = {});

/// Offset between a measured channel and the model: the mean of (measured - model) over the
/// samples of the first `window` seconds (the chair at rest at the start, as the paper's
/// Fig. 5 centres Z at the beginning of the trial). At least one sample is used.
double InitialOffset(std::span<const double> t, std::span<const double> measured,
                     std::span<const double> model, double window = 0.25);

}  // namespace pwsim
