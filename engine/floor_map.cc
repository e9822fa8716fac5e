#include "engine/floor_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "engine/input_error.h"
#include "engine/number_format.h"

namespace pwsim {

FloorFeature BumpFeature(double x_min, double x_max, double y_min, double y_max, double height, double ramp) {
  FloorFeature f;
  f.kind = FloorFeature::Kind::kBump;
  f.x_min = x_min;
  f.x_max = x_max;
  f.y_min = y_min;
  f.y_max = y_max;
  f.height = height;
  f.ramp = ramp;
  return f;
}

FloorFeature PlaneFeature(double x_min, double x_max, double y_min, double y_max, double grade_x,
                          double grade_y, double ramp) {
  FloorFeature f = BumpFeature(x_min, x_max, y_min, y_max, 0.0, ramp);
  f.kind = FloorFeature::Kind::kPlane;
  f.grade_x = grade_x;
  f.grade_y = grade_y;
  return f;
}

double HeightGrid::HeightAt(double x_W, double y_W) const {
  const double u = (x_W - x0) / cell;
  const double w = (y_W - y0) / cell;
  if (!(u >= 0.0 && w >= 0.0 && u <= nx - 1 && w <= ny - 1)) return 0.0;
  const int i = std::min(static_cast<int>(u), nx - 2);
  const int j = std::min(static_cast<int>(w), ny - 2);
  const double su = u - i;
  const double sw = w - j;
  const double* row0 = z.data() + static_cast<std::size_t>(j) * nx;
  const double* row1 = row0 + nx;
  const double lower = row0[i] + su * (row0[i + 1] - row0[i]);
  const double upper = row1[i] + su * (row1[i + 1] - row1[i]);
  return lower + sw * (upper - lower);
}

double FloorMap::HeightAt(double x_W, double y_W) const {
  double z = profile.HeightAt(x_W);
  if (features.empty() && !grid) return z;  // the sagittal terrain, bit for bit
  for (const FloorFeature& feature : features) z += feature.HeightAt(x_W, y_W);
  if (grid) z += grid->HeightAt(x_W, y_W);
  return z;
}

double FloorMap::AddLayersNear(double z_profile, double x_W, double y_W, FloorHint& hint) const {
  double z = z_profile;
  // The clear interval around x: bounded by the nearest span ends on either side of x; when one
  // feature's x span holds x (the active one), within that span; empty when x is in the spans
  // of two features, or of the grid (or NaN: every comparison false).
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  int active = -1;
  bool several = false;
  const auto clear_of = [&](double span_lo, double span_hi, int index) {
    if (span_hi < x_W) {
      lo = std::max(lo, span_hi);
    } else if (span_lo > x_W) {
      hi = std::min(hi, span_lo);
    } else {
      several = several || active >= 0 || index < 0;
      active = index;
    }
  };
  for (std::size_t k = 0; k < features.size(); ++k) {
    z += features[k].HeightAt(x_W, y_W);
    clear_of(features[k].x_min, features[k].x_max, static_cast<int>(k));
  }
  if (grid) {
    z += grid->HeightAt(x_W, y_W);
    // grown by a cell: HeightGrid's own test is on (x - x0) / cell, rounded
    clear_of(grid->x0 - grid->cell, grid->x0 + grid->nx * grid->cell, -1);
  }
  if (active >= 0) {  // and within the active feature's span (beyond it, no layer is active)
    lo = std::max(lo, features[static_cast<std::size_t>(active)].x_min);
    hi = std::min(hi, features[static_cast<std::size_t>(active)].x_max);
  }
  hint.clear_lo = several ? x_W : lo;
  hint.clear_hi = several ? x_W : hi;
  hint.active = several ? -1 : active;
  return z;
}

double FloorMap::HeightAtNearUpdatingHint(double x_W, double y_W, FloorHint& hint) const {
  const double z_profile = profile.HeightAtNear(x_W, hint.segment);
  const bool layers = !features.empty() || grid.has_value();
  double z = z_profile;
  const bool clear = x_W > hint.clear_lo && x_W < hint.clear_hi;
  double base = z_profile;  // the sum before the active feature (if any)
  bool plus_zero = false;   // + 0 after it
  if (layers) {
    // In the clear interval every layer but the active feature (if any) adds +0: z + 0 + 0 ...
    // is z + 0 (+0 turns a -0 into +0 once, then changes nothing), so the sum in HeightAt's
    // order is z_profile [+ 0] + f_active [+ 0], the +0 where layers come before or after it.
    if (!clear) {
      z = AddLayersNear(z_profile, x_W, y_W, hint);  // moves the clear interval
    } else if (hint.active < 0) {
      z = z_profile + 0.0;
    }
    if (x_W > hint.clear_lo && x_W < hint.clear_hi && hint.active >= 0) {
      const std::size_t k = static_cast<std::size_t>(hint.active);
      if (k > 0) base += 0.0;
      plus_zero = k + 1 < features.size() || grid.has_value();
      if (clear) {
        z = base + features[k].HeightAt(x_W, y_W);
        if (plus_zero) z += 0.0;
      }
    }
  }
  // The level interval around x: the open piece of the profile x is in when that piece is level
  // (HeightAt is 0 beyond the ends, z_k + 0 on a level segment: Terrain::HeightAtNear), within
  // the clear interval when there are layers; empty otherwise (and for NaN).
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::vector<double>& xs = profile.x;
  const std::vector<double>& zs = profile.z;
  double lo = x_W, hi = x_W;  // empty
  if (xs.empty()) {
    lo = -kInf;
    hi = kInf;
  } else if (x_W < xs.front()) {
    lo = -kInf;
    hi = xs.front();
  } else if (x_W > xs.back()) {
    lo = xs.back();
    hi = kInf;
  } else if (const std::size_t k = hint.segment;
             k + 1 < xs.size() && x_W > xs[k] && x_W < xs[k + 1] && zs[k] == zs[k + 1]) {
    lo = xs[k];
    hi = xs[k + 1];
  }
  int level_feature = -1;
  if (layers) {  // within the clear interval (AddLayersNear may have moved it)
    const bool level = x_W > hint.clear_lo && x_W < hint.clear_hi;
    lo = level ? std::max(lo, hint.clear_lo) : x_W;
    hi = level ? std::min(hi, hint.clear_hi) : x_W;
    level_feature = level ? hint.active : -1;
  }
  hint.level_lo = lo;
  hint.level_hi = hi;
  hint.level_z = level_feature < 0 ? z : base;
  hint.level_feature = level_feature;
  hint.level_plus_zero = plus_zero;
  return z;
}

double FloorMap::MaxHeightBound() const {
  double bound = profile.x.empty() ? 0.0 : profile.MaxHeight();
  for (const FloorFeature& f : features) {
    if (f.kind == FloorFeature::Kind::kBump) {
      bound += std::max(0.0, f.height);
    } else {
      const double xc = f.has_origin ? f.origin_x : 0.5 * (f.x_min + f.x_max);
      const double yc = f.has_origin ? f.origin_y : 0.5 * (f.y_min + f.y_max);
      bound += std::abs(f.grade_x) * std::max(std::abs(f.x_max - xc), std::abs(f.x_min - xc)) +
               std::abs(f.grade_y) * std::max(std::abs(f.y_max - yc), std::abs(f.y_min - yc));
    }
  }
  if (grid) bound += std::max(0.0, *std::max_element(grid->z.begin(), grid->z.end()));
  return bound;
}

bool FloorMap::LinearUnder(double x_W, double y_W, double dir_x, double dir_y, double radius, const FloorHint& hint,
                           double& slope) const {
  const double reach_x = radius * std::abs(dir_x), reach_y = radius * std::abs(dir_y);
  const double lo = x_W - reach_x, hi = x_W + reach_x;
  const bool layers = !features.empty() || grid.has_value();
  // every layer but the active feature adds 0 under the disc
  if (layers && !(lo > hint.clear_lo && hi < hint.clear_hi)) return false;
  double m = 0.0;
  const std::vector<double>& xs = profile.x;
  if (!xs.empty() && !(hi < xs.front() || lo > xs.back())) {
    const std::size_t k = hint.segment;
    if (!(k + 1 < xs.size() && lo > xs[k] && hi < xs[k + 1])) return false;
    m = (profile.z[k + 1] - profile.z[k]) / (xs[k + 1] - xs[k]) * dir_x;
  }
  if (layers && hint.active >= 0) {  // beside its y span (it adds 0), or its taper 1 under the whole disc
    const FloorFeature& f = features[static_cast<std::size_t>(hint.active)];
    if (y_W - reach_y > f.y_max || y_W + reach_y < f.y_min) {
      slope = m;
      return true;
    }
    if (!(lo > f.x_min + f.ramp && hi < f.x_max - f.ramp && y_W - reach_y > f.y_min + f.ramp &&
          y_W + reach_y < f.y_max - f.ramp)) {
      return false;
    }
    if (f.kind == FloorFeature::Kind::kPlane) m += f.grade_x * dir_x + f.grade_y * dir_y;
  }
  slope = m;
  return true;
}

double FloorMap::EnvelopeOffLevel(double x_W, double y_W, double dir_x, double dir_y, double radius, double z_point,
                                  const FloorHint& hint) const {
  double m = 0.0;
  if (LinearUnder(x_W, y_W, dir_x, dir_y, radius, hint, m)) {
    // centre at the tangent point s* = R m / √(1 + m²): z_point + R (√(1 + m²) - 1)
    return m == 0.0 ? z_point : z_point + radius * m * m / (1.0 + std::sqrt(1.0 + m * m));
  }
  // The profile, and at most one bump whose y taper is 1 across the disc (a kerb, threshold or
  // gap crossed along x), under the disc: piecewise linear along x with knots whose heights are
  // known (a sharp edge's two sides both), no other layer meeting the disc's box.
  const double reach_x = radius * std::abs(dir_x), reach_y = radius * std::abs(dir_y);
  const double lo = x_W - reach_x, hi = x_W + reach_x;
  int under = 0;
  const FloorFeature* bump = nullptr;
  for (const FloorFeature& f : features) {
    if (f.x_max < lo || f.x_min > hi || f.y_max < y_W - reach_y || f.y_min > y_W + reach_y) continue;
    ++under;
    bump = &f;
  }
  if (grid) {
    const HeightGrid& g = *grid;
    under += !(g.x0 + g.nx * g.cell < lo || g.x0 - g.cell > hi || g.y0 + g.ny * g.cell < y_W - reach_y ||
               g.y0 - g.cell > y_W + reach_y) ? 2 : 0;
  }
  const std::vector<double>& xs = profile.x;
  const bool beyond_profile = xs.empty() || hi < xs.front() || lo > xs.back();
  if (under == 0 && beyond_profile) return z_point;  // level: z = 0 under it
  const bool profile_ok = beyond_profile || (lo > xs.front() && hi < xs.back() &&
                                              std::lower_bound(xs.begin(), xs.end(), hi) - std::upper_bound(xs.begin(), xs.end(), lo) <
                                                  kEnvelopeBreakpoints - 6);
  const bool bump_ok = under == 0 || (under == 1 && bump->kind == FloorFeature::Kind::kBump &&
                                      y_W - reach_y >= bump->y_min + bump->ramp && y_W + reach_y <= bump->y_max - bump->ramp);
  if (profile_ok && bump_ok && std::abs(dir_x) > 1e-6) {
    // knots in x with the height just below and just above each (left, right)
    struct Knot {
      double x, left, right;
    };
    std::array<Knot, kEnvelopeBreakpoints> knots;
    int n = 0;
    std::size_t segment = hint.segment;
    const auto profile_at = [&](double x) { return beyond_profile ? 0.0 : profile.HeightAtNear(x, segment); };
    const auto bump_at = [&](double x) { return under == 1 ? bump->height * floor_detail::Taper(x, bump->x_min, bump->x_max, bump->ramp) : 0.0; };
    if (!beyond_profile) {
      for (auto it = std::upper_bound(xs.begin(), xs.end(), lo); it != xs.end() && *it < hi && n < kEnvelopeBreakpoints - 6; ++it) {
        if (!(std::abs(*it - x_W) < (radius - 1e-9 * radius) * std::abs(dir_x))) continue;  // within the inset ends
        const double z = profile.z[static_cast<std::size_t>(it - xs.begin())] + bump_at(*it);
        knots[static_cast<std::size_t>(n++)] = {*it, z, z};
      }
    }
    if (under == 1) {
      const FloorFeature& f = *bump;
      const double edges[5] = {f.x_min, f.x_min + f.ramp, f.x_max - f.ramp, f.x_max, 0.5 * (f.x_min + f.x_max)};
      const int count = f.ramp > 0.0 ? (2.0 * f.ramp < f.x_max - f.x_min ? 4 : 5) : 2;
      for (int e = 0; e < count; ++e) {
        const double x = f.ramp > 0.0 ? edges[e] : (e == 0 ? f.x_min : f.x_max);
        if (count == 5 && (e == 1 || e == 2)) continue;  // the ramps meet in the middle
        const double s_knot = (x - x_W) / dir_x;
        if (!(s_knot > -(radius - 1e-9 * radius) && s_knot < radius - 1e-9 * radius)) continue;
        const double base = profile_at(x);
        double left = base + bump_at(x), right = left;
        if (f.ramp <= 0.0) {  // a sharp edge: the floor below it outside, the bump's top inside
          if (e == 0) left = base;
          else right = base;
        }
        knots[static_cast<std::size_t>(n++)] = {x, left, right};
      }
      std::sort(knots.begin(), knots.begin() + n, [](const Knot& p, const Knot& q) { return p.x < q.x; });
    }
    const double r2 = radius * radius;
    const auto candidate = [&](double s, double z) {
      return (z - z_point) - s * s / (radius + std::sqrt(std::max(0.0, r2 - s * s)));
    };
    const bool forward = dir_x > 0.0;
    // the ends just inside the disc (1e-9 R), so that an edge at an end is seen from within
    const double inset = 1e-9 * radius, end_s = radius - inset;
    double best = 0.0;
    double s_prev = -end_s;
    const double start = x_W - end_s * dir_x;
    double z_prev = profile_at(start) + bump_at(start);
    best = std::max(best, candidate(s_prev, z_prev));
    const auto piece = [&](double s, double z_in, double z_out) {  // along s: arriving at z_in, leaving at z_out
      best = std::max(best, std::max(candidate(s, z_in), candidate(s, z_out)));
      if (s > s_prev) {
        const double rise = (z_in - z_prev) / (s - s_prev);
        const double tangent = radius * rise / std::sqrt(1.0 + rise * rise);
        if (tangent > s_prev && tangent < s) best = std::max(best, candidate(tangent, z_prev + rise * (tangent - s_prev)));
      }
      s_prev = s;
      z_prev = z_out;
    };
    for (int j = 0; j < n; ++j) {
      const Knot& k = knots[static_cast<std::size_t>(forward ? j : n - 1 - j)];
      piece((k.x - x_W) / dir_x, forward ? k.left : k.right, forward ? k.right : k.left);
    }
    const double end = x_W + end_s * dir_x;
    const double z_end = profile_at(end) + bump_at(end);
    piece(end_s, z_end, z_end);
    return z_point + best;
  }
  return EnvelopeByBreakpoints(x_W, y_W, dir_x, dir_y, radius, z_point, hint);
}

double FloorMap::EnvelopeByBreakpoints(double x_W, double y_W, double dir_x, double dir_y, double radius,
                                       double z_point, const FloorHint& hint) const {
  FloorHint near = hint;  // the lookups under the disc start from the wheel's own (same bits as HeightAt)
  const double r = radius;
  // Breakpoints s in (-R, R) where the line p + s u crosses a knot of some layer.
  std::array<double, kEnvelopeBreakpoints> knots;  // the first n set (no zeroing: this runs per wheel per tick)
  int n = 0;
  bool overflow = false;
  const auto add = [&](double knot, double origin, double u) {
    if (std::abs(u) < 1e-12) return;  // the line runs along the knot: no crossing
    const double s = (knot - origin) / u;
    if (!(s > -r && s < r)) return;
    if (n == kEnvelopeBreakpoints) {
      overflow = true;
      return;
    }
    knots[static_cast<std::size_t>(n++)] = s;
  };
  const double reach_x = r * std::abs(dir_x), reach_y = r * std::abs(dir_y);
  if (!profile.x.empty()) {
    auto it = std::upper_bound(profile.x.begin(), profile.x.end(), x_W - reach_x);
    for (; it != profile.x.end() && *it < x_W + reach_x; ++it) add(*it, x_W, dir_x);
  }
  const auto add_taper = [&](double lo, double hi, double ramp, double origin, double u) {
    add(lo, origin, u);
    add(hi, origin, u);
    if (ramp > 0.0) {
      if (2.0 * ramp < hi - lo) {
        add(lo + ramp, origin, u);
        add(hi - ramp, origin, u);
      } else {
        add(0.5 * (lo + hi), origin, u);
      }
    }
  };
  for (const FloorFeature& f : features) {
    if (f.x_max < x_W - reach_x || f.x_min > x_W + reach_x || f.y_max < y_W - reach_y || f.y_min > y_W + reach_y) continue;
    add_taper(f.x_min, f.x_max, f.ramp, x_W, dir_x);
    add_taper(f.y_min, f.y_max, f.ramp, y_W, dir_y);
  }
  if (grid) {
    const HeightGrid& g = *grid;
    const auto lines = [&](double origin0, int count, double at, double reach, double u) {
      const int first = std::max(0, static_cast<int>(std::floor((at - reach - origin0) / g.cell)));
      const int last = std::min(count - 1, static_cast<int>(std::ceil((at + reach - origin0) / g.cell)));
      for (int i = first; i <= last; ++i) add(origin0 + i * g.cell, at, u);
    };
    lines(g.x0, g.nx, x_W, reach_x, dir_x);
    lines(g.y0, g.ny, y_W, reach_y, dir_y);
  }
  if (overflow) {  // too many knots under the disc: sample it uniformly instead
    n = kEnvelopeBreakpoints;
    for (int k = 0; k < n; ++k) knots[static_cast<std::size_t>(k)] = -r + 2.0 * r * (k + 1) / (n + 1);
  } else {
    std::sort(knots.begin(), knots.begin() + n);
  }
  // Relative candidate height of the centre: (z(s) - z_point) + (√(R² - s²) - R), the second
  // term written -s² / (R + √(R² - s²)) (exactly 0 at s = 0).
  const double r2 = r * r;
  const auto candidate = [&](double s, double z) { return (z - z_point) - s * s / (r + std::sqrt(std::max(0.0, r2 - s * s))); };
  const double inset = 1e-9 * r;
  double best = 0.0;  // s = 0: the lowest point itself
  double a = -r;
  for (int k = 0; k <= n; ++k) {
    const double b = k < n ? knots[static_cast<std::size_t>(k)] : r;
    const double sa = a + inset, sb = b - inset;
    a = b;
    if (!(sb > sa)) continue;
    const double za = HeightAtNear(x_W + sa * dir_x, y_W + sa * dir_y, near);
    const double zb = HeightAtNear(x_W + sb * dir_x, y_W + sb * dir_y, near);
    best = std::max(best, std::max(candidate(sa, za), candidate(sb, zb)));
    const double m = (zb - za) / (sb - sa);
    const double tangent = r * m / std::sqrt(1.0 + m * m);  // where the line's slope meets the arc's
    if (tangent > sa && tangent < sb) best = std::max(best, candidate(tangent, za + m * (tangent - sa)));
  }
  return z_point + best;
}

FloorMap FloorFromTerrain(const Terrain& terrain) {
  FloorMap floor;
  floor.profile = terrain;
  return floor;
}

namespace {

void ReadInterval(YamlMap& map, const std::string& key, double& lo, double& hi) {
  const std::vector<double> pair = map.Numbers(key, Range::Closed(-1000.0, 1000.0, "m"), 2, 2);
  if (!(pair[1] > pair[0])) {
    map.Fail(key, "[min, max] with max > min", "[" + FormatDouble(pair[0]) + ", " + FormatDouble(pair[1]) + "]");
  }
  lo = pair[0];
  hi = pair[1];
}

FloorFeature ParseFeature(const YAML::Node& node, const YamlMap& parent, const std::string& field) {
  YamlMap entry(node, parent.file(), field, LineOf(node));
  FloorFeature feature;
  const bool bump = entry.Has("bump");
  if (bump == entry.Has("plane")) {
    entry.Fail(bump ? "plane" : "bump", "exactly one of {bump: {...}} or {plane: {...}}",
               bump ? "both" : "neither");
  }
  YamlMap body = entry.Map(bump ? "bump" : "plane");
  feature.kind = bump ? FloorFeature::Kind::kBump : FloorFeature::Kind::kPlane;
  feature.name = body.StringOr("name", "");
  ReadInterval(body, "x_m", feature.x_min, feature.x_max);
  ReadInterval(body, "y_m", feature.y_min, feature.y_max);
  feature.ramp = body.NumberOr("ramp_m", 0.0, Range::Closed(0.0, 50.0, "m"));
  if (bump) {
    feature.height = body.Number("height_m", Range::Closed(-0.5, 0.5, "m"));
  } else {
    feature.grade_x = body.NumberOr("grade_x", 0.0, Range::Closed(-0.5, 0.5));
    feature.grade_y = body.NumberOr("grade_y", 0.0, Range::Closed(-0.5, 0.5));
    if (body.Has("origin_m")) {
      const std::vector<double> origin = body.Numbers("origin_m", Range::Closed(-1000.0, 1000.0, "m"), 2, 2);
      feature.has_origin = true;
      feature.origin_x = origin[0];
      feature.origin_y = origin[1];
    }
  }
  body.Finish();
  entry.Finish();
  return feature;
}

HeightGrid ParseGrid(YamlMap& map) {
  HeightGrid grid;
  const std::vector<double> origin = map.Numbers("origin_m", Range::Closed(-1000.0, 1000.0, "m"), 2, 2);
  grid.x0 = origin[0];
  grid.y0 = origin[1];
  grid.cell = map.Number("cell_m", Range::Closed(0.005, 10.0, "m"));
  YAML::Node rows = map.Sequence("rows");
  const std::string field = map.FieldName("rows");
  const std::string file = map.file().string();
  if (rows.size() < 2) {
    throw InputError(file, LineOf(rows), field, "at least 2 rows of heights (y = y0, y0 + cell, ...)",
                     std::to_string(rows.size()) + " rows");
  }
  grid.ny = static_cast<int>(rows.size());
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const std::string row_field = field + "[" + std::to_string(j) + "]";
    if (!rows[j].IsSequence()) {
      throw InputError(file, LineOf(rows[j]), row_field, "a list of heights in m", "something else");
    }
    if (j == 0) {
      grid.nx = static_cast<int>(rows[j].size());
      if (grid.nx < 2) {
        throw InputError(file, LineOf(rows[j]), row_field, "at least 2 heights per row",
                         std::to_string(grid.nx) + " heights");
      }
    } else if (static_cast<int>(rows[j].size()) != grid.nx) {
      throw InputError(file, LineOf(rows[j]), row_field,
                       std::to_string(grid.nx) + " heights, as row 0 (a full grid, no holes)",
                       std::to_string(rows[j].size()) + " heights");
    }
    for (std::size_t i = 0; i < rows[j].size(); ++i) {
      grid.z.push_back(ScalarNumber(rows[j][i], map.file(), row_field + "[" + std::to_string(i) + "]",
                                    Range::Closed(-1.0, 1.0, "m (a hole or NaN is not a height)")));
    }
  }
  return grid;
}

}  // namespace

