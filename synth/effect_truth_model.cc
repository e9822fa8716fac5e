#include "synth/effect_truth_model.h"

#include <stdexcept>
#include <vector>

#include "engine/number_format.h"

namespace pwsim::effects {

std::shared_ptr<const TruthModel> MakeEffectTruthModel(
    EffectId id, double strength, const Chair& truth,
    const std::map<std::string, double>& overrides) {
  EffectParams fx = TruthEffect(id, strength, truth);
  if (!overrides.empty()) {
    const std::vector<ParamSpec>& specs = EffectParameters(id);
    std::vector<double> values = GetEffectValues(id, fx);
    for (const auto& [name, value] : overrides) {
      std::size_t j = 0;
      while (j < specs.size() && specs[j].name != name) ++j;
      if (j == specs.size()) {
        std::string names;
        for (const ParamSpec& s : specs) names += (names.empty() ? "" : ", ") + s.name;
        throw std::invalid_argument("effect parameter '" + name + "': expected one of " + names +
                                    " (effect " + EffectName(id) + ")");
      }
      if (!(value >= specs[j].lower && value <= specs[j].upper)) {
        throw std::invalid_argument("effect parameter '" + name + "': expected a number in [" +
                                    FormatDouble(specs[j].lower) + ", " +
                                    FormatDouble(specs[j].upper) + "], got " + FormatDouble(value));
      }
      values[j] = value;
    }
    SetEffectValues(id, values, fx);
  }
  return std::make_shared<FunctionTruthModel>(
      EffectName(id), [fx](const TruthModelInput& in) {
        PreparedTrial trial = PrepareTrial(in.chair, in.terrain, in.load_kg,
                                           std::vector<double>(in.t.begin(), in.t.end()),
                                           std::vector<double>(in.x.begin(), in.x.end()),
                                           std::vector<double>(in.a.begin(), in.a.end()));
        trial.step = 1e-3;
        const ModelOutput out = SimulateExtended(trial, ExtendedParams{*in.chair.lm, fx});
        return TruthModelOutput{out.z, out.pitch};
      });
}

}  // namespace pwsim::effects
