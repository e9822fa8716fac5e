#include "render/render_scene.h"

#include <algorithm>
#include <cmath>

namespace pwsim::render {
namespace {

using Eigen::Vector3d;

Quad MakeQuad(Vector3d a, Vector3d b, Vector3d c, Vector3d d, Rgb color, TextureKind texture,
              double tile, bool world_uv = false) {
  return Quad{{a, b, c, d}, color, texture, tile, world_uv};
}

/// The six faces of an axis-aligned box [lo, hi], facing outwards.
void AddBox(std::vector<Quad>* quads, const Vector3d& lo, const Vector3d& hi, Rgb color) {
  const double x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
  const auto none = TextureKind::kNone;
  quads->push_back(
      MakeQuad({x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}, color, none, 1));
  quads->push_back(
      MakeQuad({x0, y1, z0}, {x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, color, none, 1));
  quads->push_back(
      MakeQuad({x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1}, color, none, 1));
  quads->push_back(
      MakeQuad({x1, y0, z0}, {x0, y0, z0}, {x0, y0, z1}, {x1, y0, z1}, color, none, 1));
  quads->push_back(
      MakeQuad({x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}, color, none, 1));
  quads->push_back(
      MakeQuad({x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}, {x0, y0, z0}, color, none, 1));
}

/// A wheel as a thin octagonal disc standing in the x-z plane, centred at (x, y, r).
void AddWheel(std::vector<Quad>* quads, double x, double y, double radius, double thickness) {
  const Rgb tyre{0.12F, 0.12F, 0.13F};
  constexpr int kSides = 8;
  for (int i = 0; i < kSides; ++i) {
    const double a0 = 2.0 * M_PI * i / kSides;
    const double a1 = 2.0 * M_PI * (i + 1) / kSides;
    const Vector3d p0(x + radius * std::cos(a0), 0.0, radius + radius * std::sin(a0));
    const Vector3d p1(x + radius * std::cos(a1), 0.0, radius + radius * std::sin(a1));
    const Vector3d half(0.0, thickness / 2.0, 0.0);
    const Vector3d centre(x, y, radius);
    const Vector3d q0 = p0 + Vector3d(0, y, 0), q1 = p1 + Vector3d(0, y, 0);
    // Tread strip and the two flat sides (as degenerate quads: a triangle fan slice each).
    quads->push_back(
        MakeQuad(q0 + half, q0 - half, q1 - half, q1 + half, tyre, TextureKind::kNone, 1));
    quads->push_back(
        MakeQuad(centre + half, q0 + half, q1 + half, centre + half, tyre, TextureKind::kNone, 1));
    quads->push_back(
        MakeQuad(centre - half, q1 - half, q0 - half, centre - half, tyre, TextureKind::kNone, 1));
  }
}

/// The chair in V (x forward, y left, z up; O_V on the ground under the drive axle): wheels at
/// the chair's contact points, a base, a seat, a backrest, armrests and a footrest.
void AddChairBody(std::vector<Quad>* quads, const Chair& chair) {
  double front = 0.4, rear = -0.4;
  for (const Wheel& w : chair.wheels) {
    AddWheel(quads, w.x, 0.30, w.radius, 0.06);
    AddWheel(quads, w.x, -0.30, w.radius, 0.06);
    front = std::max(front, w.x + w.radius);
    rear = std::min(rear, w.x - w.radius);
  }
  const Rgb frame{0.20F, 0.22F, 0.26F}, seat{0.15F, 0.25F, 0.55F};
  AddBox(quads, {rear + 0.05, -0.26, 0.15}, {front - 0.05, 0.26, 0.35}, frame);
  AddBox(quads, {-0.25, -0.24, 0.45}, {0.25, 0.24, 0.53}, seat);
  AddBox(quads, {-0.33, -0.24, 0.53}, {-0.25, 0.24, 1.05}, seat);
  AddBox(quads, {-0.20, 0.24, 0.70}, {0.20, 0.30, 0.75}, frame);
  AddBox(quads, {-0.20, -0.30, 0.70}, {0.20, -0.24, 0.75}, frame);
  AddBox(quads, {front - 0.05, -0.18, 0.10}, {front + 0.10, 0.18, 0.14}, frame);
  AddBox(quads, {0.16, -0.32, 0.75}, {0.20, -0.28, 0.85},
         Rgb{0.05F, 0.05F, 0.05F});  // joystick
}

}  // namespace

void AddPrism(std::vector<Quad>* quads, const std::vector<Eigen::Vector2d>& base, double z0,
              double z1, Rgb color, TextureKind texture, double tile) {
  const std::size_t n = base.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = base[i];
    const Eigen::Vector2d& b = base[(i + 1) % n];
    quads->push_back(MakeQuad({a.x(), a.y(), z0}, {b.x(), b.y(), z0}, {b.x(), b.y(), z1},
                              {a.x(), a.y(), z1}, color, texture, tile));
  }
  // top: a fan of quads from the first corner (a quad is a triangle when two corners meet)
  for (std::size_t i = 1; i + 1 < n; i += 2) {
    const Eigen::Vector2d& c = base[std::min(i + 2, n - 1)];
    quads->push_back(MakeQuad({base[0].x(), base[0].y(), z1}, {base[i].x(), base[i].y(), z1},
                              {base[i + 1].x(), base[i + 1].y(), z1}, {c.x(), c.y(), z1}, color,
                              texture, tile));
  }
}

void AddWall(std::vector<Quad>* quads, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
             double thickness, double z0, double z1, Rgb color, TextureKind texture) {
  const Eigen::Vector2d d = b - a;
  if (!(d.norm() > 0.0)) return;
  const Eigen::Vector2d side = Eigen::Vector2d(-d.y(), d.x()).normalized() * (thickness / 2.0);
  AddPrism(quads, {a - side, b - side, b + side, a + side}, z0, z1, color, texture, 2.0);
}

void AddYawedBox(std::vector<Quad>* quads, const Eigen::Vector2d& centre, double hx, double hy,
                 double yaw, double z0, double z1, Rgb color) {
  const Eigen::Vector2d u(std::cos(yaw) * hx, std::sin(yaw) * hx);
  const Eigen::Vector2d v(-std::sin(yaw) * hy, std::cos(yaw) * hy);
  AddPrism(quads, {centre - u - v, centre + u - v, centre + u + v, centre - u + v}, z0, z1, color);
}

void AddRelief(std::vector<Quad>* quads, const ReliefGrid& grid, Rgb color, TextureKind texture,
               double flat, Rgb floor_color) {
  const int nx = static_cast<int>(grid.x.size()), ny = static_cast<int>(grid.y.size());
  if (nx < 2 || ny < 2 || grid.z.size() != grid.x.size() * grid.y.size()) return;
  auto at = [&](int i, int j) {
    return Vector3d(grid.x[static_cast<std::size_t>(i)], grid.y[static_cast<std::size_t>(j)],
                    grid.z[static_cast<std::size_t>(j) * grid.x.size() + static_cast<std::size_t>(i)]);
  };
  auto off_floor = [&](const Vector3d& p) { return p.z() != flat; };
  for (int j = 0; j + 1 < ny; ++j) {
    int run_start = -1;  // first cell of the current run on the floor
    for (int i = 0; i + 1 <= nx; ++i) {
      const bool last = i + 1 == nx;
      const bool relief = !last && (off_floor(at(i, j)) || off_floor(at(i + 1, j)) ||
                                    off_floor(at(i + 1, j + 1)) || off_floor(at(i, j + 1)));
      if ((relief || last) && run_start >= 0) {  // the run of floor cells ends before cell i
        quads->push_back(MakeQuad(at(run_start, j), at(i, j), at(i, j + 1), at(run_start, j + 1),
                                  floor_color, TextureKind::kFloor, 1.0, true));
        run_start = -1;
      }
      if (last) break;
      if (relief) {
        quads->push_back(
            MakeQuad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), color, texture, 0.5, true));
      } else if (run_start < 0) {
        run_start = i;
      }
    }
  }
  // skirts along the border, between the floor around and the relief where it is off the floor
  // (up to a raised edge, down into a dip), facing outwards either way
  const Rgb side{color.r * 0.8F, color.g * 0.8F, color.b * 0.8F};
  auto skirt = [&](const Vector3d& p, const Vector3d& q) {
    if (!(off_floor(p) || off_floor(q))) return;
    const Vector3d p0(p.x(), p.y(), flat), q0(q.x(), q.y(), flat);
    const bool up = std::max(p.z(), q.z()) > flat;
    quads->push_back(up ? MakeQuad(p0, q0, q, p, side, TextureKind::kNone, 1.0)
                        : MakeQuad(q0, p0, p, q, side, TextureKind::kNone, 1.0));
  };
  for (int i = 0; i + 1 < nx; ++i) {
    skirt(at(i, 0), at(i + 1, 0));
    skirt(at(i + 1, ny - 1), at(i, ny - 1));
  }
  for (int j = 0; j + 1 < ny; ++j) {
    skirt(at(nx - 1, j), at(nx - 1, j + 1));
    skirt(at(0, j + 1), at(0, j));
  }
}

