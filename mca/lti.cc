#include "mca/lti.h"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

using MatrixX = Eigen::MatrixXd;

MatrixX DenseA(const ContinuousSystem& system) {
  MatrixX a(system.order, system.order);
  for (int r = 0; r < system.order; ++r) {
    for (int c = 0; c < system.order; ++c) a(r, c) = system.A(r, c);
  }
  return a;
}

}  // namespace

std::complex<double> ContinuousSystem::Response(double omega) const {
  if (order == 0) return {d, 0.0};
  using Complex = std::complex<double>;
  Eigen::MatrixXcd m(order, order);
  Eigen::VectorXcd rhs(order);
  for (int r = 0; r < order; ++r) {
    for (int col = 0; col < order; ++col) m(r, col) = Complex(-A(r, col), 0.0);
    m(r, r) += Complex(0.0, omega);
    rhs(r) = Complex(b[static_cast<std::size_t>(r)], 0.0);
  }
  const Eigen::VectorXcd x = m.fullPivLu().solve(rhs);
  Complex y(d, 0.0);
  for (int r = 0; r < order; ++r) y += c[static_cast<std::size_t>(r)] * x(r);
  return y;
}

double ContinuousSystem::DcGain() const { return Response(0.0).real(); }

ContinuousSystem Gain(double k) {
  ContinuousSystem s;
  s.d = k;
  return s;
}

ContinuousSystem HighPass1(double omega) {
  PWSIM_DEMAND(omega > 0.0);
  return FromTransferFunction({1.0, 0.0}, {1.0, omega});
}

ContinuousSystem HighPass2(double omega, double zeta) {
  PWSIM_DEMAND(omega > 0.0 && zeta > 0.0);
  return FromTransferFunction({1.0, 0.0, 0.0}, {1.0, 2.0 * zeta * omega, omega * omega});
}

ContinuousSystem LowPass1(double omega) {
  PWSIM_DEMAND(omega > 0.0);
  return FromTransferFunction({omega}, {1.0, omega});
}

ContinuousSystem LowPass2(double omega, double zeta) {
  PWSIM_DEMAND(omega > 0.0 && zeta > 0.0);
  return FromTransferFunction({omega * omega}, {1.0, 2.0 * zeta * omega, omega * omega});
}

ContinuousSystem LeakyIntegrator(double leak) {
  PWSIM_DEMAND(leak >= 0.0);
  return FromTransferFunction({1.0}, {1.0, leak});
}

std::vector<double> PolyMultiply(const std::vector<double>& p, const std::vector<double>& q) {
  PWSIM_DEMAND(!p.empty() && !q.empty());
  std::vector<double> out(p.size() + q.size() - 1, 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = 0; j < q.size(); ++j) out[i + j] += p[i] * q[j];
  }
  return out;
}

ContinuousSystem FromTransferFunction(const std::vector<double>& num,
                                      const std::vector<double>& den) {
  PWSIM_DEMAND(!den.empty() && den.front() != 0.0);
  PWSIM_DEMAND(!num.empty() && num.size() <= den.size());
  const int n = static_cast<int>(den.size()) - 1;
  PWSIM_DEMAND(n <= kMaxOrder);
  // Monic denominator s^n + a1 s^(n-1) + ... + an; numerator padded to degree n.
  const double lead = den.front();
  std::vector<double> a(den.size()), b(den.size(), 0.0);
  for (std::size_t i = 0; i < den.size(); ++i) a[i] = den[i] / lead;
  const std::size_t pad = den.size() - num.size();
  for (std::size_t i = 0; i < num.size(); ++i) b[pad + i] = num[i] / lead;

  // Controllable canonical form: ẋ_i = x_(i+1), ẋ_n = -Σ a_(n+1-i) x_i + u.
  ContinuousSystem s;
  s.order = n;
  s.d = b[0];
  for (int i = 0; i < n; ++i) {
    if (i + 1 < n) s.A(i, i + 1) = 1.0;
    const auto coeff = static_cast<std::size_t>(n - i);  // a_(n-i) multiplies x_(i+1)
    s.A(n - 1, i) = -a[coeff];
    s.c[static_cast<std::size_t>(i)] = b[coeff] - a[coeff] * b[0];
  }
  if (n > 0) s.b[static_cast<std::size_t>(n - 1)] = 1.0;
  return s;
}

ContinuousSystem Series(const ContinuousSystem& first, const ContinuousSystem& second) {
  const int n1 = first.order;
  const int n2 = second.order;
  PWSIM_DEMAND(n1 + n2 <= kMaxOrder);
  ContinuousSystem s;
  s.order = n1 + n2;
  // x = [x1; x2]: ẋ1 = A1 x1 + B1 u; ẋ2 = A2 x2 + B2 (C1 x1 + D1 u); y = C2 x2 + D2 (C1 x1 + D1 u).
  for (int r = 0; r < n1; ++r) {
    for (int c = 0; c < n1; ++c) s.A(r, c) = first.A(r, c);
    s.b[static_cast<std::size_t>(r)] = first.b[static_cast<std::size_t>(r)];
    s.c[static_cast<std::size_t>(r)] = second.d * first.c[static_cast<std::size_t>(r)];
  }
  for (int r = 0; r < n2; ++r) {
    const auto rr = static_cast<std::size_t>(r);
    for (int c = 0; c < n1; ++c) s.A(n1 + r, c) = second.b[rr] * first.c[static_cast<std::size_t>(c)];
    for (int c = 0; c < n2; ++c) s.A(n1 + r, n1 + c) = second.A(r, c);
    s.b[static_cast<std::size_t>(n1 + r)] = second.b[rr] * first.d;
    s.c[static_cast<std::size_t>(n1 + r)] = second.c[rr];
  }
  s.d = second.d * first.d;
  return s;
}

DiscreteSystem Discretize(const ContinuousSystem& system, double dt) {
  PWSIM_DEMAND(dt > 0.0);
  const int n = system.order;
  DiscreteSystem out;
  out.order = n;
  out.dt = dt;
  out.d = system.d;
  out.c = system.c;
  if (n == 0) return out;
  // Augmented [x; u; u̇] with u̇ constant over the step.
  MatrixX m = MatrixX::Zero(n + 2, n + 2);
  m.topLeftCorner(n, n) = DenseA(system);
  for (int r = 0; r < n; ++r) m(r, n) = system.b[static_cast<std::size_t>(r)];
  m(n, n + 1) = 1.0;
  const MatrixX e = (m * dt).exp();
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) out.phi[static_cast<std::size_t>(r * kMaxOrder + c)] = e(r, c);
    // x⁺ = Φ x + Γu u0 + Γv (u1 - u0)/dt.
    const double gamma_u = e(r, n);
    const double gamma_v = e(r, n + 1);
    out.g0[static_cast<std::size_t>(r)] = gamma_u - gamma_v / dt;
    out.g1[static_cast<std::size_t>(r)] = gamma_v / dt;
  }
  return out;
}

}  // namespace pwsim::mca
