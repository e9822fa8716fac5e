#pragma once
// A hidden effect as the "real chair" of `pwsim generate --effect ID --strength S`: the
// extended model (effect_model.h) with the effect's truth parameters (effect_catalog.h,
// optionally overridden by name) plugged into the generator's TruthModel interface.

#include <map>
#include <memory>
#include <string>

#include "sysid/effects/effect_catalog.h"
#include "synth/truth_model.h"

namespace pwsim::effects {

/// @throws std::invalid_argument naming an override that is not a parameter of `id` or lies
/// outside the parameter's admissible range.
std::shared_ptr<const TruthModel> MakeEffectTruthModel(
    EffectId id, double strength, const Chair& truth,
    const std::map<std::string, double>& overrides = {});

}  // namespace pwsim::effects
