#include "render/road_scene.h"

#include <cmath>

namespace pwsim::render {
namespace {

using Eigen::Vector3d;

Quad Make(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d, Rgb color,
          TextureKind texture = TextureKind::kNone, double tile = 1.0) {
  return Quad{{a, b, c, d}, color, texture, tile};
}

/// The centre line resampled every `step` metres, with a unit left normal at each point
/// (the mean of the neighbouring segments' normals, so strips join without gaps).
struct Strip {
  std::vector<Vector3d> p;
  std::vector<Vector3d> n;
  std::vector<double> s;  ///< arc length [m]
};

Strip Resample(const std::vector<std::array<double, 2>>& centre, double step) {
  Strip out;
  if (centre.size() < 2) return out;
  std::vector<double> cum(centre.size(), 0.0);
  for (std::size_t i = 1; i < centre.size(); ++i) {
    cum[i] = cum[i - 1] + std::hypot(centre[i][0] - centre[i - 1][0], centre[i][1] - centre[i - 1][1]);
  }
  const double length = cum.back();
  const int count = std::max(1, static_cast<int>(std::ceil(length / step)));
  std::size_t seg = 1;
  for (int k = 0; k <= count; ++k) {
    const double s = length * k / count;
    while (seg + 1 < centre.size() && cum[seg] < s) ++seg;
    const double w = cum[seg] > cum[seg - 1] ? (s - cum[seg - 1]) / (cum[seg] - cum[seg - 1]) : 0.0;
    out.p.emplace_back(centre[seg - 1][0] + w * (centre[seg][0] - centre[seg - 1][0]),
                       centre[seg - 1][1] + w * (centre[seg][1] - centre[seg - 1][1]), 0.0);
    out.s.push_back(s);
  }
  const std::size_t n = out.p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vector3d a = out.p[i == 0 ? 0 : i - 1];
    const Vector3d b = out.p[i + 1 < n ? i + 1 : n - 1];
    Vector3d t = b - a;
    t.z() = 0.0;
    t = t.norm() > 0.0 ? Vector3d(t.normalized()) : Vector3d(1, 0, 0);
    out.n.emplace_back(-t.y(), t.x(), 0.0);
  }
  return out;
}

/// A band between lateral offsets lo < hi (left positive) along the strip at height z; `keep`
/// decides per segment (dashes).
template <typename Keep>
void AddBand(std::vector<Quad>* quads, const Strip& strip, double lo, double hi, double z, Rgb color,
             TextureKind texture, double tile, Keep keep) {
  const Vector3d up(0, 0, z);
  for (std::size_t i = 0; i + 1 < strip.p.size(); ++i) {
    if (!keep(0.5 * (strip.s[i] + strip.s[i + 1]))) continue;
    const Vector3d r0 = strip.p[i] + lo * strip.n[i] + up, l0 = strip.p[i] + hi * strip.n[i] + up;
    const Vector3d r1 = strip.p[i + 1] + lo * strip.n[i + 1] + up, l1 = strip.p[i + 1] + hi * strip.n[i + 1] + up;
    quads->push_back(Make(r0, r1, l1, l0, color, texture, tile));  // counter-clockwise from above
  }
}

void AddCone(std::vector<Quad>* quads, double x, double y) {
  const Rgb orange{0.95F, 0.45F, 0.08F};
  const double half = 0.17, height = 0.7;
  const Vector3d apex(x, y, height);
  const Vector3d c[4] = {{x - half, y - half, 0.0}, {x + half, y - half, 0.0}, {x + half, y + half, 0.0},
                         {x - half, y + half, 0.0}};
  for (int i = 0; i < 4; ++i) quads->push_back(Make(c[i], c[(i + 1) % 4], apex, apex, orange));
}

}  // namespace

