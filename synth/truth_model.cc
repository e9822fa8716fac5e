#include "synth/truth_model.h"

#include "sysid/measured/measured_trial.h"

namespace pwsim {

TruthModelOutput BaseTruthModel::Evaluate(const TruthModelInput& input) const {
  ModelOutput model =
      SimulateMeasuredTrial(input.chair, input.terrain, input.load_kg, input.t, input.x);
  return {std::move(model.z), std::move(model.pitch)};
}

}  // namespace pwsim