void AddHeightField(std::vector<Quad>* quads, const HeightGrid& grid, Rgb color, TextureKind texture,
                    double flat, Rgb floor_color) {
  if (grid.nx < 2 || grid.ny < 2 ||
      grid.z.size() != static_cast<std::size_t>(grid.nx) * static_cast<std::size_t>(grid.ny)) {
    return;
  }
  ReliefGrid relief;
  for (int i = 0; i < grid.nx; ++i) relief.x.push_back(grid.x0 + i * grid.cell);
  for (int j = 0; j < grid.ny; ++j) relief.y.push_back(grid.y0 + j * grid.cell);
  relief.z = grid.z;
  AddRelief(quads, relief, color, texture, flat, floor_color);
}

std::vector<double> FloorGridLines(const FloorMap& map, bool along_x, double lo, double hi,
                                   double cell) {
  std::vector<double> lines{lo, hi};
  if (!(hi > lo) || !(cell > 0.0)) return {lo};
  const int steps = static_cast<int>(std::ceil((hi - lo) / cell));
  for (int k = 1; k < steps; ++k) lines.push_back(lo + k * cell);
  auto add = [&](double u) {
    if (u > lo && u < hi) lines.push_back(u);
  };
  if (along_x) {
    for (double x : map.profile.x) add(x);
  }
  for (const FloorFeature& f : map.features) {
    const double u_min = along_x ? f.x_min : f.y_min, u_max = along_x ? f.x_max : f.y_max;
    add(u_min);
    add(u_max);
    if (f.ramp > 0.0) {
      add(std::min(u_min + f.ramp, u_max));
      add(std::max(u_max - f.ramp, u_min));
    } else {
      add(u_min - kStepFaceRun);
      add(u_max + kStepFaceRun);
    }
  }
  if (map.grid) {
    const HeightGrid& g = *map.grid;
    const int n = along_x ? g.nx : g.ny;
    for (int k = 0; k < n; ++k) add((along_x ? g.x0 : g.y0) + k * g.cell);
  }
  std::sort(lines.begin(), lines.end());
  std::vector<double> out;
  for (double u : lines) {
    if (out.empty() || u - out.back() > 1e-9) out.push_back(u);
  }
  out.back() = hi;  // the end stays exact (a line within 1e-9 below it merged into it)
  return out;
}

