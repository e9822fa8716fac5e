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
