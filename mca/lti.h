#pragma once
// Linear time-invariant single-input filters: designed in continuous time (transfer functions
// in s), run in discrete time with an exact first-order-hold discretisation. For an input that
// is linear between ticks the discrete output equals the continuous one at every tick, so a
// filter's behaviour does not depend on the step size (250 Hz and 1 kHz agree to O(dt²) for
// smooth inputs), and its frequency response is the continuous one.
//
//   ContinuousSystem washout = Series(HighPass2(2.0, 1.0), HighPass1(0.5));
//   DiscreteSystem discrete = Discretize(washout, 1e-3);
//   FilterState state;
//   double y = Step(discrete, state, u);   // no allocation

#include <array>
#include <complex>
#include <vector>

namespace pwsim::mca {

inline constexpr int kMaxOrder = 6;  ///< largest state dimension of one filter

/// ẋ = A x + B u, y = C x + D u with order n <= kMaxOrder; A is row-major n×n in the first
/// n*kMaxOrder slots (row stride kMaxOrder).
struct ContinuousSystem {
  int order{0};
  std::array<double, kMaxOrder * kMaxOrder> a{};
  std::array<double, kMaxOrder> b{};
  std::array<double, kMaxOrder> c{};
  double d{0.0};

  double A(int row, int col) const { return a[static_cast<std::size_t>(row * kMaxOrder + col)]; }
  double& A(int row, int col) { return a[static_cast<std::size_t>(row * kMaxOrder + col)]; }
  /// H(jω) = C (jω I - A)⁻¹ B + D.
  std::complex<double> Response(double omega) const;
  /// H(0) (the DC gain); @pre A is invertible or order 0.
  double DcGain() const;
};

/// y = k u.
ContinuousSystem Gain(double k);
/// H(s) = s / (s + ω), ω > 0 [rad/s].
ContinuousSystem HighPass1(double omega);
/// H(s) = s² / (s² + 2ζω s + ω²).
ContinuousSystem HighPass2(double omega, double zeta);
/// H(s) = ω / (s + ω).
ContinuousSystem LowPass1(double omega);
/// H(s) = ω² / (s² + 2ζω s + ω²).
ContinuousSystem LowPass2(double omega, double zeta);
/// H(s) = 1 / (s + λ), λ >= 0 [rad/s] (λ = 0: a pure integrator).
ContinuousSystem LeakyIntegrator(double leak);
/// H(s) = N(s)/D(s), coefficients in descending powers of s, deg N <= deg D <= kMaxOrder,
/// D's leading coefficient non-zero (controllable canonical form).
ContinuousSystem FromTransferFunction(const std::vector<double>& num,
                                      const std::vector<double>& den);
/// u -> first -> second. @pre first.order + second.order <= kMaxOrder.
ContinuousSystem Series(const ContinuousSystem& first, const ContinuousSystem& second);
/// Product of two polynomials in descending powers.
std::vector<double> PolyMultiply(const std::vector<double>& p, const std::vector<double>& q);

/// x⁺ = Φ x + G0 u_k + G1 u_{k+1}, y_{k+1} = C x⁺ + D u_{k+1}: the exact solution for an input
/// linear across the step (first-order hold).
struct DiscreteSystem {
  int order{0};
  double dt{0.0};
  std::array<double, kMaxOrder * kMaxOrder> phi{};
  std::array<double, kMaxOrder> g0{};
  std::array<double, kMaxOrder> g1{};
  std::array<double, kMaxOrder> c{};
  double d{0.0};
};

/// Exact FOH discretisation (matrix exponential of the augmented system). @pre dt > 0.
DiscreteSystem Discretize(const ContinuousSystem& system, double dt);

/// What the next step needs: the state and the previous input.
struct FilterState {
  std::array<double, kMaxOrder> x{};
  double u{0.0};
  bool operator==(const FilterState&) const = default;
};

/// Advances one tick to input `u`; returns the output at the new tick. No allocation.
double Step(const DiscreteSystem& system, FilterState& state, double u);
/// The output for the current state and input (no advance).
double Output(const DiscreteSystem& system, const FilterState& state);

// Inline definitions: filters step on every tick.

namespace internal {

/// One step of an order-N system: fully unrolled fixed-size loops.
template <std::size_t N>
inline double StepOrder(const DiscreteSystem& system, FilterState& state, double u) {
  std::array<double, N> next{};
  for (std::size_t r = 0; r < N; ++r) {
    double acc = system.g0[r] * state.u + system.g1[r] * u;
    for (std::size_t c = 0; c < N; ++c) acc += system.phi[r * kMaxOrder + c] * state.x[c];
    next[r] = acc;
  }
  double y = system.d * u;
  for (std::size_t r = 0; r < N; ++r) {
    state.x[r] = next[r];
    y += system.c[r] * next[r];
  }
  state.u = u;
  return y;
}

}  // namespace internal

inline double Step(const DiscreteSystem& system, FilterState& state, double u) {
  static_assert(kMaxOrder == 6, "extend the dispatch below");
  switch (system.order) {
    case 0: state.u = u; return system.d * u;
    case 1: return internal::StepOrder<1>(system, state, u);
    case 2: return internal::StepOrder<2>(system, state, u);
    case 3: return internal::StepOrder<3>(system, state, u);
    case 4: return internal::StepOrder<4>(system, state, u);
    case 5: return internal::StepOrder<5>(system, state, u);
    default: return internal::StepOrder<6>(system, state, u);
  }
}

inline double Output(const DiscreteSystem& system, const FilterState& state) {
  double y = system.d * state.u;
  for (int r = 0; r < system.order; ++r) {
    y += system.c[static_cast<std::size_t>(r)] * state.x[static_cast<std::size_t>(r)];
  }
  return y;
}

}  // namespace pwsim::mca