ReliefGrid SampleFloorRelief(const FloorMap& map, const Eigen::AlignedBox2d& box, double cell) {
  ReliefGrid grid;
  grid.x = FloorGridLines(map, true, box.min().x(), box.max().x(), cell);
  grid.y = FloorGridLines(map, false, box.min().y(), box.max().y(), cell);
  grid.z.resize(grid.x.size() * grid.y.size());
  for (std::size_t j = 0; j < grid.y.size(); ++j) {
    for (std::size_t i = 0; i < grid.x.size(); ++i) {
      grid.z[j * grid.x.size() + i] = map.HeightAt(grid.x[i], grid.y[j]);
    }
  }
  return grid;
}

void AddFloorAround(std::vector<Quad>* quads, const Eigen::AlignedBox2d& floor,
                    const Eigen::AlignedBox2d& hole, double z, Rgb color) {
  const double x0 = floor.min().x(), y0 = floor.min().y(), x1 = floor.max().x(), y1 = floor.max().y();
  const double hx0 = hole.min().x(), hy0 = hole.min().y(), hx1 = hole.max().x(), hy1 = hole.max().y();
  auto add = [&](double ax, double ay, double bx, double by) {
    if (bx > ax && by > ay) {
      quads->push_back(MakeQuad({ax, ay, z}, {bx, ay, z}, {bx, by, z}, {ax, by, z}, color,
                                TextureKind::kFloor, 1.0, true));
    }
  };
  add(x0, y0, x1, hy0);    // in front of the hole (−y side)
  add(x0, hy1, x1, y1);    // behind it
  add(x0, hy0, hx0, hy1);  // left of it (−x)
  add(hx1, hy0, x1, hy1);  // right of it
}

