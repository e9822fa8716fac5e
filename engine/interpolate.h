#pragma once
// Linear interpolation, one implementation for every library (terrain heights, resampling of
// measured trials onto the simulation grid, sampling that grid at the measured times, the
// session's platform-pose history).
//
// Between knots (x_k, y_k) and (x_{k+1}, y_{k+1}) with s = (x - x_k) / (x_{k+1} - x_k):
//   y(x) = y_k + s (y_{k+1} - y_k)                                   (Lerp)
// This form returns y_k exactly at s = 0. A query exactly on an interior knot starts the
// segment there (s = 0), so knot values come back bit for bit.

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

namespace pwsim {

/// a + s (b - a).
inline double Lerp(double a, double b, double s) { return a + s * (b - a); }

/// A query's place on sorted knots: between knot k and k + 1, at fraction s in [0, 1].
struct KnotSegment {
  std::size_t k{0};
  double s{0.0};
};

/// For strictly increasing knots `x` (at least 2): the segment with x[k] <= xq < x[k+1];
/// a query before the first or from the last knot on clamps to the end segment, s to [0, 1].
KnotSegment FindKnotSegment(std::span<const double> x, double xq);

/// The same segment as FindKnotSegment (same k, same s, same bits), searched first at `hint`
/// and the segment after it (a query that moves little between calls: one comparison or two
/// instead of a binary search); `hint` is updated to the segment found.
inline KnotSegment FindKnotSegmentNear(std::span<const double> x, double xq, std::size_t& hint) {
  const std::size_t last = x.size() - 1;  // segments 0 .. last - 1
  for (std::size_t k = hint; k < std::min(hint + 2, last); ++k) {
    // k is FindKnotSegment's segment when x[k] <= xq < x[k + 1] (the first segment also takes
    // queries before the knots, the last one queries from its end on)
    const bool above_start = k == 0 || x[k] <= xq;
    const bool below_end = k + 1 == last || xq < x[k + 1];
    if (above_start && below_end) {
      hint = k;
      return {k, std::clamp((xq - x[k]) / (x[k + 1] - x[k]), 0.0, 1.0)};
    }
  }
  const KnotSegment found = FindKnotSegment(x, xq);
  hint = found.k;
  return found;
}

/// y at xq, linear between the knots (x strictly increasing, same size as y, >= 2), held at
/// the end values outside [x.front(), x.back()].
double InterpolateLinear(std::span<const double> x, std::span<const double> y, double xq);

/// The same at each query of `xq` (any order).
std::vector<double> InterpolateLinear(std::span<const double> x, std::span<const double> y,
                                      std::span<const double> xq);

/// A signal on the uniform grid t0 + k dt (k < grid.size(), >= 1 sample) at time t: linear
/// between grid points, held at the ends. The index is computed, not searched.
double SampleUniformGrid(std::span<const double> grid, double t0, double dt, double t);

/// Knots (t strictly increasing, x the same size, >= 2) resampled onto the grid
/// t.front() + k dt for k < n: linear between knots, held at the end values. The queries are
/// sorted, so the knots are walked once (O(n + knots)). A grid time equal to a knot ends the
/// segment before it (s = 1).
std::vector<double> ResampleOnUniformGrid(std::span<const double> t, std::span<const double> x,
                                          double dt, std::size_t n);

}  // namespace pwsim
