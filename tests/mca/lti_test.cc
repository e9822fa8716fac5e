#include "mca/lti.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "mca/dof.h"

namespace pwsim::mca {
namespace {

using Complex = std::complex<double>;

/// Runs `system` on u(t) = sin(ω t) for whole periods after settling and fits gain and phase.
Complex SimulatedResponse(const ContinuousSystem& system, double omega, double dt) {
  const DiscreteSystem dut = Discretize(system, dt);
  FilterState state;
  const double period = 2.0 * kPi / omega;
  const auto settle = static_cast<long>(std::ceil(std::max(30.0, 4.0 * period) / dt));
  const auto measure = static_cast<long>(std::llround(4.0 * period / dt));
  double ss = 0.0, sc = 0.0, cc = 0.0, ys = 0.0, yc = 0.0;
  for (long k = 1; k <= settle + measure; ++k) {
    const double t = static_cast<double>(k) * dt;
    const double y = Step(dut, state, std::sin(omega * t));
    if (k > settle) {
      const double s = std::sin(omega * t), c = std::cos(omega * t);
      ss += s * s; sc += s * c; cc += c * c; ys += y * s; yc += y * c;
    }
  }
  const double det = ss * cc - sc * sc;
  const double a = (ys * cc - yc * sc) / det;  // y = a sin + b cos
  const double b = (yc * ss - ys * sc) / det;
  return {a, b};  // gain·e^{jφ} = a + j b for a sine input
}

// Tests the second-order high-pass against its critically damped step response (1 - ωt)e^{-ωt}.
TEST(LtiTest, HighPass2StepResponseIsExact) {
  const double omega = 2.0, dt = 1e-3;
  const DiscreteSystem dut = Discretize(HighPass2(omega, 1.0), dt);
  FilterState state;
  state.u = 1.0;  // the unit step is already applied at t = 0
  EXPECT_DOUBLE_EQ(Output(dut, state), 1.0);
  for (int k = 1; k <= 5000; ++k) {
    const double t = k * dt;
    const double y = Step(dut, state, 1.0);
    ASSERT_NEAR(y, (1.0 - omega * t) * std::exp(-omega * t), 1e-10) << "t = " << t;
  }
}

// Tests the first-order high-pass step response e^{-ωt} and the low-pass 1 - e^{-ζωt}(...).
TEST(LtiTest, FirstOrderAndUnderdampedStepResponses) {
  const double dt = 4e-3;
  const DiscreteSystem hp = Discretize(HighPass1(0.5), dt);
  const double omega = 3.0, zeta = 0.7;
  const DiscreteSystem lp = Discretize(LowPass2(omega, zeta), dt);
  FilterState hs, ls;
  hs.u = ls.u = 1.0;
  const double wd = omega * std::sqrt(1.0 - zeta * zeta);
  for (int k = 1; k <= 2500; ++k) {
    const double t = k * dt;
    ASSERT_NEAR(Step(hp, hs, 1.0), std::exp(-0.5 * t), 1e-10);
    const double expected =
        1.0 - std::exp(-zeta * omega * t) *
                  (std::cos(wd * t) + zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * t));
    ASSERT_NEAR(Step(lp, ls, 1.0), expected, 1e-10);
  }
}

// Tests that the state-space realisation has the transfer function it was built from.
TEST(LtiTest, ResponseMatchesTransferFunction) {
  const ContinuousSystem dut = Series(HighPass2(2.0, 0.7), HighPass1(0.5));
  for (double w : {0.1, 0.631, 1.0, 3.981, 15.85}) {
    const Complex s(0.0, w);
    const Complex expected = s * s / (s * s + 2.0 * 0.7 * 2.0 * s + 4.0) * s / (s + 0.5);
    EXPECT_NEAR(std::abs(dut.Response(w) - expected), 0.0, 1e-12) << w;
  }
  EXPECT_NEAR(LowPass2(3.0, 0.5).DcGain(), 1.0, 1e-12);
  EXPECT_NEAR(LeakyIntegrator(0.25).DcGain(), 4.0, 1e-12);
}

// Tests that the discrete filter's gain and phase at chosen frequencies are the continuous
// design's within 1e-3 (gain) and 1e-3 rad (phase), at 250 Hz and 1 kHz.
TEST(LtiTest, DiscreteGainAndPhaseMatchContinuous) {
  const ContinuousSystem dut = Series(HighPass2(2.0, 1.0), HighPass1(0.5));
  for (double dt : {4e-3, 1e-3}) {
    for (double w : {0.398, 1.0, 2.512, 10.0}) {
      const Complex simulated = SimulatedResponse(dut, w, dt);
      const Complex expected = dut.Response(w);
      EXPECT_NEAR(std::abs(simulated), std::abs(expected), 1e-3) << "w " << w << " dt " << dt;
      EXPECT_NEAR(std::arg(simulated), std::arg(expected), 1e-3) << "w " << w << " dt " << dt;
    }
  }
}

// Tests that the same filter run at 250 Hz and 1 kHz gives the same output at common times.
TEST(LtiTest, StepSizeIndependent) {
  const ContinuousSystem system = Series(HighPass2(2.0, 1.0), LeakyIntegrator(0.1));
  const DiscreteSystem slow = Discretize(system, 4e-3);
  const DiscreteSystem fast = Discretize(system, 1e-3);
  FilterState s_slow, s_fast;
  // u(0) = 0: both runs start at rest
  auto input = [](double t) {
    return std::sin(1.3 * t) + 0.5 * (std::tanh(2.0 * (t - 3.0)) - std::tanh(-6.0));
  };
  double worst = 0.0;
  for (int k = 1; k <= 2500; ++k) {
    const double y_slow = Step(slow, s_slow, input(k * 4e-3));
    double y_fast = 0.0;
    for (int j = 1; j <= 4; ++j) y_fast = Step(fast, s_fast, input((4 * (k - 1) + j) * 1e-3));
    worst = std::max(worst, std::abs(y_slow - y_fast));
  }
  EXPECT_LT(worst, 1e-5);
}

// Tests the controllable canonical form and the polynomial product.
TEST(LtiTest, TransferFunctionHelpers) {
  const std::vector<double> p = PolyMultiply({2.0, 1.0}, {3.0, 1.0});
  ASSERT_EQ(p.size(), 3u);
  EXPECT_DOUBLE_EQ(p[0], 6.0);
  EXPECT_DOUBLE_EQ(p[1], 5.0);
  EXPECT_DOUBLE_EQ(p[2], 1.0);
  const ContinuousSystem dut = FromTransferFunction({1.0, 2.0}, p);
  const Complex s(0.0, 0.7);
  EXPECT_NEAR(std::abs(dut.Response(0.7) - (s + 2.0) / (6.0 * s * s + 5.0 * s + 1.0)), 0.0, 1e-12);
}

}  // namespace
}  // namespace pwsim::mca