Eigen::Vector3d QuadNormal(const Quad& quad) {
  const Vector3d n = (quad.corners[1] - quad.corners[0]).cross(quad.corners[2] - quad.corners[0]);
  return n.norm() > 0.0 ? Vector3d(n.normalized()) : Vector3d(0, 0, 1);
}

RenderScene BuildRenderScene(const Scene& scene, const RenderConfig& config) {
  RenderScene out;
  out.texture_seed = config.texture_seed;

  // Room: x from -2 m to length - 2 m (scene.h), y across, z up; faces point inwards.
  const double x0 = -2.0, x1 = scene.room.length - 2.0;
  const double y0 = -scene.room.width / 2.0, y1 = scene.room.width / 2.0;
  const double z1 = scene.room.height;
  out.room_min_W = Eigen::Vector3d(x0, y0, 0.0);
  out.room_max_W = Eigen::Vector3d(x1, y1, z1);
  const Rgb floor{0.85F, 0.80F, 0.72F}, wall{0.90F, 0.90F, 0.88F}, ceiling{0.95F, 0.95F, 0.95F};
  out.world.push_back(MakeQuad({x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}, floor,
                               TextureKind::kFloor, 1.0));
  out.world.push_back(MakeQuad({x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1}, {x0, y0, z1}, ceiling,
                               TextureKind::kCeiling, 1.5));
  out.world.push_back(MakeQuad({x1, y0, 0}, {x1, y1, 0}, {x1, y1, z1}, {x1, y0, z1}, wall,
                               TextureKind::kWall, 2.0));  // far wall, ahead of the chair
  out.world.push_back(MakeQuad({x0, y1, 0}, {x0, y0, 0}, {x0, y0, z1}, {x0, y1, z1}, wall,
                               TextureKind::kWall, 2.0));  // wall behind
  out.world.push_back(MakeQuad({x0, y0, 0}, {x1, y0, 0}, {x1, y0, z1}, {x0, y0, z1},
                               Rgb{0.86F, 0.88F, 0.92F}, TextureKind::kWall, 2.0));  // right
  out.world.push_back(MakeQuad({x1, y1, 0}, {x0, y1, 0}, {x0, y1, z1}, {x1, y1, z1},
                               Rgb{0.92F, 0.88F, 0.84F}, TextureKind::kWall, 2.0));  // left

  // Speed cushion: each raised segment of the terrain profile becomes a top face and two sides;
  // a skirt along each ramp closes it. Lifted 1 mm to stay clear of the floor's depth.
  const double half_width = std::min(config.cushion_width, scene.room.width) / 2.0;
  const Rgb cushion{0.95F, 0.55F, 0.15F};
  const std::vector<double>& xs = scene.terrain.x;
  const std::vector<double>& zs = scene.terrain.z;
  constexpr double kLift = 0.001;
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    if (zs[i] <= 0.0 && zs[i + 1] <= 0.0) continue;
    const double xa = xs[i], xb = xs[i + 1], za = zs[i] + kLift, zb = zs[i + 1] + kLift;
    out.world.push_back(MakeQuad({xa, -half_width, za}, {xb, -half_width, zb}, {xb, half_width, zb},
                                 {xa, half_width, za}, cushion, TextureKind::kCushion, 0.5));
    const Rgb side{0.75F, 0.40F, 0.10F};
    out.world.push_back(MakeQuad({xa, -half_width, 0}, {xb, -half_width, 0}, {xb, -half_width, zb},
                                 {xa, -half_width, za}, side, TextureKind::kNone, 1));
    out.world.push_back(MakeQuad({xb, half_width, 0}, {xa, half_width, 0}, {xa, half_width, za},
                                 {xb, half_width, zb}, side, TextureKind::kNone, 1));
  }

  AddChairBody(&out.chair, scene.chair);
  return out;
}

