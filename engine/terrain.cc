#include "engine/terrain.h"

#include <algorithm>
#include <sstream>

#include "engine/atomic_file.h"
#include "engine/check.h"
#include "engine/input_error.h"
#include "engine/interpolate.h"
#include "engine/number_format.h"

namespace pwsim {

double Terrain::HeightAt(double x_W) const {
  if (x.empty() || x_W <= x.front() || x_W >= x.back()) {
    if (x.empty()) return 0.0;
    if (x_W == x.front()) return z.front();
    if (x_W == x.back()) return z.back();
    return 0.0;
  }
  return InterpolateLinear(x, z, x_W);
}

double Terrain::SlopeAt(double x_W) const {
  if (x.size() < 2 || x_W < x.front() || x_W >= x.back()) return 0.0;
  const std::size_t k = FindKnotSegment(x, x_W).k;
  return (z[k + 1] - z[k]) / (x[k + 1] - x[k]);
}

double Terrain::MaxHeight() const {
  double highest = 0.0;
  for (double height : z) highest = std::max(highest, height);
  return highest;
}

Terrain MakeSpeedCushion(double start_x, double height, double ramp_length,
                         double plateau_length, double end_x) {
  PWSIM_DEMAND(start_x > 0.0 && ramp_length > 0.0 && plateau_length >= 0.0);
  const double top_start = start_x + ramp_length;
  const double top_end = top_start + plateau_length;
  const double down_end = top_end + ramp_length;
  PWSIM_DEMAND(end_x > down_end);
  return Terrain{{0.0, start_x, top_start, top_end, down_end, end_x},
                 {0.0, 0.0, height, height, 0.0, 0.0}};
}

Terrain ParseTerrainProfile(YamlMap& map) {
  YAML::Node points = map.Sequence("profile_m");
  const std::string field = map.FieldName("profile_m");
  const std::string file = map.file().string();
  if (points.size() < 2) {
    throw InputError(file, LineOf(points), field, "at least 2 [x_m, z_m] points",
                     std::to_string(points.size()) + " points");
  }
  Terrain terrain;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string item = field + "[" + std::to_string(i) + "]";
    if (!points[i].IsSequence() || points[i].size() != 2) {
      throw InputError(file, LineOf(points[i]), item, "a pair [x_m, z_m]", "something else");
    }
    const double x = ScalarNumber(points[i][0], map.file(), item + "[0]", Range::Any("m"));
    const double z = ScalarNumber(points[i][1], map.file(), item + "[1]",
                                  Range::Closed(-1.0, 1.0, "m"));
    if (!terrain.x.empty() && !(x > terrain.x.back())) {
      std::ostringstream got;
      got << x << " after " << terrain.x.back();
      throw InputError(file, LineOf(points[i]), item + "[0]", "x strictly increasing", got.str());
    }
    terrain.x.push_back(x);
    terrain.z.push_back(z);
  }
  return terrain;
}

Terrain ReadTerrainFile(const std::filesystem::path& file) {
  return ReadTaggedYamlFile(file, "pwsim-terrain/1", ParseTerrainProfile);
}

void WriteTerrainFile(const Terrain& terrain, const std::filesystem::path& file) {
  std::string text = "format: pwsim-terrain/1\nprofile_m: [";
  for (std::size_t i = 0; i < terrain.x.size(); ++i) {
    text += (i == 0 ? "[" : ", [") + FormatDouble(terrain.x[i]) + ", " +
            FormatDouble(terrain.z[i]) + "]";
  }
  text += "]\n";
  WriteFileAtomically(file, text);
}

}  // namespace pwsim
