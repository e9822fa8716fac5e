#include "engine/vehicle/tyre.h"

namespace pwsim::vehicle {

TyreForce CombinedSlipForce(const TyreParams& tyre, double kappa, double tan_alpha, double fz) {
  TyreForce f;
  if (!(fz > 0.0)) return f;
  const double dx = tyre.mu_x * fz;
  const double dy = tyre.mu_y * fz;
  const double sx = tyre.slip_stiffness * fz * kappa / dx;
  const double sy = CorneringStiffness(tyre, fz) * tan_alpha / dy;
  const double s = std::sqrt(sx * sx + sy * sy);
  if (s < 1e-12) {
    f.fx = dx * sx;
    f.fy = dy * sy;
    return f;
  }
  f.fx = dx * UnitMagic(s, tyre.shape_x, tyre.curvature_x) * sx / s;
  f.fy = dy * UnitMagic(s, tyre.shape_y, tyre.curvature_y) * sy / s;
  return f;
}

}  // namespace pwsim::vehicle
