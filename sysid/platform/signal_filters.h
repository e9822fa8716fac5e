#pragma once
// Digital filters of the identification chain, defined as MATLAB/scipy define them so that the
// reference method (Janot/Gautier IDIM-LS on EMPS) is reproduced sample for sample:
//   Butterworth(N, Wn)     = MATLAB butter(N, Wn)          (Wn: fraction of Nyquist)
//   ChebyshevI(N, rp, Wn)  = MATLAB cheby1(N, rp, Wn)
//   FiltFilt(b, a, x)      = MATLAB filtfilt: odd reflection of 3·(nfilt−1) samples at both
//                            ends, steady-state initial conditions (scipy lfilter_zi) scaled
//                            by the first sample, forward pass, backward pass.
//   Decimate(x, r)         = MATLAB decimate(x, r): cheby1(8, 0.05 dB, 0.8/r), FiltFilt, then
//                            keep samples nbeg, nbeg+r, ... with nbeg = r − (r·nout − n) (1-based).
//   DiffCentral(x, dt)     = centred difference (x[k+1] − x[k−1])/(2 dt) inside, one-sided at
//                            both ends (the reference method's diffcent.m).
// Designs: analogue prototype poles (Butterworth: exp(jπ(2k+N−1)/(2N)); Chebyshev I:
// −sinh(μ + jπm/(2N)), μ = asinh(1/ε)/N, ε = √(10^(rp/10) − 1)), prewarped cut-off
// 4·tan(πWn/2), bilinear transform with fs = 2, N zeros at z = −1.
// Tested against scipy.signal and the published coefficients (tests/sysid/platform/).

#include <vector>

namespace pwsim::sysid::platform {

struct TransferFunction {
  std::vector<double> b;  ///< numerator, descending powers of z^-1... b[0] + b[1] z^-1 + ...
  std::vector<double> a;  ///< denominator, a[0] = 1
};

/// @throws std::invalid_argument unless 1 <= order <= 20 and 0 < wn < 1.
TransferFunction Butterworth(int order, double wn);
/// @throws std::invalid_argument unless 1 <= order <= 20, ripple_db > 0 and 0 < wn < 1.
TransferFunction ChebyshevI(int order, double ripple_db, double wn);

/// Direct form II transposed filter (MATLAB filter / scipy lfilter) from state `z`
/// (size max(len a, len b) − 1), which it updates.
void Filter(const TransferFunction& tf, const std::vector<double>& x, std::vector<double>& y,
            std::vector<double>& z);
/// Steady-state initial conditions for a unit step input (scipy lfilter_zi).
std::vector<double> SteadyStateInitial(const TransferFunction& tf);
/// The state from which Filter continues the quadratic input x_k = c0 + c1·k + c2·k²
/// (k = 0, 1, ...) on its forced response, without a start transient: a filter started on a
/// signal that is already moving (a block cut out of a recording). The forced response of
/// A(q⁻¹)y = B(q⁻¹)x to a quadratic is a quadratic y_k = d0 + d1·k + d2·k²; matching powers of
/// k with S_j(c) = Σ_i i^j c_i:
///   d2·S0(a) = c2·S0(b),
///   d1·S0(a) − 2d2·S1(a) = c1·S0(b) − 2c2·S1(b),
///   d0·S0(a) − d1·S1(a) + d2·S2(a) = c0·S0(b) − c1·S1(b) + c2·S2(b);
/// the state is what the past x_k, y_k (k < 0) of the same polynomials leave in the direct form
/// II transposed: z_j = Σ_{i>j} (b_i·x_{j−i} − a_i·y_{j−i}).
/// @throws std::invalid_argument when A(1) = 0 (a pole at z = 1: no steady state).
std::vector<double> PolynomialSteadyState(const TransferFunction& tf, double c0, double c1,
                                          double c2);
/// Zero-phase filtering with MATLAB's edge handling. @throws std::invalid_argument when x is
/// not longer than 3·(nfilt − 1) samples.
std::vector<double> FiltFilt(const TransferFunction& tf, const std::vector<double>& x);
/// MATLAB decimate(x, r) with its default Chebyshev I filter. @throws std::invalid_argument
/// when r < 1 or x is too short.
std::vector<double> Decimate(const std::vector<double>& x, int r);
/// Index (0-based) of the first sample Decimate keeps for a signal of n samples.
int DecimateFirstIndex(int n, int r);
/// Centred first difference; one-sided at both ends. @throws std::invalid_argument for < 2 samples.
std::vector<double> DiffCentral(const std::vector<double>& x, double dt);

}  // namespace pwsim::sysid::platform
