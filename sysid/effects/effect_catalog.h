#pragma once
// The effect ids of measured-trials.md and, for each, its family (EffectFamily): the
// parameters as a named vector for grey-box fitting (name, unit, typical scale, bounds,
// starting points) and the family's members, the discrete laws among which the fit chooses
// (sysid/diagnose/greybox_fit.h: FitModelJoint multi-starts members x starts). Also the "truth"
// values of a hidden effect at a given strength (strength 1 = moderate) for synthetic trials.

#include <optional>
#include <span>
#include <string>
#include <utility>
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

/// One fitted parameter of an effect: its name, unit, bounds, starts and the field of
/// EffectParams it is (Set/GetEffectValues read and write through `field`, so an effect's
/// table is the one place its parameters are listed).
struct ParamSpec {
  std::string name;  ///< e.g. "caster_tyre_period_s" (unit suffix)
  double scale{1.0};  ///< typical magnitude (the optimiser works on value/scale)
  double lower{0.0};
  double upper{1.0};
  std::vector<double> starts;  ///< starting values; the members start at their combinations
  double EffectParams::*field{nullptr};  ///< where the value lives (null: not bound)
  const char* unit{"-"};                ///< SI unit, "-" for a ratio
};

/// One discrete law of a family: its setting of the family's EffectMembers field, the
/// starting vectors tried (each a full EffectParameters vector, in this order), the parameters
/// held at their start while it is solved, and how many of its starts are solved. The fit
/// scores every start of every member by its training error and solves the best of each.
struct FamilyMember {
  std::string name;                         ///< e.g. "whole_chair"
  EffectMembers setting;                    ///< its family's field (CopyMember) is the member's
  std::vector<std::vector<double>> starts;  ///< starting vectors, tried in this order
  std::vector<std::size_t> held;            ///< parameters held at their start (e.g. c_t = 0)
  int solved{1};                            ///< the best `solved` starts are solved
  /// ≥ 0: instead of `solved`, the best start of each distinct start value of this parameter
  /// (a start's error can favour one rung over the basin of another).
  int rung{-1};
  /// Its starts compete with the previous member's for that member's solves (one ranking).
  bool ranked_with_previous{false};
  /// Fitted alone, each start is also tried with the suspension raised so that with the start's
  /// tyres in series it keeps the stiffness the data showed.
  bool series_start{false};
};

/// An effect's family: its parameters and its members (one member "law" where the family has
/// a single law; every member shares the parameters), how its member is copied and reported,
/// and its truth for synthetic trials. Each effect's family is one function of
/// effect_catalog.cc (e.g. TyreComplianceFamily): the one place of the catalogue that knows it.
struct EffectFamily {
  EffectId id;
  std::vector<ParamSpec> params;
  std::vector<FamilyMember> members;
  /// Copies the family's field of EffectMembers (its member) from `from` into `to`; null for a
  /// family of one law.
  void (*copy_member)(const EffectMembers& from, EffectMembers& to){nullptr};
  /// The member as named flags for reports (1 or 0); null for a family of one law.
  std::vector<std::pair<std::string, double>> (*member_flags)(const EffectMembers& member){nullptr};
  const char* name{""};         ///< the spec's id (EffectName)
  const char* description{""};  ///< one line (EffectDescription)
  /// The hidden effect's values at strength s > 0 on `chair` (TruthEffect).
  EffectParams (*truth)(double s, const Chair& chair){nullptr};
};

/// The family of effect `id`.
const EffectFamily& Family(EffectId id);
/// The parameters of one effect's extension (Family(id).params).
const std::vector<ParamSpec>& EffectParameters(EffectId id);
/// Effect `id`'s family member in `member` as named flags for reports: cushion_whole_chair
/// (cushion), bump_rebound and bump_compression (stops), 1 or 0; none for the other families.
std::vector<std::pair<std::string, double>> MemberFlags(EffectId id, const EffectMembers& member);
/// Copies effect `id`'s family member (its field of EffectMembers) from `from` into `to`.
void CopyMember(EffectId id, const EffectMembers& from, EffectMembers& to);

/// Writes the named vector `values` (EffectParameters order) into `fx`.
void SetEffectValues(EffectId id, std::span<const double> values, EffectParams& fx);
/// Reads the named vector of effect `id` from `fx`.
std::vector<double> GetEffectValues(EffectId id, const EffectParams& fx);
/// Copies effect `id` from `from` into `to`: its values and its family's discrete member (the
/// cushion's load basis, the stops' sides), nothing of any other effect.
void CopyEffect(EffectId id, const EffectParams& from, EffectParams& to);

/// The hidden-effect parameters for synthetic trials of `chair` at `strength` (1 = moderate;
/// 0 = off). Strength scales the physical size of the effect (radius, compliance, coupling...).
EffectParams TruthEffect(EffectId id, double strength, const Chair& chair);

}  // namespace pwsim::effects
