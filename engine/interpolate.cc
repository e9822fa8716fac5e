#include "engine/interpolate.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"

namespace pwsim {

KnotSegment FindKnotSegment(std::span<const double> x, double xq) {
  PWSIM_DEMAND(x.size() >= 2);
  // First knot strictly greater than xq; the segment is [k - 1, k], clamped to the ends.
  const auto upper = std::upper_bound(x.begin(), x.end(), xq);
  const std::size_t hi =
      std::clamp<std::size_t>(static_cast<std::size_t>(upper - x.begin()), 1, x.size() - 1);
  const std::size_t k = hi - 1;
  const double s = std::clamp((xq - x[k]) / (x[hi] - x[k]), 0.0, 1.0);
  return {k, s};
}

double InterpolateLinear(std::span<const double> x, std::span<const double> y, double xq) {
  PWSIM_DEMAND(x.size() == y.size() && !x.empty());
  if (xq >= x.back()) return y.back();  // held exactly (Lerp at s = 1 may round)
  const KnotSegment seg = FindKnotSegment(x, xq);
  return Lerp(y[seg.k], y[seg.k + 1], seg.s);
}

double SampleUniformGrid(std::span<const double> grid, double t0, double dt, double t) {
  PWSIM_DEMAND(!grid.empty() && dt > 0.0);
  const std::size_t last = grid.size() - 1;
  const double pos = std::max(0.0, (t - t0) / dt);
  const std::size_t k = std::min(last, static_cast<std::size_t>(pos));
  if (k == last) return grid[last];
  return Lerp(grid[k], grid[k + 1], pos - static_cast<double>(k));
}

std::vector<double> ResampleOnUniformGrid(std::span<const double> t, std::span<const double> x,
                                          double dt, std::size_t n) {
  PWSIM_DEMAND(t.size() == x.size() && t.size() >= 2 && dt > 0.0);
  std::vector<double> grid(n);
  std::size_t seg = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double time = t.front() + static_cast<double>(k) * dt;
    while (seg + 2 < t.size() && time > t[seg + 1]) ++seg;
    const double s = std::clamp((time - t[seg]) / (t[seg + 1] - t[seg]), 0.0, 1.0);
    grid[k] = Lerp(x[seg], x[seg + 1], s);
  }
  return grid;
}

std::vector<double> InterpolateLinear(std::span<const double> x, std::span<const double> y,
                                      std::span<const double> xq) {
  std::vector<double> out(xq.size());
  for (std::size_t i = 0; i < xq.size(); ++i) out[i] = InterpolateLinear(x, y, xq[i]);
  return out;
}

}  // namespace pwsim
