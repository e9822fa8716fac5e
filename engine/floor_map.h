#pragma once
// FloorMap: the 2.5-D floor of a room or circuit, the ground height z(x, y) in W (x forward
// along the start heading, y left, z up). It is a sum of three layers, each 0 where absent:
//
//   z(x, y) = z_profile(x) + Σ_k f_k(x, y) + z_grid(x, y)
//
//   z_profile  the sagittal Terrain of the straight runs (speed cushion), uniform across y;
//   f_k        features on a rectangle [x_min, x_max] × [y_min, y_max], tapered at its edges
//              by s(u) = clamp(min(u - u_min, u_max - u) / ramp, 0, 1) (a step when ramp = 0):
//                bump   f = h · s_x(x) · s_y(y)                        (threshold, kerb, cushion,
//                                                                      a bump under one side)
//                plane  f = (g_x (x - x_0) + g_y (y - y_0)) · s_x(x) · s_y(y)
//                       (x_0, y_0) its origin (the rectangle's centre unless given); a ramp
//                       (g_x, origin at its foot) or a cross-slope (g_y)
//   z_grid     a regular height grid, bilinear between nodes, 0 outside it.
//
// With only a profile, HeightAt(x, y) returns z_profile(x) bit for bit (the full-DoF chair on a
// straight run reproduces the sagittal ChairSimulator exactly).
//
// Rolling envelope. A wheel of radius R rolling in the vertical plane through its contact point
// p along the unit direction u (its heading in W) touches the floor where its disc does, not at
// its lowest point: the height of its centre less R is
//
//   z_env(p) = max_{|s| <= R}  z(p + s u) + √(R² − s²) − R
//
// (the wheel's width and the floor's slope across u are neglected). Up a step of height h at
// x_e (h < R) the centre rides the arc z_c = h + √(R² − (x_e − x)²) around the edge over the
// last √(2Rh − h²) before it; over a gap of width w < 2R it sinks R − √(R² − w²/4) only. Along
// u the floor is piecewise smooth between breakpoints (the profile's knots, each feature's
// taper knots in x and y, the grid's lines; at most kEnvelopeBreakpoints of them, else the
// span is sampled uniformly at that many points); on each piece it is taken linear through its
// ends (exact for the profile and for features crossed along one axis; bilinear products
// otherwise), and the maximum of z(s) + √(R² − s²) on a line z_a + m (s − s_a) is at its ends or
// at the tangent point s* = R m / √(1 + m²). The pieces' ends are evaluated just inside them
// (1e-9 R), so a step's one-sided heights are both seen. On a level piece of the floor that
// holds the whole disc (the hint's level interval, no active feature) z_env = z exactly.
//
// Friction patches. `patches` lower the tyre-floor friction on rectangles (a wet or polished
// patch): the friction at (x, y) is min(μ_wheel, μ_patch) of the patches that hold the point.

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "engine/terrain.h"
#include "engine/yaml_reader.h"

namespace pwsim {

struct FloorFeature {
  enum class Kind { kBump, kPlane };
  Kind kind{Kind::kBump};
  std::string name;
  double x_min{0.0}, x_max{0.0};  ///< [m] rectangle in W
  double y_min{0.0}, y_max{0.0};  ///< [m]
  double ramp{0.0};               ///< [m] edge taper inside the rectangle (0: a sharp step)
  double height{0.0};             ///< bump: plateau height h [m] (negative: a dip)
  double grade_x{0.0};            ///< plane: rise per metre along x [-]
  double grade_y{0.0};            ///< plane: rise per metre along y [-] (cross-slope, left up > 0)
  bool has_origin{false};         ///< plane: (origin_x, origin_y) given, else the centre
  double origin_x{0.0}, origin_y{0.0};  ///< plane: where f = 0 before tapering [m]

