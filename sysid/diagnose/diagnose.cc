#include "sysid/diagnose/diagnose.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "engine/check.h"
#include "sysid/identify/fitness.h"
#include "sysid/identify/identify.h"
#include "engine/input_error.h"
#include "sysid/diagnose/base_residuals.h"
#include "sysid/diagnose/format_text.h"

namespace pwsim::diagnose {
namespace {

using effects::EffectId;

double HeldOutError(const std::vector<FitTrial>& trials, const effects::ExtendedParams& params,
                    const ChannelWeights& w) {
  std::size_t n = 0;
  const double sse = WeightedSse(trials, params, w, &n);
  return n > 0 ? std::sqrt(sse / static_cast<double>(n)) : 0.0;
}

std::vector<std::pair<std::string, double>> NamedParameters(const FitResult& fit) {
  std::vector<std::pair<std::string, double>> out;
  std::size_t col = 0;
  for (EffectId id : fit.effects) {
    const auto& specs = effects::EffectParameters(id);
    for (std::size_t j = 0; j < specs.size(); ++j) out.emplace_back(specs[j].name, fit.effect_values[col++]);
    if (id == EffectId::kCushionCompliance)
      out.emplace_back("cushion_whole_chair", fit.params.fx.cushion_whole_chair ? 1.0 : 0.0);
    if (id == EffectId::kNonlinearStiffness)
      out.emplace_back("bump_rebound", fit.params.fx.bump_rebound ? 1.0 : 0.0);
  }
  out.emplace_back("k_z", fit.params.lm.k_z);
  out.emplace_back("c_z", fit.params.lm.c_z);
  out.emplace_back("k_theta", fit.params.lm.k_theta);
  out.emplace_back("c_theta", fit.params.lm.c_theta);
  return out;
}

}  // namespace


namespace {

/// Weighted mean square per residual (both channels) of `params` on `trials`.
double MeanSquareError(const std::vector<FitTrial>& trials, const effects::ExtendedParams& params,
                       const ChannelWeights& w) {
  std::size_t n = 0;
  const double sse = WeightedSse(trials, params, w, &n);
  return n > 0 ? sse / static_cast<double>(n) : 0.0;
}

std::vector<ResidualRecord> ResidualRecords(const std::vector<FitTrial>& trials,
                                            const std::vector<effects::TrialRecord>& records,
                                            const std::vector<std::size_t>& index,
                                            const effects::ExtendedParams& params) {
  std::vector<ResidualRecord> out;
  for (std::size_t k = 0; k < trials.size(); ++k) {
    const TrialResidual r = ComputeResidual(trials[k], params);
    const effects::TrialRecord& rec = records[index[k]];
    ResidualRecord rr;
    rr.name = rec.name;
    rr.speed = rec.speed;
    rr.load_kg = rec.load_kg;
    rr.t = rec.t;
    rr.x = rec.x;
    if (r.finite) {
      rr.e_z = r.e_z;
      rr.e_pitch = r.e_pitch;
      rr.gm_z = r.model.z_gm;
      rr.gm_pitch = r.model.pitch_gm;
    } else {
      rr.e_z.assign(rec.t.size(), 1.0);
      rr.e_pitch.assign(rec.t.size(), 1.0);
    }
    out.push_back(std::move(rr));
  }
  return out;
}

}  // namespace

Diagnosis Diagnose(const std::vector<effects::TrialRecord>& records_given,
                   const DiagnoseOptions& options) {
  PWSIM_DEMAND(records_given.size() >= 2);
  std::vector<effects::TrialRecord> records = records_given;  // in the order of their names
  std::stable_sort(records.begin(), records.end(), [](const effects::TrialRecord& a, const effects::TrialRecord& b) {
    return a.name < b.name;
  });
  Diagnosis dx;
  dx.chair = records.front().chair;
  PWSIM_DEMAND(dx.chair.gm.has_value());
  const std::vector<bool> held = ChooseHeldOut(records, &dx.split);
  dx.selection = ChooseSelection(records, held);
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (held[i]) dx.heldout_trials.push_back(records[i].name);
    else if (dx.selection[i]) dx.selection_trials.push_back(records[i].name);
    else dx.training_trials.push_back(records[i].name);
  }
  // The splits as fit trials for `chair` (its GM; the records' own when null). Every candidate
  // is simulated on identification's grid (FitStep), so each split but the training one (the
  // fits put it there themselves) is put on it once here and serves the base model and every
  // extension alike. Rebuilt when the GM is identified again under a marker lever, and then
  // with a_x estimated from O_V's x rather than the marker's (a lever r_z turns a pitch
  // oscillation into a swing of the measured x).
  struct Splits {
    std::vector<FitTrial> training, report, selection, all, checked;  ///< report: held out
    std::vector<std::size_t> checked_index;  ///< records of `checked`
  };
  auto make_splits = [&](const Chair* chair, const effects::EffectParams* lever) {
    Splits out;
    for (std::size_t i = 0; i < records.size(); ++i) {
      std::vector<double> accel;
      if (lever) {
        const TrackUnderLever o = TrackUnderMarkerLever(records[i], lever->marker_lever_x,
                                                        lever->marker_lever_z, options.rest_window);
        accel = effects::EstimateAcceleration(records[i].t, o.x);
      }
      FitTrial f = MakeFitTrial(records[i], chair ? *chair : records[i].chair, options.rest_window,
                                std::move(accel));
      out.all.push_back(f);
      if (held[i] || dx.selection[i]) {
        out.checked.push_back(f);
        out.checked_index.push_back(i);
      }
      if (held[i]) out.report.push_back(std::move(f));
      else if (dx.selection[i]) out.selection.push_back(std::move(f));
      else out.training.push_back(std::move(f));
    }
    if (out.selection.empty()) out.selection = out.training;  // too few trials: choose on the training ones
    if (out.checked.empty()) {
      out.checked = out.report;
      for (std::size_t i = 0; i < records.size(); ++i)
        if (held[i]) out.checked_index.push_back(i);
    }
    out.report = WithFitStep(out.report, std::nullopt);
    out.selection = WithFitStep(out.selection, std::nullopt);
    out.checked = WithFitStep(out.checked, std::nullopt);
    out.all = WithFitStep(out.all, std::nullopt);
    return out;
  };
  Splits splits = make_splits(nullptr, nullptr);
  const std::vector<FitTrial>& training = splits.training;
  const std::vector<FitTrial>& heldout_base = splits.report;
  const std::vector<FitTrial>& selection_base = splits.selection;
  const std::vector<FitTrial>& checked_base = splits.checked;
  const std::vector<FitTrial>& all = splits.all;
  const std::vector<std::size_t>& checked_index = splits.checked_index;
  const ChannelWeights w = MakeChannelWeights(training);
  const LumpedParams start = dx.chair.lm.value_or(LumpedParams{});
  dx.base = FitModel(training, std::nullopt, start, w, options.fit);
  const double base_error = HeldOutError(heldout_base, dx.base.params, w);
  dx.base_heldout = PooledFitPct(heldout_base, dx.base.params);

