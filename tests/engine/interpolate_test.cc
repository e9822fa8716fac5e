// engine/interpolate.h against closed forms: a straight line is reproduced, knot values come
// back exactly, the ends are held, and the three entry points agree where their conventions
// coincide.
#include "engine/interpolate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace pwsim {
namespace {

TEST(Interpolate, LerpIsExactAtTheStartAndLinearInBetween) {
  EXPECT_EQ(Lerp(0.1, 0.7, 0.0), 0.1);
  EXPECT_DOUBLE_EQ(Lerp(0.1, 0.7, 1.0), 0.7);
  EXPECT_DOUBLE_EQ(Lerp(-2.0, 6.0, 0.25), 0.0);
  EXPECT_DOUBLE_EQ(Lerp(3.0, 3.0, 0.8), 3.0);
}

TEST(Interpolate, ReproducesAStraightLineOnIrregularKnots) {
  // y = 3 x - 1 on knots with irregular spacing: linear interpolation is exact (to rounding).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> step(0.01, 0.5);
  std::vector<double> x{-1.0};
  for (int i = 0; i < 40; ++i) x.push_back(x.back() + step(rng));
  std::vector<double> y;
  for (double v : x) y.push_back(3.0 * v - 1.0);
  std::uniform_real_distribution<double> query(x.front(), x.back());
  for (int i = 0; i < 1000; ++i) {
    const double q = query(rng);
    EXPECT_NEAR(InterpolateLinear(x, y, q), 3.0 * q - 1.0, 1e-12) << q;
  }
}

TEST(Interpolate, KnotsComeBackExactlyAndTheEndsAreHeld) {
  const std::vector<double> x{0.0, 0.3, 0.7, 1.1};
  const std::vector<double> y{0.1, -0.37, 2.9, 0.05};
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_EQ(InterpolateLinear(x, y, x[i]), y[i]) << i;
  EXPECT_EQ(InterpolateLinear(x, y, -5.0), y.front());
  EXPECT_EQ(InterpolateLinear(x, y, 9.0), y.back());
  // Midpoints: the mean of the neighbours (closed form).
  EXPECT_DOUBLE_EQ(InterpolateLinear(x, y, 0.5), 0.5 * (y[1] + y[2]));
  const KnotSegment seg = FindKnotSegment(x, 0.3);
  EXPECT_EQ(seg.k, 1U);  // a query on a knot starts the segment there
  EXPECT_EQ(seg.s, 0.0);
  EXPECT_EQ(FindKnotSegment(x, 2.0).k, 2U);
  EXPECT_EQ(FindKnotSegment(x, 2.0).s, 1.0);
  EXPECT_EQ(FindKnotSegment(x, -2.0).k, 0U);
  EXPECT_EQ(FindKnotSegment(x, -2.0).s, 0.0);
}

TEST(Interpolate, UniformGridSamplingAgreesWithTheKnotForm) {
  // A grid g_k = sin(k dt) sampled at arbitrary times equals the knot interpolation through
  // the same points; outside the grid the end values are held.
  const double t0 = 0.25, dt = 0.01;
  std::vector<double> grid, knots;
  for (int k = 0; k < 200; ++k) {
    knots.push_back(t0 + k * dt);
    grid.push_back(std::sin(3.0 * k * dt));
  }
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> query(knots.front(), knots.back());
  for (int i = 0; i < 1000; ++i) {
    const double t = query(rng);
    EXPECT_NEAR(SampleUniformGrid(grid, t0, dt, t), InterpolateLinear(knots, grid, t), 1e-12) << t;
  }
  EXPECT_EQ(SampleUniformGrid(grid, t0, dt, 0.0), grid.front());
  EXPECT_EQ(SampleUniformGrid(grid, t0, dt, 99.0), grid.back());
  EXPECT_EQ(SampleUniformGrid(std::vector<double>{4.0}, t0, dt, 1.0), 4.0);  // one sample
}

TEST(Interpolate, ResamplingOntoAGridMatchesPointwiseInterpolation) {
  // Irregular knots (like mocap frames with drops) onto a 1 ms grid: the single walk gives
  // what interpolating each grid time separately gives, and covers [t.front(), ...].
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> step(0.005, 0.03);
  std::vector<double> t{0.1};
  for (int i = 0; i < 60; ++i) t.push_back(t.back() + step(rng));
  std::vector<double> x;
  for (double v : t) x.push_back(0.8 * v * v);
  const double dt = 1e-3;
  const auto n = static_cast<std::size_t>((t.back() - t.front()) / dt) + 1;
  const std::vector<double> grid = ResampleOnUniformGrid(t, x, dt, n);
  ASSERT_EQ(grid.size(), n);
  EXPECT_EQ(grid.front(), x.front());
  for (std::size_t k = 0; k < n; ++k) {
    const double time = t.front() + static_cast<double>(k) * dt;
    EXPECT_NEAR(grid[k], InterpolateLinear(t, x, time), 1e-12) << k;
  }
  // Past the last knot the value is held.
  const std::vector<double> longer = ResampleOnUniformGrid(t, x, dt, n + 50);
  EXPECT_EQ(longer.back(), x.back());
}

}  // namespace
}  // namespace pwsim
