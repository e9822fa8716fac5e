// The trial splits of the diagnosis (report, selection, training) and the measured trials as
// diagnosis records; declared in diagnose.h.
#include <algorithm>
#include <cmath>
#include <map>

#include "engine/check.h"
#include "engine/input_error.h"
#include "sysid/diagnose/diagnose.h"
#include "sysid/diagnose/format_text.h"
#include "sysid/diagnose/lever_from_track.h"
#include "sysid/identify/fitness.h"
#include "sysid/identify/identify.h"

namespace pwsim::diagnose {

std::vector<bool> ChooseHeldOut(const std::vector<effects::TrialRecord>& trials,
                                std::string* description) {
  const std::size_t n = trials.size();
  std::vector<bool> held(n, false);
  auto levels = [&](auto get) {
    std::vector<double> v;
    for (const auto& t : trials) {
      const double key = std::round(get(t) * 20.0) / 20.0;
      if (std::find(v.begin(), v.end(), key) == v.end()) v.push_back(key);
    }
    std::sort(v.begin(), v.end());
    return v;
  };
  auto try_level = [&](auto get, const char* what, const char* unit) {
    const std::vector<double> v = levels(get);
    if (v.size() < 2) return false;
    const double pick = v[(v.size() - 1) / 2];
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
      held[i] = std::round(get(trials[i]) * 20.0) / 20.0 == pick;
      count += held[i];
    }
    if (count == 0 || n - count < 2) {
      std::fill(held.begin(), held.end(), false);
      return false;
    }
    if (description) *description = Format("%s %.2f %s left out", what, pick, unit);
    return true;
  };
  if (try_level([](const auto& t) { return t.speed; }, "speed", "m/s")) return held;
  if (try_level([](const auto& t) { return t.load_kg; }, "load", "kg")) return held;
  for (std::size_t i = 2; i < n; i += 3) held[i] = true;
  if (n == 2) held[1] = true;
  if (description) *description = "every third trial left out";
  return held;
}

namespace {
/// The base model's identification: identify's method with rigid heave (the α sum to 1), so
/// that an obstacle lower under the chair than in its terrain file stays in the residual.
IdentifyOptions BaseIdentifyOptions() {
  IdentifyOptions options;
  options.rigid_heave = true;
  return options;
}
}  // namespace

effects::TrialRecord RecordOf(const MeasuredTrial& trial, const Chair& chair) {
  effects::TrialRecord r;
  r.name = trial.name;
  r.chair = chair;
  r.terrain = trial.terrain;
  r.load_kg = trial.load_kg;
  r.speed = trial.NominalSpeed();
  r.t = trial.track.t;
  r.x = trial.track.x;
  r.z = trial.track.z;
  r.pitch = trial.track.pitch;
  return r;
}

std::vector<effects::TrialRecord> RecordsFromMeasured(const std::vector<MeasuredTrial>& trials,
                                                      std::string* base_source) {
  std::vector<effects::TrialRecord> records;
  for (const MeasuredTrial& m : trials) {
    if (m.chair.wheel_count() != trials.front().chair.wheel_count()) {
      throw InputError(m.chair_file.string(), 0, "wheels",
                       "the same wheels as " + trials.front().chair_file.string(),
                       std::to_string(m.chair.wheel_count()) + " wheels");
    }
    records.push_back(RecordOf(m, m.chair));
  }
  Chair chair = trials.front().chair;
  if (chair.gm && chair.lm) {
    if (base_source) *base_source = "chair.yaml (gm and lm as given)";
    return records;
  }
  const std::vector<bool> held = ChooseHeldOut(records);
  std::vector<MeasuredTrial> training;
  for (std::size_t i = 0; i < trials.size(); ++i)
    if (!held[i]) training.push_back(trials[i]);
  // In the order of their names, whatever order they came in: one set, one base model.
  std::stable_sort(training.begin(), training.end(),
                   [](const MeasuredTrial& a, const MeasuredTrial& b) { return a.name < b.name; });
  try {
    const IdentifyResult id = IdentifyChair(training, AssignRoles(training), BaseIdentifyOptions());
    chair = id.chair;
    if (base_source)
      *base_source = "identified on the training trials (pwsim identify's method, α summing to 1)";
  } catch (const InputError&) {
    // Too few speed levels for the paper's GM/LM roles: GM on every training trial, Table I LM.
    std::vector<const MeasuredTrial*> ptrs;
    for (const MeasuredTrial& m : training) ptrs.push_back(&m);
    chair.gm = IdentifyGeometric(ptrs, chair, BaseIdentifyOptions());
    if (!chair.lm) chair.lm = LumpedParams{};
    if (base_source) *base_source = "GM identified on every training trial (α summing to 1), LM from Table I";
  }
  for (auto& r : records) {
    r.chair = chair;
    r.gm_from_trials = true;
  }
  return records;
}

TrackUnderLever TrackUnderMarkerLever(const effects::TrialRecord& r, double lever_x_m,
                                      double lever_z_m, double rest_window) {
  // θ centred on the rest window (the chair starts at rest on its start level), then the
  // lever taken out: x = x_m - r_x cos θ + r_z sin θ, Z = Z_m - r_x sin θ - r_z (cos θ - 1).
  const double theta0 = RestPitch(r, rest_window);
  TrackUnderLever out{r.x, r.z};
  for (std::size_t k = 0; k < r.t.size(); ++k) {
    const double th = r.pitch[k] - theta0;
    out.x[k] = r.x[k] - lever_x_m * std::cos(th) + lever_z_m * std::sin(th);
    out.z[k] = r.z[k] - lever_x_m * std::sin(th) - lever_z_m * (std::cos(th) - 1.0);
  }
  return out;
}