  /// f_k(x, y) [m].
  double HeightAt(double x_W, double y_W) const;
};

namespace floor_detail {

/// s(u): 1 inside the interval away from its edges, tapering linearly to 0 over `ramp`.
inline double Taper(double u, double lo, double hi, double ramp) {
  if (u < lo || u > hi) return 0.0;
  const double inset = std::min(u - lo, hi - u);
  // inset >= ramp gives inset / ramp >= 1 (a rounded quotient keeps its side of 1): clamped to
  // 1 without the division
  if (inset >= ramp) return 1.0;
  return std::clamp(inset / ramp, 0.0, 1.0);
}

}  // namespace floor_detail

// Inline: every contact of the full-DoF chair looks up the floor every tick.
inline double FloorFeature::HeightAt(double x_W, double y_W) const {
  const double sx = floor_detail::Taper(x_W, x_min, x_max, ramp);
  if (sx == 0.0) return 0.0;
  const double sy = floor_detail::Taper(y_W, y_min, y_max, ramp);
  if (sy == 0.0) return 0.0;
  if (kind == Kind::kBump) return height * sx * sy;
  const double xc = has_origin ? origin_x : 0.5 * (x_min + x_max);
  const double yc = has_origin ? origin_y : 0.5 * (y_min + y_max);
  return (grade_x * (x_W - xc) + grade_y * (y_W - yc)) * sx * sy;
}

/// A bump of height `height` [m] on [x_min, x_max] × [y_min, y_max] tapered over `ramp` [m].
FloorFeature BumpFeature(double x_min, double x_max, double y_min, double y_max, double height, double ramp);
/// A plane of grades (g_x, g_y) about the rectangle's centre, tapered over `ramp` [m].
FloorFeature PlaneFeature(double x_min, double x_max, double y_min, double y_max, double grade_x,
                          double grade_y, double ramp);

/// A rectangle of the floor with its own tyre-floor friction coefficient.
struct FrictionPatch {
  std::string name;
  double x_min{0.0}, x_max{0.0};  ///< [m] in W
  double y_min{0.0}, y_max{0.0};  ///< [m]
  double friction{0.3};           ///< μ [-] on the patch
};

/// Most breakpoints the envelope evaluates piecewise under one wheel.
inline constexpr int kEnvelopeBreakpoints = 48;

/// Regular grid of heights: node (i, j) at (x0 + i·cell, y0 + j·cell), z[j·nx + i].
struct HeightGrid {
  double x0{0.0}, y0{0.0};  ///< [m] node (0, 0)
  double cell{0.1};         ///< [m] spacing, both axes
  int nx{0}, ny{0};         ///< nodes along x and y (>= 2 each)
  std::vector<double> z;    ///< [m] finite, nx·ny values

  /// Bilinear height [m]; 0 outside the grid.
  double HeightAt(double x_W, double y_W) const;
};

/// What a lookup that moves little between calls (one wheel from tick to tick) carries over,
/// each part an interval of x in which a lookup's work is known in advance:
///   segment   the profile's segment (Terrain::HeightAtNear's search starts there);
///   clear     clear_lo < x < clear_hi reaches no feature's [x_min, x_max] but the active one's
///             (if any) nor the grid's x span (grown by a cell): there every other feature and
///             the grid add exactly +0 (each is 0 outside its x span), so z = z_profile + 0, or
///             z_profile [+ 0] + f_active [+ 0], without visiting them;
///   level     level_lo < x < level_hi is also inside one level piece of the profile (a level
///             segment, or beyond its ends): there z is level_z, whatever x and y, with no
///             active feature; with one (a ramp or cross-slope on level ground), z is
///             level_z + f_active(x, y) [+ 0], level_z then the profile's part [+ 0].
/// Any hint gives the same bits as HeightAt; a fresh one is empty.
struct FloorHint {
  std::size_t segment{0};
  double clear_lo{0.0}, clear_hi{0.0};  ///< [m]
  int active{-1};                       ///< the feature whose x span the clear interval is in
  double level_lo{0.0}, level_hi{0.0};  ///< [m]
  double level_z{0.0};                  ///< [m]
  int level_feature{-1};                ///< the active feature on the level piece (-1: none)
  bool level_plus_zero{false};          ///< + 0 after the active feature (layers follow it)
};

struct FloorMap {
  Terrain profile;                    ///< along x, uniform in y (may be empty: flat)
  std::vector<FloorFeature> features;
  std::optional<HeightGrid> grid;
  std::vector<FrictionPatch> patches;

