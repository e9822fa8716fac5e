#include "sysid/effects/effect_catalog.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <utility>

#include "engine/check.h"

namespace pwsim::effects {
namespace {

constexpr std::array<EffectId, kEffectCount> kAll{
    EffectId::kWheelRadius,        EffectId::kTyreCompliance,     EffectId::kCushionCompliance,
    EffectId::kHeavePitchCoupling, EffectId::kNonlinearStiffness, EffectId::kSuspensionFriction,
    EffectId::kInertialPitch,      EffectId::kMarkerOffset};

int Index(EffectId id) { return static_cast<int>(id); }

double MeanRadius(const Chair& chair, bool casters) {
  const std::vector<bool> caster = CasterWheels(chair);
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < chair.wheels.size(); ++i) {
    if (caster[i] != casters) continue;
    sum += chair.wheels[i].radius;
    ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

}  // namespace

std::span<const EffectId> AllEffects() { return kAll; }

const char* EffectName(EffectId id) { return Family(id).name; }

const char* EffectDescription(EffectId id) { return Family(id).description; }

std::optional<EffectId> ParseEffect(const std::string& name) {
  for (EffectId id : kAll) {
    if (name == EffectName(id)) return id;
  }
  return std::nullopt;
}

std::string EffectNameList() {
  std::string list;
  for (EffectId id : kAll) {
    if (!list.empty()) list += ", ";
    list += EffectName(id);
  }
  return list;
}

namespace {

/// Every combination of the parameters' start lists (the first parameter varying fastest),
/// each parameter's list replaced where `lists` gives one; combinations `keep` rejects are left
/// out.
std::vector<std::vector<double>> StartGrid(
    const std::vector<ParamSpec>& params, std::vector<std::vector<double>> lists = {},
    const std::function<bool(const std::vector<double>&)>& keep = {}) {
  lists.resize(params.size());
  for (std::size_t j = 0; j < params.size(); ++j)
    if (lists[j].empty()) lists[j] = params[j].starts;
  std::vector<std::vector<double>> grid;
  std::vector<std::size_t> index(params.size(), 0);
  while (true) {
    std::vector<double> start(params.size());
    for (std::size_t j = 0; j < params.size(); ++j) start[j] = lists[j][index[j]];
    if (!keep || keep(start)) grid.push_back(std::move(start));
    std::size_t j = 0;
    while (j < params.size() && ++index[j] == lists[j].size()) index[j++] = 0;
    if (j == params.size()) return grid;
  }
}

FamilyMember Member(std::string name, std::vector<std::vector<double>> starts) {
  FamilyMember member;
  member.name = std::move(name);
  member.starts = std::move(starts);
  return member;
}

// ---- wheel_radius ----
EffectFamily WheelRadiusFamily() {
  using F = EffectParams;
  EffectFamily family{EffectId::kWheelRadius, {}, {}};
  family.name = "wheel_radius";
  family.description =
      "finite wheel radius: wheel centres ride the rolling-disc envelope of the ground";
  family.params = {
      {"caster_radius_m", 0.1, 0.0, 0.35, {0.04, 0.12}, &F::caster_radius, "m"},
      {"drive_radius_m", 0.1, 0.0, 0.40, {0.04, 0.18}, &F::drive_radius, "m"}};
  const std::vector<ParamSpec>& p = family.params;
  family.members = {Member("law", StartGrid(p))};
  family.truth = [](double s, const Chair& chair) {
    EffectParams fx;
    fx.caster_radius = s * MeanRadius(chair, true);
    fx.drive_radius = s * MeanRadius(chair, false);
    return fx;
  };
  return family;
}

// ---- tyre_compliance ----
EffectFamily TyreComplianceFamily() {
  using F = EffectParams;
  EffectFamily family{EffectId::kTyreCompliance, {}, {}};
  family.name = "tyre_compliance";
  family.description =
      "vertical tyre compliance: series spring-damper per wheel, with an unsprung mass or massless";
  family.params = {
      {"caster_tyre_period_s", 0.1, 0.02, 1.0, {0.06, 0.15, 0.4}, &F::caster_tyre_period, "s"},
      {"drive_tyre_period_s", 0.1, 0.02, 1.0, {0.05, 0.15}, &F::drive_tyre_period, "s"},
      {"tyre_damping_ratio", 0.3, 0.05, 1.0, {0.3}, &F::tyre_damping, "-"},
      {"caster_tyre_compliance_m_per_n", 5e-5, 0.0, 5e-4, {0.0, 5e-5, 2.5e-4},
          &F::caster_tyre_compliance, "m/N"},
      {"drive_tyre_compliance_m_per_n", 1e-5, 0.0, 2e-4, {0.0, 1e-5, 6e-5},
          &F::drive_tyre_compliance, "m/N"},
      {"tyre_time_constant_s", 0.005, 1e-4, 0.05, {0.005}, &F::tyre_time_constant, "s"},
      {"rear_caster_compliance_ratio", 0.5, 0.2, 5.0, {1.0}, &F::rear_caster_compliance_ratio,
          "-"}};
  const std::vector<ParamSpec>& p = family.params;
  // Stiff tyres (c_t held at 0: a filter of the ground with no reaction; the best two
  // starts solved, their periods lying in different basins more often than not) and
  // compliant tyres in series with each wheel's own suspension spring (the best start of
  // each caster-compliance rung: a start's error favours the stiff rungs, whose fits stay
  // near the base model, over a soft tyre's basin).
  // Massless tyres in series (no unsprung mass: the periods and ζ held, the dampers' time
  // constant and the rear casters' compliance ratio fitted), the best start of each
  // caster-compliance rung as well.
  auto compliant_tyre = [](const std::vector<double>& s) { return s[3] > 0.0 || s[4] > 0.0; };
  FamilyMember stiff = Member("stiff", StartGrid(p, {{}, {}, {}, {0.0}, {0.0}}));
  stiff.held = {3, 4, 5, 6};
  stiff.solved = 2;
  FamilyMember compliant = Member("compliant", StartGrid(p, {}, compliant_tyre));
  compliant.held = {5, 6};
  compliant.rung = 3;
  compliant.series_start = true;
  FamilyMember massless =
      Member("massless", StartGrid(p, {{0.15}, {0.15}, {0.3}, {}, {}, {0.003, 0.008}}, compliant_tyre));
  massless.setting.tyre = TyreLaw::kMassless;
  massless.held = {0, 1, 2};
  massless.rung = 3;
  massless.series_start = true;
  family.members = {stiff, compliant, massless};
  family.copy_member = [](const EffectMembers& from, EffectMembers& to) { to.tyre = from.tyre; };
  family.member_flags = [](const EffectMembers& m) -> std::vector<std::pair<std::string, double>> {
    return {{"tyre_massless", m.tyre == TyreLaw::kMassless ? 1.0 : 0.0}};
  };
  family.truth = [](double s, const Chair&) {
    EffectParams fx;
    // Casters 5 Hz and drive wheels 12.5 Hz at s = 1; softer and less damped above.
    fx.caster_tyre_period = std::clamp(0.2 * s, 0.045, 1.0);
    fx.drive_tyre_period = std::clamp(0.08 * s, 0.045, 1.0);
    fx.tyre_damping = std::max(0.05, 0.25 / std::pow(std::max(1.0, s), 1.75));
    return fx;
  };
  return family;
}

// ---- cushion_compliance ----
EffectFamily CushionComplianceFamily() {
  using F = EffectParams;
  EffectFamily family{EffectId::kCushionCompliance, {}, {}};
  family.name = "cushion_compliance";
  family.description =
      "the obstacle yields under load: effective height h (g - c (W/1 kN)^p), W per wheel or whole chair";
  family.params = {
      {"cushion_loss_per_kn", 0.2, 0.0, 1.2, {0.1, 0.4}, &F::cushion_loss_per_kn, "-"},
      {"cushion_height_gain", 0.2, 0.5, 1.5, {1.0}, &F::cushion_height_gain, "-"},
      {"cushion_exponent", 0.5, 0.3, 2.5, {1.0}, &F::cushion_exponent, "-"},
      {"cushion_pitch_gain", 0.2, 0.5, 2.0, {1.0}, &F::cushion_pitch_gain, "-"}};
  const std::vector<ParamSpec>& p = family.params;
  // The load basis: each wheel's static load or the whole chair's weight; one ranking, the
  // better start solved.
  FamilyMember whole = Member("whole_chair", StartGrid(p));
  whole.setting.cushion_load = CushionLoad::kWholeChair;
  whole.ranked_with_previous = true;
  family.members = {Member("per_wheel", StartGrid(p)), whole};
  family.copy_member = [](const EffectMembers& from, EffectMembers& to) {
    to.cushion_load = from.cushion_load;
  };
  family.member_flags = [](const EffectMembers& m) -> std::vector<std::pair<std::string, double>> {
    return {{"cushion_whole_chair", m.cushion_load == CushionLoad::kWholeChair ? 1.0 : 0.0}};
  };
  family.truth = [](double s, const Chair&) {
    EffectParams fx;
    fx.cushion_loss_per_kn = 0.12 * s;
    return fx;
  };
  return family;
}

// ---- heave_pitch_coupling ----
EffectFamily HeavePitchCouplingFamily() {
  using F = EffectParams;
  EffectFamily family{EffectId::kHeavePitchCoupling, {}, {}};
  family.name = "heave_pitch_coupling";
  family.description =
      "off-diagonal stiffness and damping between heave and pitch";
  family.params = {
      {"stiffness_coupling", 0.2, -0.8, 0.8, {-0.2, 0.2}, &F::stiffness_coupling, "-"},
      {"damping_coupling", 0.2, -0.8, 0.8, {0.0}, &F::damping_coupling, "-"}};
  const std::vector<ParamSpec>& p = family.params;
  family.members = {Member("law", StartGrid(p))};
  family.truth = [](double s, const Chair&) {
    EffectParams fx;
    fx.stiffness_coupling = std::min(0.8, 0.3 * s);
    fx.damping_coupling = std::min(0.8, 0.3 * s);
    return fx;
  };
  return family;
}

// ---- nonlinear_stiffness ----
EffectFamily NonlinearStiffnessFamily() {
  using F = EffectParams;
  EffectFamily family{EffectId::kNonlinearStiffness, {}, {}};
  family.name = "nonlinear_stiffness";
  family.description =
      "progressive (hardening) suspension stiffness: symmetric cubic and per-wheel bump stops, "
      "in compression or both ways";
  family.params = {
      {"heave_hardening", 0.5, 0.0, 10.0, {0.3}, &F::heave_hardening, "-"},
      {"pitch_hardening", 0.5, 0.0, 10.0, {0.3}, &F::pitch_hardening, "-"},
      {"bump_gain", 0.5, 0.0, 20.0, {0.0, 1.0}, &F::bump_gain, "-"},
      {"bump_gap_m", 0.005, 0.0, 0.03, {0.004}, &F::bump_gap, "m"}};
  const std::vector<ParamSpec>& p = family.params;
  // Stops in compression only, in rebound as well, or in rebound only (with stops: b > 0),
  // the best start of each solved (a start's error hardly tells them apart).
  FamilyMember both = Member("both", StartGrid(p, {{}, {}, {1.0}, {}}));
  both.setting.stops = StopSides::kBoth;
  FamilyMember rebound = Member("rebound", StartGrid(p, {{}, {}, {1.0}, {}}));
  rebound.setting.stops = StopSides::kRebound;
  family.members = {Member("compression", StartGrid(p)), both, rebound};
  family.copy_member = [](const EffectMembers& from, EffectMembers& to) { to.stops = from.stops; };
  family.member_flags = [](const EffectMembers& m) -> std::vector<std::pair<std::string, double>> {
    return {{"bump_rebound", m.stops != StopSides::kCompression ? 1.0 : 0.0},
            {"bump_compression", m.stops != StopSides::kRebound ? 1.0 : 0.0}};
  };
  family.truth = [](double s, const Chair&) {
    EffectParams fx;
    fx.heave_hardening = 1.0 * s;
    fx.pitch_hardening = 1.0 * s;
    return fx;
  };
  return family;
}

// ---- suspension_friction ----
EffectFamily SuspensionFrictionFamily() {
  using F = EffectParams;
  EffectFamily family{EffectId::kSuspensionFriction, {}, {}};
  family.name = "suspension_friction";
  family.description =
      "dry (Coulomb) friction in the suspension: Dahl's law or smooth Coulomb, per wheel";
  family.params = {
      {"caster_friction_n", 20.0, 0.0, 250.0, {10.0, 40.0}, &F::caster_friction, "N"},
      {"drive_friction_n", 20.0, 0.0, 250.0, {10.0, 40.0}, &F::drive_friction, "N"},
      {"friction_presliding_m", 5e-4, 5e-5, 5e-3, {2e-4, 1e-3}, &F::friction_presliding, "m"},
      {"friction_smooth_rate_mps", 5e-3, 5e-4, 5e-2, {5e-3}, &F::friction_smooth_rate, "m/s"}};
  const std::vector<ParamSpec>& p = family.params;
  // Dahl's law (v_s held) and smooth Coulomb (δ_p held), the best start of each solved.
  FamilyMember dahl = Member("dahl", StartGrid(p));
  dahl.held = {3};
  FamilyMember smooth = Member("smooth_coulomb", StartGrid(p, {{}, {}, {5e-4}, {2e-3, 8e-3}}));
  smooth.setting.friction = FrictionLaw::kSmoothCoulomb;
  smooth.held = {2};
  family.members = {dahl, smooth};
  family.copy_member = [](const EffectMembers& from, EffectMembers& to) { to.friction = from.friction; };
  family.member_flags = [](const EffectMembers& m) -> std::vector<std::pair<std::string, double>> {
    return {{"friction_smooth_coulomb", m.friction == FrictionLaw::kSmoothCoulomb ? 1.0 : 0.0}};
  };
  family.truth = [](double s, const Chair&) {
    EffectParams fx;
    fx.caster_friction = 40.0 * s;
    fx.drive_friction = 60.0 * s;
    fx.friction_presliding = 5e-4;
    return fx;
  };
  return family;
}

// ---- inertial_pitch ----
EffectFamily InertialPitchFamily() {
  using F = EffectParams;
  EffectFamily family{EffectId::kInertialPitch, {}, {}};
  family.name = "inertial_pitch";
  family.description =
      "pitch torque from longitudinal acceleration (the Γθ term), chair and occupant levers";
  family.params = {
      {"cm_lever_m", 0.2, -1.5, 1.5, {0.0}, &F::cm_lever, "m"},
      {"load_cm_lever_m", 0.2, -1.5, 1.5, {0.0}, &F::load_cm_lever, "m"}};
  const std::vector<ParamSpec>& p = family.params;
  family.members = {Member("law", StartGrid(p))};
  family.truth = [](double s, const Chair& chair) {
    EffectParams fx;
    fx.cm_lever = chair.cm_height * s;
    fx.load_cm_lever = chair.cm_height * s;
    return fx;
  };
  return family;
}

// ---- marker_offset ----
EffectFamily MarkerOffsetFamily() {
  using F = EffectParams;
  EffectFamily family{EffectId::kMarkerOffset, {}, {}};
  family.name = "marker_offset";
  family.description =
      "tracked origin not at O_V: a lever arm (forward, up) mixes pitch into the measured x and altitude";
  family.params = {
      {"marker_lever_x_m", 0.1, -1.0, 1.0, {0.0, 0.15}, &F::marker_lever_x, "m"},
      {"marker_lever_z_m", 0.2, -1.5, 1.5, {0.0, 0.5}, &F::marker_lever_z, "m"}};
  const std::vector<ParamSpec>& p = family.params;
  family.members = {Member("law", StartGrid(p))};
  family.truth = [](double s, const Chair&) {
    EffectParams fx;
    fx.marker_lever_x = 0.15 * s;
    return fx;
  };
  return family;
}

EffectFamily MakeFamily(EffectId id) {
  using Make = EffectFamily (*)();
  static constexpr std::array<Make, kEffectCount> make{
      WheelRadiusFamily,        TyreComplianceFamily,     CushionComplianceFamily,
      HeavePitchCouplingFamily, NonlinearStiffnessFamily, SuspensionFrictionFamily,
      InertialPitchFamily,      MarkerOffsetFamily};
  return make[static_cast<std::size_t>(Index(id))]();
}

}  // namespace

const EffectFamily& Family(EffectId id) {
  static const std::array<EffectFamily, kEffectCount> families = [] {
    std::array<EffectFamily, kEffectCount> all;
    for (EffectId e : kAll) all[static_cast<std::size_t>(Index(e))] = MakeFamily(e);
    return all;
  }();
  return families[static_cast<std::size_t>(Index(id))];
}

const std::vector<ParamSpec>& EffectParameters(EffectId id) { return Family(id).params; }

std::vector<std::pair<std::string, double>> MemberFlags(EffectId id, const EffectMembers& member) {
  const EffectFamily& family = Family(id);
  return family.member_flags ? family.member_flags(member) : std::vector<std::pair<std::string, double>>{};
}

void CopyMember(EffectId id, const EffectMembers& from, EffectMembers& to) {
  const EffectFamily& family = Family(id);
  if (family.copy_member) family.copy_member(from, to);
}

void CopyEffect(EffectId id, const EffectParams& from, EffectParams& to) {
  SetEffectValues(id, GetEffectValues(id, from), to);
  CopyMember(id, from.member, to.member);
}

void SetEffectValues(EffectId id, std::span<const double> v, EffectParams& fx) {
  const std::vector<ParamSpec>& params = EffectParameters(id);
  PWSIM_DEMAND(v.size() == params.size());
  for (std::size_t j = 0; j < params.size(); ++j) fx.*params[j].field = v[j];
}

std::vector<double> GetEffectValues(EffectId id, const EffectParams& fx) {
  std::vector<double> v;
  for (const ParamSpec& spec : EffectParameters(id)) v.push_back(fx.*spec.field);
  return v;
}

EffectParams TruthEffect(EffectId id, double strength, const Chair& chair) {
  if (strength <= 0.0) return EffectParams{};
  return Family(id).truth(strength, chair);
}

}  // namespace pwsim::effects
