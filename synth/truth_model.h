#pragma once
// TruthModel: what the synthetic "real chair" does in `pwsim generate` (generate.h). Given the
// truth chair, the terrain, the load and the chair's true longitudinal motion at the mocap
// frame times, it returns the true Z and θ of O_V at those times. The default is the paper's
// base model (GM eq. 1-2 + exact LM eq. 3-5). Hidden model effects (diagnosis, `--effect ID
// --strength S`) plug in here by implementing this interface (or wrapping a std::function in
// FunctionTruthModel); the generator itself does not change.

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "engine/terrain.h"

namespace pwsim {

struct TruthModelInput {
  const Chair& chair;      ///< the truth chair (gm and lm set)
  const Terrain& terrain;  ///< the ground of this trial
  double load_kg{0.0};     ///< M_u [kg]
  std::span<const double> t;  ///< [s] every frame time, strictly increasing (dropped ones too)
  std::span<const double> x;  ///< [m] true x of O_V at t
  std::span<const double> v;  ///< [m/s] true forward speed at t
  std::span<const double> a;  ///< [m/s^2] true forward acceleration at t
};

struct TruthModelOutput {
  std::vector<double> z;      ///< [m] true Z of O_V at t (0 = flat-ground GM altitude)
  std::vector<double> pitch;  ///< [rad] true θ at t, positive nose-up
};

class TruthModel {
 public:
  virtual ~TruthModel() = default;
  /// Short id written into the generated set's manifest ("base" or an effect id).
  virtual std::string Id() const = 0;
  virtual TruthModelOutput Evaluate(const TruthModelInput& input) const = 0;
};

/// The paper's model: GM + LM driven by x(t) on a 1 kHz internal step.
class BaseTruthModel final : public TruthModel {
 public:
  std::string Id() const override { return "base"; }
  TruthModelOutput Evaluate(const TruthModelInput& input) const override;
};

/// Adapts a callable to the interface.
class FunctionTruthModel final : public TruthModel {
 public:
  using Function = std::function<TruthModelOutput(const TruthModelInput&)>;
  FunctionTruthModel(std::string id, Function function)
      : id_(std::move(id)), function_(std::move(function)) {}
  std::string Id() const override { return id_; }
  TruthModelOutput Evaluate(const TruthModelInput& input) const override {
    return function_(input);
  }

 private:
  std::string id_;
  Function function_;
};

}  // namespace pwsim
