#include "engine/lumped_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace pwsim {
namespace {

// Closed-form free response of m q'' + c q' + k q = 0 from q(0) = q0, q'(0) = 0 (underdamped).
double FreeResponse(const AxisParams& axis, double q0, double t) {
  const double omega_n = std::sqrt(axis.stiffness / axis.inertia);
  const double zeta = axis.damping / (2.0 * std::sqrt(axis.stiffness * axis.inertia));
  const double omega_d = omega_n * std::sqrt(1.0 - zeta * zeta);
  return q0 * std::exp(-zeta * omega_n * t) *
         (std::cos(omega_d * t) + zeta * omega_n / omega_d * std::sin(omega_d * t));
}

// Tests that the exact propagator matches the closed-form free response to 1e-6 relative.
TEST(LumpedModelTest, FreeResponseMatchesClosedForm) {
  const Chair chair = MakeTableOneChair();
  const LumpedModelParams params = MakeLumpedModelParams(chair, 100.0);
  const DiscreteLumpedModel dut = Discretize(params, 1e-3);
  LumpedState state{0.05, 0.0, 0.1, 0.0};
  for (int tick = 1; tick <= 2000; ++tick) {
    state = Step(dut, state, {});
    const double t = tick * 1e-3;
    EXPECT_NEAR(state.z, FreeResponse(params.heave, 0.05, t), 1e-6 * 0.05) << "t=" << t;
    EXPECT_NEAR(state.pitch, FreeResponse(params.pitch, 0.1, t), 1e-6 * 0.1) << "t=" << t;
  }
}

// Tests the response to a base-excitation step (a ramp over one tick, then held) against the
// closed-form response of (C s + K)/(M s^2 + C s + K) to that same ramp-and-hold input.
TEST(LumpedModelTest, RampAndHoldInputMatchesClosedForm) {
  const Chair chair = MakeTableOneChair();
  const LumpedModelParams params = MakeLumpedModelParams(chair, 50.0);
  const double dt = 1e-3;
  const double height = 0.065;
  const double ramp_time = 0.2;  // the input rises linearly for 0.2 s, then holds
  const DiscreteLumpedModel dut = Discretize(params, dt);

  // Reference: unit-ramp response r(t) of H(s), closed form, then superpose r(t) - r(t - T).
  const AxisParams& a = params.heave;
  const double wn = std::sqrt(a.stiffness / a.inertia);
  const double zeta = a.damping / (2.0 * std::sqrt(a.stiffness * a.inertia));
  const double wd = wn * std::sqrt(1.0 - zeta * zeta);
  // Error e = u - q obeys m e'' + c e' + k e = m u''; for a unit ramp u = t from rest,
  // e(0) = 0, e'(0) = 1 (u jumps in slope), so e(t) = exp(-ζωn t) sin(ωd t)/ωd.
  auto ramp = [&](double t) {
    if (t <= 0.0) return 0.0;
    return t - std::exp(-zeta * wn * t) * std::sin(wd * t) / wd;
  };
  auto reference = [&](double t) { return height / ramp_time * (ramp(t) - ramp(t - ramp_time)); };

  LumpedState state;
  double max_error = 0.0;
  for (int tick = 0; tick < 1500; ++tick) {
    const double t0 = tick * dt;
    const double t1 = t0 + dt;
    auto input = [&](double t) { return height * std::min(t, ramp_time) / ramp_time; };
    state = Step(dut, state, {input(t0), input(t1), 0.0, 0.0, 0.0});
    max_error = std::max(max_error, std::abs(state.z - reference(t1)));
  }
  EXPECT_LT(max_error, 1e-6 * height);
}

// Tests that a constant torque settles at Γ/Kθ (static equilibrium of eq. 3).
TEST(LumpedModelTest, ConstantTorqueSettlesAtStaticDeflection) {
  const LumpedModelParams params = MakeLumpedModelParams(MakeTableOneChair(), 0.0);
  const DiscreteLumpedModel dut = Discretize(params, 1e-3);
  LumpedState state;
  for (int tick = 0; tick < 5000; ++tick) state = Step(dut, state, {0, 0, 0, 0, 25.0});
  EXPECT_NEAR(state.pitch, 25.0 / params.pitch.stiffness, 1e-9);
  EXPECT_NEAR(state.pitch_rate, 0.0, 1e-9);
}

struct ModalCase {
  double load_kg;
  double heave_hz, heave_zeta, pitch_hz, pitch_zeta;  // computed by hand from Table I
};

// Measures frequency and damping from a simulated free response: the damped period from
// successive upward zero crossings and ζ from the logarithmic decrement of successive peaks.
Mode MeasureMode(const DiscreteLumpedModel& model, bool heave) {
  LumpedState state;
  (heave ? state.z : state.pitch) = 1.0;
  std::vector<double> crossings;
  std::vector<double> peaks;
  double prev = 1.0, prev2 = 1.0;
  for (int tick = 1; tick < 20000 && crossings.size() < 3; ++tick) {
    state = Step(model, state, {});
    const double q = heave ? state.z : state.pitch;
    if (prev < 0.0 && q >= 0.0) {
      crossings.push_back((tick - 1 + (-prev) / (q - prev)) * model.dt);
    }
    if (tick >= 2 && prev > prev2 && prev >= q && prev > 0.0) peaks.push_back(prev);
    prev2 = prev;
    prev = q;
  }
  EXPECT_GE(crossings.size(), 2u);
  EXPECT_GE(peaks.size(), 1u);
  const double period = crossings[1] - crossings[0];
  const double omega_d = 2.0 * M_PI / period;
  // Log decrement over one period between the initial displacement (a peak at t=0) and the
  // next peak.
  const double delta = std::log(1.0 / peaks[0]);
  const double zeta = delta / std::sqrt(4.0 * M_PI * M_PI + delta * delta);
  return {omega_d / std::sqrt(1.0 - zeta * zeta), zeta};
}

class LumpedModalTest : public ::testing::TestWithParam<ModalCase> {};

// Tests heave and pitch natural frequency and damping at 0, 50 and 100 kg (Table I, eq. 4-5),
// both from the formulas and measured on the simulated free response.
TEST_P(LumpedModalTest, TableOneModalNumbers) {
  const ModalCase& c = GetParam();
  const Chair chair = MakeTableOneChair();
  const Mode heave = HeaveMode(chair, c.load_kg);
  const Mode pitch = PitchMode(chair, c.load_kg);
  EXPECT_NEAR(heave.omega_n / (2 * M_PI), c.heave_hz, 0.005);
  EXPECT_NEAR(heave.zeta, c.heave_zeta, 0.005);
  EXPECT_NEAR(pitch.omega_n / (2 * M_PI), c.pitch_hz, 0.005);
  EXPECT_NEAR(pitch.zeta, c.pitch_zeta, 0.005);

  const DiscreteLumpedModel model = Discretize(MakeLumpedModelParams(chair, c.load_kg), 1e-4);
  const Mode heave_sim = MeasureMode(model, true);
  const Mode pitch_sim = MeasureMode(model, false);
  EXPECT_NEAR(heave_sim.omega_n, heave.omega_n, 1e-3 * heave.omega_n);
  EXPECT_NEAR(heave_sim.zeta, heave.zeta, 2e-3);
  EXPECT_NEAR(pitch_sim.omega_n, pitch.omega_n, 1e-3 * pitch.omega_n);
  EXPECT_NEAR(pitch_sim.zeta, pitch.zeta, 2e-3);
}

// Hand computation: M = 53 + Mu, J = 9.9 + 0.43² M, f = sqrt(K/M)/2π, ζ = C/(2 sqrt(K M)).
INSTANTIATE_TEST_SUITE_P(Loads, LumpedModalTest,
                         ::testing::Values(ModalCase{0.0, 4.4696, 0.7525, 3.6568, 0.6186},
                                           ModalCase{50.0, 3.2062, 0.5398, 3.0168, 0.5103},
                                           ModalCase{100.0, 2.6306, 0.4429, 2.6264, 0.4443}));

}  // namespace
}  // namespace pwsim
