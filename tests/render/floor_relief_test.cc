// Circuit floors drawn as the physics sees them: the rendered relief of a floor map with every
// kind of layer (a profile ramp, a threshold, a sharp level change, a dip, a tapered
// cross-slope, a rib mat) is held against FloorMap::HeightAt, the height the wheels meet: at
// every drawn vertex exactly, and between vertices on the triangles the renderer draws.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "engine/scene.h"
#include "render/render_scene.h"

namespace pwsim::render {
namespace {

/// A floor with every layer; the features' numbers are those of the shipped circuit and skill
/// scenes (threshold 2 cm, level change 5 cm sharp, side slope 8.7 % tapered over 0.5 m).
FloorMap EveryLayer() {
  FloorMap map;
  map.profile.x = {4.0, 6.0, 8.0, 10.0};  // a 15 % ramp up 0.3 m, a landing, a ramp down
  map.profile.z = {0.0, 0.3, 0.3, 0.0};
  map.features.push_back(BumpFeature(2.96, 3.04, -1.5, 1.5, 0.02, 0.02));   // threshold
  map.features.push_back(BumpFeature(12.0, 14.0, -1.0, 1.0, 0.05, 0.0));    // level change
  map.features.push_back(BumpFeature(15.0, 16.0, -2.0, -1.0, -0.08, 0.01)); // dip
  map.features.push_back(PlaneFeature(17.0, 21.0, -2.0, 2.0, 0.0, 0.08749, 0.5));  // side slope
  HeightGrid ribs;  // a rubber mat, ribs 1 cm high every other 0.25 m
  ribs.x0 = -1.0;
  ribs.y0 = -2.0;
  ribs.cell = 0.25;
  ribs.nx = 7;
  ribs.ny = 5;
  ribs.z.assign(35, 0.0);
  for (int j = 1; j < 4; ++j) {
    for (int i = 1; i < 6; i += 2) ribs.z[static_cast<std::size_t>(j * 7 + i)] = 0.01;
  }
  map.grid = ribs;
  return map;
}

Scene CircuitOver(const FloorMap& map) {
  Scene scene;
  scene.circuit = CircuitSpec{};
  scene.circuit->floor = map;
  scene.circuit->walls.push_back(Wall{{-1.0, -2.5}, {23.0, -2.5}, 0.1, "right"});
  scene.circuit->walls.push_back(Wall{{-1.0, 2.5}, {23.0, 2.5}, 0.1, "left"});
  return scene;
}

/// The drawn height under (x, y): the quad's triangle (0, 1, 2) or (0, 2, 3) that holds the
/// point seen from above, interpolated; NaN when no floor quad holds it.
double DrawnHeight(const std::vector<const Quad*>& floor, double x, double y) {
  for (const Quad* q : floor) {
    double x_lo = q->corners[0].x(), x_hi = x_lo, y_lo = q->corners[0].y(), y_hi = y_lo;
    for (const auto& c : q->corners) {
      x_lo = std::min(x_lo, c.x()), x_hi = std::max(x_hi, c.x());
      y_lo = std::min(y_lo, c.y()), y_hi = std::max(y_hi, c.y());
    }
    if (x < x_lo || x > x_hi || y < y_lo || y > y_hi) continue;
    for (const auto& [a, b, c] : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
      const Eigen::Vector3d &pa = q->corners[a], &pb = q->corners[b], &pc = q->corners[c];
      const double det = (pb.x() - pa.x()) * (pc.y() - pa.y()) - (pc.x() - pa.x()) * (pb.y() - pa.y());
      if (std::abs(det) < 1e-15) continue;
      const double wb = ((x - pa.x()) * (pc.y() - pa.y()) - (pc.x() - pa.x()) * (y - pa.y())) / det;
      const double wc = ((pb.x() - pa.x()) * (y - pa.y()) - (x - pa.x()) * (pb.y() - pa.y())) / det;
      if (wb < -1e-12 || wc < -1e-12 || wb + wc > 1 + 1e-12) continue;
      return pa.z() + wb * (pb.z() - pa.z()) + wc * (pc.z() - pa.z());
    }
  }
  return std::nan("");
}

struct ReliefError {
  double vertex{0.0};  ///< [m] largest |drawn − HeightAt| at a floor vertex
  double between{0.0}; ///< [m] the same at sample points between vertices
  double x{0.0}, y{0.0};
  int samples{0};
};

ReliefError MeasureRelief(const RenderScene& rs, const FloorMap& map) {
  std::vector<const Quad*> floor;
  for (const Quad& q : rs.world) {
    if (q.texture == TextureKind::kFloor || q.texture == TextureKind::kCushion) floor.push_back(&q);
  }
  ReliefError e;
  for (const Quad* q : floor) {
    for (const auto& c : q->corners) e.vertex = std::max(e.vertex, std::abs(c.z() - map.HeightAt(c.x(), c.y())));
  }
  // sample points on a lattice incommensurate with the grid lines (steps 0.0231 m, 0.391 m)
  // over the relief, and just beside each sharp edge
  for (double x = -1.0; x < 22.0; x += 0.0231) {
    for (double y = -2.4; y < 2.4; y += 0.391) {
      const double drawn = DrawnHeight(floor, x, y);
      if (std::isnan(drawn)) continue;
      ++e.samples;
      const double error = std::abs(drawn - map.HeightAt(x, y));
      if (error > e.between) e.between = error, e.x = x, e.y = y;
    }
  }
  return e;
}

// Tests that the circuit render scene draws the floor map: every vertex of a floor or relief
// quad at HeightAt exactly, and between vertices within 1 mm (the drawn triangles against the
// map: the profile, threshold, dip, level change and mat are piecewise bilinear between the
// grid lines, the side slope's taper quadratic). A regular 5 cm grid, the drawing before the
// grid lines followed the breakpoints, misses by up to the level change's 5 cm.
TEST(FloorReliefTest, DrawnFloorIsTheFloorMap) {
  const FloorMap map = EveryLayer();
  const RenderScene rs = BuildCircuitRenderScene(CircuitOver(map), RenderConfig{});
  const ReliefError e = MeasureRelief(rs, map);
  std::printf("floor-map relief: %d samples, vertex error %.3g m, between %.3g m at (%.4f, %.4f)\n",
              e.samples, e.vertex, e.between, e.x, e.y);
  EXPECT_GT(e.samples, 10000);
  EXPECT_EQ(e.vertex, 0.0);
  EXPECT_LT(e.between, 1e-3);

  // the same floor on the regular grid alone (HeightAt at its nodes, as drawn before)
  HeightGrid regular;
  regular.x0 = -1.0;
  regular.y0 = -2.5;
  regular.cell = 0.05;
  regular.nx = 461;
  regular.ny = 101;
  for (int j = 0; j < regular.ny; ++j) {
    for (int i = 0; i < regular.nx; ++i) regular.z.push_back(map.HeightAt(-1.0 + i * 0.05, -2.5 + j * 0.05));
  }
  RenderScene old;
  AddHeightField(&old.world, regular, Rgb{});
  const ReliefError e_old = MeasureRelief(old, map);
  std::printf("regular 5 cm grid: between %.3g m at (%.4f, %.4f)\n", e_old.between, e_old.x, e_old.y);
  EXPECT_GT(e_old.between, 10 * e.between) << "the check no longer tells the two drawings apart";
}

// Tests the grid lines: every taper knot of a feature inside the span, a sharp edge doubled
// kStepFaceRun outside it, the profile's knots along x only, the ends exact, increasing.
TEST(FloorReliefTest, GridLinesFollowTheBreakpoints) {
  const FloorMap map = EveryLayer();
  const std::vector<double> xs = FloorGridLines(map, true, -1.0, 22.0, 0.05);
  const std::vector<double> ys = FloorGridLines(map, false, -2.5, 2.5, 0.05);
  auto has = [](const std::vector<double>& v, double u) {
    return std::any_of(v.begin(), v.end(), [u](double w) { return std::abs(w - u) < 1e-12; });
  };
  for (double x : {2.96, 2.98, 3.02, 3.04, 12.0 - kStepFaceRun, 12.0, 14.0, 14.0 + kStepFaceRun, 15.01, 15.99,
                   17.5, 20.5, 4.0, 6.0, 8.0, 10.0, -0.75, 0.5}) {
    EXPECT_TRUE(has(xs, x)) << x;
  }
  for (double y : {-1.5 + 0.02, -1.0 - kStepFaceRun, 1.0 + kStepFaceRun, -1.99, -1.01, 1.5, -1.75}) {
    EXPECT_TRUE(has(ys, y)) << y;
  }
  EXPECT_EQ(xs.front(), -1.0);
  EXPECT_EQ(xs.back(), 22.0);
  EXPECT_TRUE(std::is_sorted(xs.begin(), xs.end()));
  EXPECT_TRUE(std::adjacent_find(xs.begin(), xs.end()) == xs.end());
  for (std::size_t k = 1; k < xs.size(); ++k) EXPECT_LE(xs[k] - xs[k - 1], 0.05 + 1e-12);
}

}  // namespace
}  // namespace pwsim::render