  // Noise level and floor from the data alone.
  {
    std::vector<std::vector<double>> z_all, p_all, z_held, p_held;
    for (std::size_t i = 0; i < records.size(); ++i) {
      z_all.push_back(records[i].z);
      p_all.push_back(records[i].pitch);
      if (held[i]) {
        z_held.push_back(records[i].z);
        p_held.push_back(records[i].pitch);
      }
    }
    dx.sigma_z = PooledNoiseSigma(z_all);
    dx.sigma_pitch = PooledNoiseSigma(p_all);
    dx.noise_floor = {NoiseFloorFitPct(z_held, dx.sigma_z), NoiseFloorFitPct(p_held, dx.sigma_pitch)};
  }
  const double noise_ms = 0.5 * (w.z * w.z * dx.sigma_z * dx.sigma_z +
                                 w.pitch * w.pitch * dx.sigma_pitch * dx.sigma_pitch);
  dx.base_check = CheckResidual(ResidualRecords(checked_base, records, checked_index, dx.base.params),
                                dx.sigma_z, dx.sigma_pitch, options.verdict);

  // Residual analysis of the base model on every trial.
  for (std::size_t i = 0; i < all.size(); ++i) {
    const TrialResidual r = ComputeResidual(all[i], dx.base.params);
    TrialAnalysis a;
    a.name = records[i].name;
    a.heldout = held[i];
    a.speed = records[i].speed;
    a.load_kg = records[i].load_kg;
    a.t = records[i].t;
    a.x = records[i].x;
    a.accel = all[i].prepared.accel;
    a.z = records[i].z;
    a.pitch = records[i].pitch;
    a.z_base = r.z_model;
    a.pitch_base = r.pitch_model;
    a.z_ext = r.z_model;
    a.pitch_ext = r.pitch_model;
    a.z_gm = r.model.z_gm;
    a.pitch_gm = r.model.pitch_gm;
    dx.trials.push_back(std::move(a));
  }
  dx.residuals = Analyse(dx.trials, dx.chair, records);