  /// z(x, y) [m].
  double HeightAt(double x_W, double y_W) const;
  /// The same, bit for bit, starting from `hint` (updated): the profile's search at its
  /// segment, and no feature or grid visited while x stays in its clear interval.
  double HeightAtNear(double x_W, double y_W, FloorHint& hint) const;
  /// Highest point of every layer, summed (an upper bound, for rendering and checks) [m].
  double MaxHeightBound() const;
  /// z_env [m] of a wheel of radius `radius` [m] whose contact is at (x, y), rolling along the
  /// unit vector (dir_x, dir_y); `z_point` = z(x, y) and `hint` as HeightAtNear left them.
  /// Radius 0: z_point. On a level piece holding the whole disc: z_point, without a lookup.
  double EnvelopeAt(double x_W, double y_W, double dir_x, double dir_y, double radius, double z_point,
                    const FloorHint& hint) const {
    if (radius <= 0.0 || LevelUnder(x_W, y_W, radius, hint)) return z_point;
    return EnvelopeOffLevel(x_W, y_W, dir_x, dir_y, radius, z_point, hint);
  }
  /// Is the floor level under the whole disc: the hint's level piece holds it, with no feature
  /// active or beside the active one's y span (where it adds 0)?
  bool LevelUnder(double x_W, double y_W, double radius, const FloorHint& hint) const {
    if (!(x_W - radius > hint.level_lo && x_W + radius < hint.level_hi)) return false;
    if (hint.level_feature < 0) return true;
    const FloorFeature& f = features[static_cast<std::size_t>(hint.level_feature)];
    return y_W - radius > f.y_max || y_W + radius < f.y_min;
  }
  /// EnvelopeAt off a level piece. Where the floor along the wheel is one linear piece under the
  /// whole disc (a profile segment, a plane feature's plateau: the hint tells), of slope m along
  /// u, z_env = z_point + R (√(1 + m²) − 1) without a lookup; otherwise by the breakpoints.
  double EnvelopeOffLevel(double x_W, double y_W, double dir_x, double dir_y, double radius, double z_point,
                          const FloorHint& hint) const;
  /// The friction coefficient at (x, y): min(`wheel`, μ of every patch holding the point).
  double FrictionAt(double x_W, double y_W, double wheel) const {
    double mu = wheel;
    for (const FrictionPatch& p : patches) {
      if (x_W >= p.x_min && x_W <= p.x_max && y_W >= p.y_min && y_W <= p.y_max) mu = std::min(mu, p.friction);
    }
    return mu;
  }

 private:
  /// EnvelopeAt by the breakpoints of the floor under the disc (see the header's comment).
  double EnvelopeByBreakpoints(double x_W, double y_W, double dir_x, double dir_y, double radius, double z_point,
                               const FloorHint& hint) const;
  /// The slope along (dir_x, dir_y) where the floor is one linear piece under the disc; false
  /// where the hint cannot tell.
  bool LinearUnder(double x_W, double y_W, double dir_x, double dir_y, double radius, const FloorHint& hint,
                   double& slope) const;
  /// HeightAtNear outside the hint's level interval; sets the hint's intervals around x.
  double HeightAtNearUpdatingHint(double x_W, double y_W, FloorHint& hint) const;
  /// z_profile + Σ_k f_k + z_grid, summed in HeightAt's order; sets hint's clear interval.
  double AddLayersNear(double z_profile, double x_W, double y_W, FloorHint& hint) const;
};

inline double FloorMap::HeightAtNear(double x_W, double y_W, FloorHint& hint) const {
  if (x_W > hint.level_lo && x_W < hint.level_hi) {
    if (hint.level_feature < 0) return hint.level_z;
    // HeightAtNearUpdatingHint's sum in the clear interval, its profile part known
    const double z = hint.level_z + features[static_cast<std::size_t>(hint.level_feature)].HeightAt(x_W, y_W);
    return hint.level_plus_zero ? z + 0.0 : z;
  }
  return HeightAtNearUpdatingHint(x_W, y_W, hint);
}

/// A floor that is the sagittal terrain alone.
FloorMap FloorFromTerrain(const Terrain& terrain);

/// Reads `{profile_m: [[x, z], ...], features: [...], grid: {...}, patches: [...]}` (every key optional):
///   features: - {bump: {name, x_m: [min, max], y_m: [min, max], height_m, ramp_m}}
///             - {plane: {name, x_m: [...], y_m: [...], grade_x, grade_y, origin_m: [x, y], ramp_m}}
///   grid: {origin_m: [x0, y0], cell_m, rows: [[z at y0 for x0, x0 + cell ...], [next y] ...]}
///   patches: - {name, x_m: [min, max], y_m: [min, max], friction}     (μ in (0, 2])
/// Holes (null or missing values, ragged rows), NaN and infinities are errors naming the row
/// and column. @throws InputError (file, line, field, expected).
FloorMap ParseFloorMap(YamlMap& map);

}  // namespace pwsim
