#pragma once
// Terrain: the ground height z(x) along the straight path, in frame W (x forward, z up).
// Piecewise linear through the listed points; z = 0 outside the listed span
// (measured-trials.md, terrain.yaml). The speed cushion of the paper is one such profile.

#include <filesystem>
#include <string>
#include <vector>

#include "engine/interpolate.h"
#include "engine/yaml_reader.h"

namespace pwsim {

struct Terrain {
  std::vector<double> x;  ///< [m] strictly increasing breakpoints along W's x axis
  std::vector<double> z;  ///< [m] ground height at each breakpoint

  /// z(x) [m]; 0 outside [x.front(), x.back()].
  double HeightAt(double x_W) const;
  /// z(x) as HeightAt, bit for bit, with the breakpoint search started at `hint` (a lookup that
  /// moves little between calls, as a wheel from tick to tick); `hint` is updated.
  double HeightAtNear(double x_W, std::size_t& hint) const;
  /// dz/dx [-] (right-hand slope at a breakpoint); 0 outside the span.
  double SlopeAt(double x_W) const;
  /// Highest point of the profile [m].
  double MaxHeight() const;
};

inline double Terrain::HeightAtNear(double x_W, std::size_t& hint) const {
  // the branches of HeightAt and InterpolateLinear, in the same order, with the hinted search
  if (x.empty()) return 0.0;
  if (x_W <= x.front() || x_W >= x.back()) {  // HeightAt's ends, inline (a wheel past the profile)
    if (x_W == x.front()) return z.front();
    if (x_W == x.back()) return z.back();
    return 0.0;
  }
  const KnotSegment seg = FindKnotSegmentNear(x, x_W, hint);
  // A level segment: Lerp adds s · (+0) = +0 for any s in [0, 1], so z_k + 0 is its result bit
  // for bit (the s above is then unused and its division skipped).
  if (z[seg.k] == z[seg.k + 1]) return z[seg.k] + 0.0;
  return Lerp(z[seg.k], z[seg.k + 1], seg.s);
}

/// The paper's speed cushion: flat, a 0.30 m ramp up to `height` from `start_x`, a plateau of
/// `plateau_length`, a ramp down, flat until `end_x`.
Terrain MakeSpeedCushion(double start_x = 1.80, double height = 0.065, double ramp_length = 0.30,
                         double plateau_length = 1.50, double end_x = 12.0);

/// Reads the `profile_m` list (and only that) from an open mapping.
Terrain ParseTerrainProfile(YamlMap& map);
/// Reads a `pwsim-terrain/1` file.
Terrain ReadTerrainFile(const std::filesystem::path& file);
/// Writes a `pwsim-terrain/1` file (atomically).
void WriteTerrainFile(const Terrain& terrain, const std::filesystem::path& file);

}  // namespace pwsim
