#pragma once
// The effect ids of measured-trials.md and, for each, its parameters as a named vector for
// grey-box fitting (name, unit, typical scale, bounds, starting points) and the "truth" values
// of a hidden effect at a given strength (strength 1 = moderate) for synthetic trials.

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "sysid/effects/effect_model.h"

namespace pwsim::effects {

enum class EffectId {
  kWheelRadius,
  kTyreCompliance,
  kCushionCompliance,
  kHeavePitchCoupling,
  kNonlinearStiffness,
  kSuspensionFriction,
  kInertialPitch,
  kMarkerOffset,
};

inline constexpr int kEffectCount = 8;

/// Every effect, in the spec's table order.
std::span<const EffectId> AllEffects();
/// The spec's id, e.g. "tyre_compliance".
const char* EffectName(EffectId id);
/// One line: what the effect is.
const char* EffectDescription(EffectId id);
/// Parses a spec id; nullopt when unknown.
std::optional<EffectId> ParseEffect(const std::string& name);
/// "wheel_radius, tyre_compliance, ..." for error messages.
std::string EffectNameList();

struct ParamSpec {
  std::string name;  ///< e.g. "caster_tyre_period_s" (unit suffix)
  double scale{1.0};  ///< typical magnitude (the optimiser works on value/scale)
  double lower{0.0};
  double upper{1.0};
  std::vector<double> starts;  ///< starting values tried before the local fit
};

/// The parameters of one effect's extension.
const std::vector<ParamSpec>& EffectParameters(EffectId id);

/// Writes the named vector `values` (EffectParameters order) into `fx`.
void SetEffectValues(EffectId id, std::span<const double> values, EffectParams& fx);
/// Reads the named vector of effect `id` from `fx`.
std::vector<double> GetEffectValues(EffectId id, const EffectParams& fx);
/// Copies effect `id` from `from` into `to`: its values and its family's discrete member (the
/// cushion's load basis, the stops' rebound), nothing of any other effect.
void CopyEffect(EffectId id, const EffectParams& from, EffectParams& to);

/// The hidden-effect parameters for synthetic trials of `chair` at `strength` (1 = moderate;
/// 0 = off). Strength scales the physical size of the effect (radius, compliance, coupling...).
EffectParams TruthEffect(EffectId id, double strength, const Chair& chair);

}  // namespace pwsim::effects