RenderScene BuildRoadScene(const RoadGeometry& road, const CabinGeometry& cabin, std::uint32_t texture_seed) {
  RenderScene out;
  out.texture_seed = texture_seed;
  out.clear_color = Rgb{0.62F, 0.76F, 0.92F};  // sky
  out.light_dir_W = Vector3d(0.3, 0.2, 1.0);
  // no closed room: the renderer clears every frame (room_min == room_max)

  // ground around the road, textured so that its optical flow shows speed
  double cx = 0.0, cy = 0.0;
  for (const auto& p : road.centre) {
    cx += p[0];
    cy += p[1];
  }
  if (!road.centre.empty()) {
    cx /= static_cast<double>(road.centre.size());
    cy /= static_cast<double>(road.centre.size());
  }
  const double g = road.ground_half_size;
  out.world.push_back(Make({cx - g, cy - g, 0}, {cx + g, cy - g, 0}, {cx + g, cy + g, 0}, {cx - g, cy + g, 0},
                           Rgb{0.42F, 0.58F, 0.30F}, TextureKind::kFloor, 3.0));

  const Strip strip = Resample(road.centre, 2.0);
  const double w = road.lane_width;
  const double right = -0.5 * w;
  const double left = (road.lanes - 0.5) * w;
  auto all = [](double) { return true; };
  AddBand(&out.world, strip, right - 0.5, left + 0.5, 0.01, Rgb{0.36F, 0.36F, 0.37F}, TextureKind::kFloor, 1.0, all);
  const Rgb paint{0.95F, 0.95F, 0.93F};
  AddBand(&out.world, strip, right - 0.2, right - 0.08, 0.02, paint, TextureKind::kNone, 1.0, all);
  AddBand(&out.world, strip, left + 0.08, left + 0.2, 0.02, paint, TextureKind::kNone, 1.0, all);
  for (int lane = 1; lane < road.lanes; ++lane) {
    const double y = right + lane * w;
    AddBand(&out.world, strip, y - 0.06, y + 0.06, 0.02, paint, TextureKind::kNone, 1.0,
            [](double s) { return std::fmod(s, 12.0) < 4.0; });  // 4 m dash, 8 m gap
  }
  for (const auto& c : road.cones) AddCone(&out.world, c[0], c[1]);

  // cabin in V (origin at the CoG): bonnet, dashboard top, two A-pillars and the roof edge
  const double z0 = -cabin.cg_height;
  const double hw = cabin.half_width;
  const double xs = cabin.windscreen_x;
  const Rgb body{0.12F, 0.22F, 0.45F}, dash{0.08F, 0.08F, 0.09F};
  out.chair.push_back(Make({xs, -hw, z0 + 0.95}, {cabin.front, -hw, z0 + 0.8}, {cabin.front, hw, z0 + 0.8},
                           {xs, hw, z0 + 0.95}, body));
  out.chair.push_back(Make({xs - 0.35, -hw, z0 + 1.0}, {xs, -hw, z0 + 1.0}, {xs, hw, z0 + 1.0},
                           {xs - 0.35, hw, z0 + 1.0}, dash));
  for (double side : {-1.0, 1.0}) {
    const double y0 = side * hw, y1 = side * (hw - 0.08);
    out.chair.push_back(Make({xs, y0, z0 + 0.95}, {xs - 0.55, y0, z0 + 1.45}, {xs - 0.55, y1, z0 + 1.45},
                             {xs, y1, z0 + 0.95}, dash));
  }
  out.chair.push_back(Make({xs - 0.55, -hw, z0 + 1.45}, {xs - 0.75, -hw, z0 + 1.45}, {xs - 0.75, hw, z0 + 1.45},
                           {xs - 0.55, hw, z0 + 1.45}, dash));
  return out;
}

Eigen::Isometry3d CarPose(double x, double y, double cg_height, double yaw, double roll, double pitch) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Vector3d(x, y, cg_height);
  X.linear() = (Eigen::AngleAxisd(yaw, Vector3d::UnitZ()) * Eigen::AngleAxisd(-pitch, Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Vector3d::UnitX()))
                   .toRotationMatrix();
  return X;
}

Eigen::Isometry3d EyePoseInCar(const Eigen::Isometry3d& X_WV, const std::array<double, 3>& head_offset) {
  Eigen::Isometry3d X_VC = Eigen::Isometry3d::Identity();
  X_VC.translation() = Vector3d(head_offset[0], head_offset[1], head_offset[2]);
  return X_WV * X_VC;
}

}  // namespace pwsim::render