namespace {
/// The trials RecordsFromMeasured identified the base on (all but the report trials, in the
/// order of their names) as measured trials for `chair`: each track corrected for the marker
/// lever of `fx` and each wheel's contact height scaled by the cushion's yield in `fx`.
std::vector<MeasuredTrial> TrialsUnderEffects(const std::vector<effects::TrialRecord>& records,
                                              const Chair& chair, const effects::EffectParams& fx,
                                              double rest_window) {
  const std::vector<bool> held = ChooseHeldOut(records);
  std::vector<MeasuredTrial> trials;
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (held[i]) continue;
    const effects::TrialRecord& r = records[i];
    MeasuredTrial m;
    m.name = r.name;
    m.chair = chair;
    m.terrain = r.terrain;
    m.load_kg = r.load_kg;
    m.profile.speed = r.speed;
    TrackUnderLever corrected = TrackUnderMarkerLever(r, fx.marker_lever_x, fx.marker_lever_z, rest_window);
    m.track.t = r.t;
    m.track.x = std::move(corrected.x);
    m.track.z = std::move(corrected.z);
    m.track.pitch = r.pitch;
    m.track.y.assign(r.t.size(), 0.0);
    m.contact_height_scale = effects::CushionHeightFactors(chair, r.load_kg, fx);
    trials.push_back(std::move(m));
  }
  std::stable_sort(trials.begin(), trials.end(),
                   [](const MeasuredTrial& a, const MeasuredTrial& b) { return a.name < b.name; });
  return trials;
}

/// The GM trials of `trials` (the slowest speed level), else all.
std::vector<const MeasuredTrial*> GeometricTrials(const std::vector<MeasuredTrial>& trials) {
  const std::vector<TrialRole> roles = AssignRoles(trials);
  std::vector<const MeasuredTrial*> gm_trials;
  for (std::size_t k = 0; k < trials.size(); ++k)
    if (roles[k] == TrialRole::kGeometric) gm_trials.push_back(&trials[k]);
  if (gm_trials.empty())
    for (const MeasuredTrial& m : trials) gm_trials.push_back(&m);
  return gm_trials;
}
}  // namespace

GeometricParams GeometryUnderMarkerLever(const std::vector<effects::TrialRecord>& records,
                                         const Chair& chair, const LumpedParams& lm,
                                         double lever_x_m, double lever_z_m, double rest_window) {
  PWSIM_DEMAND(chair.gm.has_value());
  effects::EffectParams lever;
  lever.marker_lever_x = lever_x_m;
  lever.marker_lever_z = lever_z_m;
  const std::vector<MeasuredTrial> trials = TrialsUnderEffects(records, chair, lever, rest_window);
  return IdentifyGeometric(GeometricTrials(trials), chair, BaseIdentifyOptions(), lm);
}

Chair BaseUnderCushion(const std::vector<effects::TrialRecord>& records, const Chair& chair,
                       const effects::EffectParams& fx, double rest_window) {
  PWSIM_DEMAND(chair.gm.has_value() && chair.lm.has_value());
  const std::vector<MeasuredTrial> trials = TrialsUnderEffects(records, chair, fx, rest_window);
  try {
    return IdentifyChair(trials, AssignRoles(trials), BaseIdentifyOptions()).chair;
  } catch (const InputError&) {
    // Too few speed levels for the paper's roles: the GM alone, under the LM as it is.
    Chair out = chair;
    out.gm = IdentifyGeometric(GeometricTrials(trials), chair, BaseIdentifyOptions(), chair.lm);
    return out;
  }
}

FitPct PooledFitPct(const std::vector<FitTrial>& trials, const effects::ExtendedParams& params) {
  PooledFit fz, fp;
  for (const FitTrial& t : trials) {
    const TrialResidual r = ComputeResidual(t, params);
    if (!r.finite) return {-1e9, -1e9};
    fz.Add(t.z, r.z_model);
    fp.Add(t.pitch, r.pitch_model);
  }
  return {fz.Percent(), fp.Percent()};
}

std::vector<bool> ChooseSelection(const std::vector<effects::TrialRecord>& trials,
                                  const std::vector<bool>& report) {
  std::vector<std::size_t> rest;
  for (std::size_t i = 0; i < trials.size(); ++i)
    if (!report[i]) rest.push_back(i);
  std::stable_sort(rest.begin(), rest.end(), [&](std::size_t a, std::size_t b) {
    if (trials[a].speed != trials[b].speed) return trials[a].speed < trials[b].speed;
    return trials[a].load_kg < trials[b].load_kg;
  });
  std::vector<bool> selection(trials.size(), false);
  std::size_t chosen = 0;
  for (std::size_t k = 0; k < rest.size(); ++k) {
    if (k % 3 == (k / 3) % 3 && rest.size() - chosen - 1 >= 2) {
      selection[rest[k]] = true;
      ++chosen;
    }
  }
  return selection;
}

}  // namespace pwsim::diagnose
