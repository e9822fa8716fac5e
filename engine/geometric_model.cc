#include "engine/geometric_model.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"

namespace pwsim {

GeometricModel::GeometricModel(const Chair& chair) {
  PWSIM_DEMAND(chair.gm.has_value());
  PWSIM_DEMAND(chair.gm->alpha.size() == chair.wheels.size());
  for (const Wheel& wheel : chair.wheels) wheel_x_.push_back(wheel.x);
  alpha_ = chair.gm->alpha;
  for (const PairWeight& pair : chair.gm->beta) {
    PWSIM_DEMAND(pair.i >= 0 && pair.i < pair.j && pair.j < chair.wheel_count());
    if (pair.weight == 0.0) continue;
    const double dx = wheel_x_[pair.i] - wheel_x_[pair.j];
    PWSIM_DEMAND(dx > 0.0);
    pairs_.push_back({pair.i, pair.j, pair.weight, 1.0 / dx});
  }
}

void GeometricModel::ContactHeights(const Terrain& terrain, double x_V,
                                    std::span<double> z_O) const {
  PWSIM_DEMAND(z_O.size() >= wheel_x_.size());
  for (std::size_t i = 0; i < wheel_x_.size(); ++i) z_O[i] = terrain.HeightAt(x_V + wheel_x_[i]);
}

void GeometricModel::ContactHeights(const Terrain& terrain, double x_V, std::span<double> z_O,
                                    std::span<std::size_t> hints) const {
  PWSIM_DEMAND(z_O.size() >= wheel_x_.size() && hints.size() >= wheel_x_.size());
  for (std::size_t i = 0; i < wheel_x_.size(); ++i) z_O[i] = terrain.HeightAtNear(x_V + wheel_x_[i], hints[i]);
}

GeometricOutput GeometricModel::Evaluate(std::span<const double> z_O) const {
  GeometricOutput out;
  for (std::size_t i = 0; i < alpha_.size(); ++i) out.z += alpha_[i] * z_O[i];
  for (const Pair& pair : pairs_) {
    const double rise = z_O[pair.i] - z_O[pair.j];
    // a level pair adds weight · asin(0) = ±0, which leaves the sum's bits as they are (the sum
    // starts at +0 and never becomes -0): skip the asin
    if (rise == 0.0) continue;
    const double sine = std::clamp(rise * pair.inv_dx, -1.0, 1.0);
    out.pitch += pair.weight * std::asin(sine);
  }
  return out;
}

}  // namespace pwsim
