#pragma once
// (cos θ, sin θ) carried from tick to tick instead of evaluated: rotating by a small step δ,
//   cos(θ + δ) = c cos δ - s sin δ,   sin(θ + δ) = s cos δ + c sin δ,
// with cos δ, sin δ from their Taylor series for |δ| <= 0.01 (terms to δ⁶ and δ⁵: truncation
// below δ⁷/5040 < 2e-18) and from libm beyond; the pair is renormalised (one Newton step of
// 1/√(c² + s²) from 1, exact to rounding for a length within 1e-8 of 1) so that rounding does
// not accumulate in its length. Deterministic: same inputs, same bits.

#include <cmath>

namespace pwsim {

/// (cos δ, sin δ) of one small step δ, as RotateBy evaluates them: computed once, a rotation
/// by the same δ can be applied several times (ApplyRotation) with the same bits as RotateBy.
struct SmallRotation {
  double cos_delta{1.0}, sin_delta{0.0};
};

inline SmallRotation MakeSmallRotation(double delta) {
  if (std::abs(delta) <= 0.01) {
    const double d2 = delta * delta;
    return {1.0 - d2 * (0.5 - d2 * (1.0 / 24.0 - d2 * (1.0 / 720.0))),
            delta * (1.0 - d2 * (1.0 / 6.0 - d2 * (1.0 / 120.0)))};
  }
  return {std::cos(delta), std::sin(delta)};
}

/// (c, s) rotated by the step and renormalised. @pre the step is not 0 (RotateBy leaves the
/// pair untouched then).
inline void ApplyRotation(double& c, double& s, const SmallRotation& step) {
  const double next_c = c * step.cos_delta - s * step.sin_delta;
  const double next_s = s * step.cos_delta + c * step.sin_delta;
  const double inverse_length = 1.5 - 0.5 * (next_c * next_c + next_s * next_s);
  c = next_c * inverse_length;
  s = next_s * inverse_length;
}

inline void RotateBy(double& c, double& s, double delta) {
  if (delta == 0.0) return;
  ApplyRotation(c, s, MakeSmallRotation(delta));
}

}  // namespace pwsim