  // Round 1: every extension alone (the ranking).
  const double base_sel = HeldOutError(selection_base, dx.base.params, w);
  for (EffectId id : options.candidates) {
    RankEntry e;
    e.effect = id;
    e.fit = FitModel(training, id, dx.base.params.lm, w, options.fit);
    e.delta_bic = e.fit.bic - dx.base.bic;
    const double err = HeldOutError(heldout_base, e.fit.params, w);
    e.heldout_gain = base_error > 0.0 ? 1.0 - err / base_error : 0.0;
    const double sel = HeldOutError(selection_base, e.fit.params, w);
    e.selection_gain = base_sel > 0.0 ? 1.0 - sel / base_sel : 0.0;
    e.heldout = PooledFitPct(heldout_base, e.fit.params);
    e.earns = e.delta_bic < options.bic_threshold && e.selection_gain >= options.min_heldout_gain;
    e.parameters = NamedParameters(e.fit);
    e.evidence = dx.residuals.evidence[static_cast<int>(id)] +
                 Format("; extension removes %.0f %% of the selection error, %.0f %% of the "
                        "held-out error",
                        100.0 * e.selection_gain, 100.0 * e.heldout_gain);
    dx.ranking.push_back(std::move(e));
  }
  std::stable_sort(dx.ranking.begin(), dx.ranking.end(), [](const RankEntry& a, const RankEntry& b) {
    if (a.earns != b.earns) return a.earns;
    return a.selection_gain > b.selection_gain;
  });

