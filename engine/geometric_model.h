#pragma once
// Geometric model (GM), seed 000 eq. (1)-(2): wheel contact heights Z_Oi -> the altitude Z_GM
// and pitch θ_GM of the chair reference point O_V.
//   Z_GM = Σ_i α_i Z_Oi
//   θ_GM = Σ_{i<j} β_ij asin((Z_Oi - Z_Oj) / dx_ij),  dx_ij = x_i - x_j > 0 (wheels front to rear)
// Contacts are points under each wheel's x on the ground (the paper's model); extensions such
// as the rolling-disc envelope of a finite wheel live elsewhere.

#include <span>
#include <vector>

#include "engine/chair.h"
#include "engine/terrain.h"

namespace pwsim {

struct GeometricOutput {
  double z{0.0};      ///< Z_GM [m]
  double pitch{0.0};  ///< θ_GM [rad], positive nose-up
};

class GeometricModel {
 public:
  /// @pre chair.gm is set and sized to the chair's wheels.
  explicit GeometricModel(const Chair& chair);

  int wheel_count() const { return static_cast<int>(wheel_x_.size()); }

  /// Z_Oi = z(x_V + x_i) for each wheel [m]; `z_O` has wheel_count() entries.
  void ContactHeights(const Terrain& terrain, double x_V, std::span<double> z_O) const;

  /// The same heights, bit for bit, with each wheel's terrain search started at its `hints`
  /// entry (updated): the per-tick path of ChairSimulator.
  void ContactHeights(const Terrain& terrain, double x_V, std::span<double> z_O,
                      std::span<std::size_t> hints) const;

  /// Eq. (1)-(2). The asin argument is clamped to [-1, 1] (a slope steeper than vertical
  /// between two contacts is not a chair on the ground).
  GeometricOutput Evaluate(std::span<const double> z_O) const;

 private:
  struct Pair {
    int i{0};
    int j{1};
    double weight{0.0};
    double inv_dx{1.0};  ///< 1/dx_ij [1/m]
  };
  std::vector<double> wheel_x_;
  std::vector<double> alpha_;
  std::vector<Pair> pairs_;
};

}  // namespace pwsim