RenderScene BuildCircuitRenderScene(const Scene& scene, const RenderConfig& config,
                                    double relief_cell) {
  const CircuitSpec& circuit = *scene.circuit;
  RenderScene out;
  out.texture_seed = config.texture_seed;
  out.clear_color = Rgb{0.62F, 0.74F, 0.86F};  // sky; room_min/max stay 0: the view is cleared

  // The circuit's extent: everything placed in it, plus a margin.
  Eigen::AlignedBox2d box;
  box.extend(Eigen::Vector2d(circuit.start.x, circuit.start.y));
  for (const Wall& w : circuit.walls) {
    box.extend(Eigen::Vector2d(w.from.x, w.from.y));
    box.extend(Eigen::Vector2d(w.to.x, w.to.y));
  }
  for (const Obstacle& o : circuit.obstacles) box.extend(Eigen::Vector2d(o.centre.x, o.centre.y));
  for (const Gate& g : circuit.gates) {
    box.extend(Eigen::Vector2d(g.left.x, g.left.y));
    box.extend(Eigen::Vector2d(g.right.x, g.right.y));
  }
  for (const Point2& p : circuit.joystick.path) box.extend(Eigen::Vector2d(p.x, p.y));
  constexpr double kMargin = 3.0;
  const Eigen::Vector2d lo = box.min() - Eigen::Vector2d(kMargin, kMargin);
  const Eigen::Vector2d hi = box.max() + Eigen::Vector2d(kMargin, kMargin);
  const Rgb floor{0.85F, 0.80F, 0.72F};

  // Floor relief: every layer of the floor map, sampled where it can be non-zero.
  Eigen::AlignedBox2d relief;
  const FloorMap& map = circuit.floor;
  if (!map.profile.x.empty()) {
    relief.extend(Eigen::Vector2d(map.profile.x.front(), lo.y()));
    relief.extend(Eigen::Vector2d(map.profile.x.back(), hi.y()));
  }
  for (const FloorFeature& f : map.features) {
    relief.extend(Eigen::Vector2d(f.x_min, f.y_min));
    relief.extend(Eigen::Vector2d(f.x_max, f.y_max));
  }
  if (map.grid) {
    relief.extend(Eigen::Vector2d(map.grid->x0, map.grid->y0));
    relief.extend(Eigen::Vector2d(map.grid->x0 + (map.grid->nx - 1) * map.grid->cell,
                                  map.grid->y0 + (map.grid->ny - 1) * map.grid->cell));
  }
  // The floor: the relief grid (its cells on the floor drawn as floor) and the floor around it.
  const Eigen::AlignedBox2d whole(lo, hi);
  Eigen::AlignedBox2d hole;  // empty: no relief
  if (!relief.isEmpty()) {
    relief = relief.intersection(whole);
    const Eigen::Vector2d size = relief.sizes();
    double cell = relief_cell;
    while ((size.x() / cell + 2) * (size.y() / cell + 2) > 250000.0) cell *= 1.5;  // bounded
    const ReliefGrid grid = SampleFloorRelief(map, relief, cell);
    if (grid.x.size() >= 2 && grid.y.size() >= 2) {
      AddRelief(&out.world, grid, Rgb{0.95F, 0.55F, 0.15F}, TextureKind::kCushion, 0.0, floor);
      hole = Eigen::AlignedBox2d(Eigen::Vector2d(grid.x.front(), grid.y.front()),
                                 Eigen::Vector2d(grid.x.back(), grid.y.back()));
    }
  }
  if (hole.isEmpty()) hole = Eigen::AlignedBox2d(lo, lo);  // a point: the floor is whole
  AddFloorAround(&out.world, whole, hole, 0.0, floor);

  // Walls, obstacles, gates.
  const double wall_height = scene.room.height;
  for (std::size_t i = 0; i < circuit.walls.size(); ++i) {
    const Wall& w = circuit.walls[i];
    const Rgb wall = i % 2 == 0 ? Rgb{0.90F, 0.90F, 0.88F} : Rgb{0.86F, 0.88F, 0.92F};
    AddWall(&out.world, {w.from.x, w.from.y}, {w.to.x, w.to.y}, w.thickness, 0.0, wall_height,
            wall);
  }
  const Rgb obstacle{0.20F, 0.45F, 0.75F};
  for (const Obstacle& o : circuit.obstacles) {
    if (o.shape == Obstacle::Shape::kBox) {
      AddYawedBox(&out.world, {o.centre.x, o.centre.y}, o.half_length, o.half_width, o.yaw, 0.0,
                  o.height, obstacle);
      continue;
    }
    std::vector<Eigen::Vector2d> base;
    constexpr int kSides = 16;
    for (int k = 0; k < kSides; ++k) {
      const double a = 2.0 * M_PI * k / kSides;
      base.emplace_back(o.centre.x + o.radius * std::cos(a), o.centre.y + o.radius * std::sin(a));
    }
    AddPrism(&out.world, base, 0.0, o.height, obstacle);
  }
  const Rgb post{0.10F, 0.60F, 0.25F};
  for (const Gate& g : circuit.gates) {
    const Eigen::Vector2d l(g.left.x, g.left.y), r(g.right.x, g.right.y);
    AddYawedBox(&out.world, l, 0.03, 0.03, 0.0, 0.0, 1.2, post);
    AddYawedBox(&out.world, r, 0.03, 0.03, 0.0, 0.0, 1.2, post);
    const Eigen::Vector2d d = r - l;
    if (!(d.norm() > 0.0)) continue;
    const Eigen::Vector2d across = Eigen::Vector2d(-d.y(), d.x()).normalized() * 0.03;
    const double z = std::max(map.HeightAt(l.x(), l.y()), map.HeightAt(r.x(), r.y())) + 0.002;
    out.world.push_back(MakeQuad({l.x() - across.x(), l.y() - across.y(), z},
                                 {r.x() - across.x(), r.y() - across.y(), z},
                                 {r.x() + across.x(), r.y() + across.y(), z},
                                 {l.x() + across.x(), l.y() + across.y(), z}, post,
                                 TextureKind::kNone, 1.0));
  }
  AddChairBody(&out.chair, scene.chair);
  return out;
}

}  // namespace pwsim::render