  // Forward selection (skipped when the base model is adequate).
  dx.extended = dx.base;
  dx.extended_check = dx.base_check;
  const double base_excess = std::max(0.0, MeanSquareError(heldout_base, dx.base.params, w) - noise_ms);
  double previous_excess = base_excess;
  if (!dx.base_check.NoiseLike()) {
    FitResult current = dx.base;
    double current_sel = base_sel;
    std::vector<EffectId> found;
    // Joint fits of the later rounds are screened with fewer iterations; the winner is then
    // solved on (the joint fits are the expensive part of a diagnosis).
    FitOptions screen = options.fit;
    screen.max_iterations = std::min(options.fit.max_iterations, options.screen_iterations);
    screen.multi_start = false;
    while (static_cast<int>(found.size()) < options.max_causes) {
      std::optional<FitResult> best;
      double best_gain = -1e9, best_sel = 0.0;
      if (found.empty()) {
        for (const RankEntry& e : dx.ranking) {
          if (e.earns && e.selection_gain > best_gain) {
            best = e.fit;
            best_gain = e.selection_gain;
            best_sel = base_sel * (1.0 - e.selection_gain);
          }
        }
      } else {
        for (const RankEntry& solo : dx.ranking) {
          const EffectId id = solo.effect;
          if (std::find(found.begin(), found.end(), id) != found.end()) continue;
          // Only extensions that improve the training fit on their own (ΔBIC below the
          // threshold) are tried jointly: the joint fits are the expensive part.
          if (!(solo.delta_bic < options.bic_threshold)) continue;
          std::vector<EffectId> list = found;
          list.push_back(id);
          // The new extension starts where its own fit alone ended (that fit searched the
          // family's starts and members), the causes found where they are.
          effects::ExtendedParams from = current.params;
          effects::CopyEffect(id, solo.fit.params.fx, from.fx);
          FitResult f = FitModelJoint(training, list, from, w, screen);
          const double sel = HeldOutError(selection_base, f.params, w);
          const double gain = current_sel > 0.0 ? 1.0 - sel / current_sel : 0.0;
          const bool earns = f.bic - current.bic < options.bic_threshold && gain >= options.min_heldout_gain;
          if (earns && gain > best_gain) {
            best = std::move(f);
            best_gain = gain;
            best_sel = sel;
          }
        }
      }
      if (!best) break;
      if (!found.empty() && screen.max_iterations < options.fit.max_iterations) {
        // The screened winner solved on to the full iterations (kept when it still earns).
        FitOptions full = options.fit;
        full.multi_start = false;
        FitResult f = FitModelJoint(training, best->effects, best->params, w, full);
        const double sel = HeldOutError(selection_base, f.params, w);
        const double gain = current_sel > 0.0 ? 1.0 - sel / current_sel : 0.0;
        if (f.bic - current.bic < options.bic_threshold && gain >= options.min_heldout_gain) {
          best = std::move(f);
          best_gain = gain;
          best_sel = sel;
        }
      }
      // A marker lever found in a set whose GM was identified on the measured x: that GM saw
      // the wheels where the marker was, not where they were. The GM is identified again on
      // the tracks corrected for the lever, and the causes so far re-fitted with it (kept when
      // the selection trials agree). Without this, a later extension that can move the GM
      // (the tyre family's suspension plane) earns by mending the GM instead of its own effect.
      if (records.front().gm_from_trials && best->effects.back() == EffectId::kMarkerOffset) {
        // Alternate GM and fit (the lever was fitted under the old GM) while the selection
        // trials improve by more than 1 %; at most six rounds, each a refinement of the last.
        FitOptions refine = options.fit;
        refine.multi_start = false;
        for (int round = 0; round < 6; ++round) {
          Chair regeometry = dx.chair;
          regeometry.gm = GeometryUnderMarkerLever(records, dx.chair, best->params.lm,
                                                   best->params.fx.marker_lever_x,
                                                   best->params.fx.marker_lever_z, options.rest_window);
          Splits next = make_splits(&regeometry, &best->params.fx);
          FitResult refit = FitModelJoint(next.training, best->effects, best->params, w, refine);
          const double sel = HeldOutError(next.selection, refit.params, w);
          if (!(sel < best_sel)) break;
          const bool small = sel > 0.99 * best_sel;
          splits = std::move(next);
          dx.chair = regeometry;
          dx.gm_under_marker = true;
          best_gain = current_sel > 0.0 ? 1.0 - sel / current_sel : best_gain;
          best_sel = sel;
          best = std::move(refit);
          if (small) break;
        }
      }
      Cause c;
      c.effect = best->effects.back();
      c.selection_gain = best_gain;
      c.delta_bic = best->bic - current.bic;
      const double excess = std::max(0.0, MeanSquareError(heldout_base, best->params, w) - noise_ms);
      c.heldout_gain_pct = base_excess > 0.0 ? 100.0 * (previous_excess - excess) / base_excess : 0.0;
      previous_excess = excess;
      found.push_back(c.effect);
      dx.causes.push_back(c);
      current = std::move(*best);
      current_sel = best_sel;
      dx.extended_check =
          CheckResidual(ResidualRecords(checked_base, records, checked_index, current.params),
                        dx.sigma_z, dx.sigma_pitch, options.verdict);
      if (dx.extended_check.NoiseLike()) break;
    }
    dx.extended = current;
  }
  dx.verdict = Decide(dx.base_check, dx.causes.size(), dx.extended_check);
  dx.extended_heldout = dx.base_heldout;
  if (dx.verdict == Verdict::kAdequate) dx.causes.clear();
  if (!dx.causes.empty()) {
    dx.cause = effects::EffectName(dx.causes.front().effect);
    dx.extended_heldout = PooledFitPct(heldout_base, dx.extended.params);
    for (std::size_t i = 0; i < all.size(); ++i) {
      const TrialResidual r = ComputeResidual(all[i], dx.extended.params);
      if (!r.finite) continue;
      dx.trials[i].z_ext = r.z_model;
      dx.trials[i].pitch_ext = r.pitch_model;
    }
  } else {
    dx.extended = dx.base;
  }
  dx.extended_parameters = NamedParameters(dx.extended);
  return dx;
}

}  // namespace pwsim::diagnose