FloorMap ParseFloorMap(YamlMap& map) {
  FloorMap floor;
  if (map.Has("profile_m")) floor.profile = ParseTerrainProfile(map);
  if (map.Has("features")) {
    YAML::Node list = map.Sequence("features");
    for (std::size_t k = 0; k < list.size(); ++k) {
      floor.features.push_back(ParseFeature(list[k], map, map.FieldName("features") + "[" + std::to_string(k) + "]"));
    }
  }
  if (map.Has("grid")) {
    YamlMap grid = map.Map("grid");
    floor.grid = ParseGrid(grid);
    grid.Finish();
  }
  if (map.Has("patches")) {
    YAML::Node list = map.Sequence("patches");
    for (std::size_t k = 0; k < list.size(); ++k) {
      YamlMap entry(list[k], map.file(), map.FieldName("patches") + "[" + std::to_string(k) + "]", LineOf(list[k]));
      FrictionPatch patch;
      patch.name = entry.StringOr("name", "");
      ReadInterval(entry, "x_m", patch.x_min, patch.x_max);
      ReadInterval(entry, "y_m", patch.y_min, patch.y_max);
      patch.friction = entry.Number("friction", Range::Positive(2.0, "(friction coefficient)"));
      entry.Finish();
      floor.patches.push_back(patch);
    }
  }
  return floor;
}

}  // namespace pwsim
