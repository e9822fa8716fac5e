#include "mca/vestibular.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

namespace pwsim::mca {
namespace {

using Complex = std::complex<double>;

double PhaseDeg(Complex h) { return std::arg(h) / kDegToRad; }

// Tests the otolith against its transfer function evaluated independently, and against the
// reference table (mca-anchors §4.1, recomputed here from the same transfer function).
TEST(VestibularTest, OtolithFrequencyResponse) {
  const OtolithParams p;
  const ContinuousSystem dut = OtolithSystem(p);
  struct Row { double w, gain, phase_deg; };
  for (const Row& row : {Row{0.1, 0.5833, 21.02}, Row{0.5, 0.8908, -6.31}, Row{1.0, 0.8149, -27.13},
                         Row{2.0, 0.5960, -49.66}, Row{10.0, 0.1484, -80.74}}) {
    const Complex s(0.0, row.w);
    const Complex expected = p.gain * (p.tau_a * s + 1.0) / ((p.tau_l * s + 1.0) * (p.tau_s * s + 1.0));
    EXPECT_NEAR(std::abs(dut.Response(row.w) - expected), 0.0, 1e-12);
    EXPECT_NEAR(std::abs(dut.Response(row.w)), row.gain, 1e-3) << row.w;
    EXPECT_NEAR(PhaseDeg(dut.Response(row.w)), row.phase_deg, 0.1) << row.w;
  }
  EXPECT_NEAR(dut.DcGain(), 0.4, 1e-12);
}

// Tests the canals per axis (pitch at three frequencies, roll and yaw at 1 rad/s).
TEST(VestibularTest, CanalFrequencyResponse) {
  const CanalParams p;
  struct Row { int axis; double w, gain, phase_deg; };
  for (const Row& row : {Row{1, 0.1, 0.4442, 79.94}, Row{1, 1.0, 0.9772, 6.88}, Row{1, 10.0, 0.7070, -43.73},
                         Row{0, 1.0, 0.9814, 5.51}, Row{2, 1.0, 0.9897, 1.80}}) {
    const ContinuousSystem dut = CanalSystem(p, row.axis);
    const double tl = p.tau_l[static_cast<std::size_t>(row.axis)];
    const Complex s(0.0, row.w);
    const Complex expected =
        p.tau_a * tl * s * s / ((p.tau_a * s + 1.0) * (tl * s + 1.0) * (p.tau_s * s + 1.0));
    EXPECT_NEAR(std::abs(dut.Response(row.w) - expected), 0.0, 1e-12);
    EXPECT_NEAR(std::abs(dut.Response(row.w)), row.gain, 1e-3);
    EXPECT_NEAR(PhaseDeg(dut.Response(row.w)), row.phase_deg, 0.1);
  }
}

// Tests the otolith step response against its closed form (partial fractions) and that a head
// at rest perceives nothing.
TEST(VestibularTest, OtolithStepAndRest) {
  const VestibularParams params;
  const double dt = 1e-3;
  VestibularModel dut(params, dt);
  for (int k = 0; k < 1000; ++k) {
    const Perceived p = dut.Step(HeadMotion{});
    for (std::size_t i = 0; i < 3; ++i) ASSERT_EQ(p.fs[i], 0.0);
  }
  // step of 1 m/s^2 in surge, ramped over the first tick (first-order hold from rest)
  const OtolithParams& o = params.otolith;
  HeadMotion m;
  m.fs[0] = 1.0;
  // y(t) = K [1 + A e^{-t/τL} + B e^{-t/τS}],  A = (τa - τL)/(τL - τS), B = (τS - τa)/(τL - τS)
  const double a = (o.tau_a - o.tau_l) / (o.tau_l - o.tau_s);
  const double b = (o.tau_s - o.tau_a) / (o.tau_l - o.tau_s);
  dut.Reset();
  for (int k = 1; k <= 20000; ++k) {
    const double y = dut.Step(m).fs[0];
    const double t = k * dt - 0.5 * dt;  // the first-order hold delays a step by dt/2
    if (k % 1000 == 0) {
      const double expected = o.gain * (1.0 + a * std::exp(-t / o.tau_l) + b * std::exp(-t / o.tau_s));
      EXPECT_NEAR(y, expected, 2e-5) << k;
    }
  }
}

}  // namespace
}  // namespace pwsim::mca
