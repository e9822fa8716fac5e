#include "report/diagnosis_report.h"

#include <algorithm>
#include <cmath>

#include "engine/atomic_file.h"
#include "plot/plot.h"
#include "report/format.h"
#include "sysid/diagnose/parallel_for.h"
#include "sysid/effects/effect_catalog.h"

namespace pwsim::report {

using diagnose::Diagnosis;
using diagnose::RankEntry;

namespace {

nlohmann::ordered_json FitJson(const diagnose::FitPct& fit) {
  return {{"z", JsonNumber(fit.z)}, {"pitch", JsonNumber(fit.pitch)}};
}

nlohmann::ordered_json NoiseJson(const diagnose::ChannelNoise& n) {
  nlohmann::ordered_json acf = nlohmann::ordered_json::array();
  for (double r : n.acf) acf.push_back(JsonNumber(r));
  return {{"sigma", JsonNumber(n.sigma)}, {"sigma_hf", JsonNumber(n.sigma_hf)},
          {"from_rest", n.from_rest}, {"rest_samples", n.rest_samples}, {"acf", acf},
          {"drift_rate", JsonNumber(n.drift_rate)}, {"drift_statistic", JsonNumber(n.drift_statistic)},
          {"drift_bound", JsonNumber(n.drift_bound)}, {"drift_systematic", n.drift_systematic},
          {"final_rest_unsettled", n.final_rest_unsettled}, {"slow_scale_s", JsonNumber(n.slow_scale_s)},
          {"drift_left", JsonNumber(n.drift_left)}};
}

nlohmann::ordered_json ChannelCheckJson(const diagnose::ChannelCheck& c) {
  return {{"rho", JsonNumber(c.rho)},
          {"rho_local", JsonNumber(c.rho_local)},
          {"whiteness", JsonNumber(c.whiteness)},
          {"whiteness_noise", JsonNumber(c.whiteness_noise)},
          {"whiteness_bound", JsonNumber(c.whiteness_bound)},
          {"input_r", JsonNumber(c.input_r)},
          {"input_bound", JsonNumber(c.input_bound)},
          {"noise_like", c.NoiseLike()}};
}

nlohmann::ordered_json CheckJson(const diagnose::NoiseCheck& c) {
  return {{"z", ChannelCheckJson(c.z)}, {"pitch", ChannelCheckJson(c.pitch)}, {"noise_like", c.NoiseLike()}};
}

}  // namespace

nlohmann::ordered_json VerdictInputsJson(const Diagnosis& d) {
  const diagnose::VerdictOptions& o = d.options.verdict;
  return {{"limits", {{"rho_max", o.rho_max}, {"rho_local", o.rho_local}, {"window_s", o.window_s},
                      {"alpha", o.alpha}, {"input_r_max", o.input_r_max}, {"clip_sigma", o.clip_sigma},
                      {"drift_budget", o.drift_budget},
                      {"bic_threshold", d.options.bic_threshold},
                      {"min_selection_gain", d.options.min_selection_gain}}},
          {"selection_noise_ms", JsonNumber(d.selection_noise_ms)},
          {"noise", {{"z", NoiseJson(d.noise.z)}, {"pitch", NoiseJson(d.noise.pitch)}}},
          {"base", CheckJson(d.base_check)},
          {"extended", CheckJson(d.extended_check)}};
}

double ProbabilityOf(const Diagnosis& d, effects::EffectId id) {
  for (const diagnose::EffectProbability& p : d.probabilities)
    if (p.effect == id) return p.probability;
  return 0.0;
}

namespace {

nlohmann::ordered_json CauseJson(const diagnose::Cause& c) {
  return {{"effect", effects::EffectName(c.effect)},
          {"heldout_gain_pct", JsonNumber(c.heldout_gain_pct)},
          {"heldout_gain_lower_pct", JsonNumber(c.heldout_gain_lower_pct)},
          {"heldout_gain_upper_pct", JsonNumber(c.heldout_gain_upper_pct)},
          {"selection_gain_pct", JsonNumber(100.0 * c.selection_gain)},
          {"delta_bic", JsonNumber(c.delta_bic)},
          {"confirmed", c.confirmed},
          {"report_trials", c.report_trials},
          {"report_trials_improved", c.report_trials_improved}};
}

}  // namespace

nlohmann::ordered_json DiagnosisJson(const Diagnosis& d, const std::string& base_source,
                                     double seconds) {
  nlohmann::ordered_json j;
  j["format"] = "pwsim-diagnosis/1";
  j["cause"] = d.cause;
  j["ranking"] = nlohmann::ordered_json::array();
  for (const RankEntry& e : d.ranking) {
    nlohmann::ordered_json params = nlohmann::ordered_json::object();
    for (const auto& [name, value] : e.parameters) params[name] = JsonNumber(value);
    j["ranking"].push_back({{"effect", effects::EffectName(e.effect)},
                            {"evidence", e.evidence},
                            {"delta_bic", JsonNumber(e.delta_bic)},
                            {"heldout_fit_pct", FitJson(e.heldout)},
                            {"parameters", params},
                            {"selection_gain_pct", JsonNumber(100.0 * e.selection_gain)},
                            {"earns", e.earns},
                            {"heldout_gain_pct", JsonNumber(e.heldout_gain.pct)},
                            {"heldout_gain_lower_pct", JsonNumber(e.heldout_gain.lower_pct)},
                            {"heldout_gain_upper_pct", JsonNumber(e.heldout_gain.upper_pct)},
                            {"probability", JsonNumber(ProbabilityOf(d, e.effect))}});
  }
  j["heldout_fit_pct"] = {{"base", FitJson(d.base_heldout)}, {"extended", FitJson(d.extended_heldout)}};
  j["heldout_trials"] = d.heldout_trials;
  // Additions of measured-trials.md (v1).
  j["verdict"] = diagnose::VerdictName(d.verdict);
  // `causes`: the causes found (earned on the selection trials, confirmed by the report trials);
  // `selected_causes` (an addition): every cause forward selection added, confirmed or not.
  j["causes"] = nlohmann::ordered_json::array();
  j["selected_causes"] = nlohmann::ordered_json::array();
  for (const diagnose::Cause& c : d.causes) {
    if (c.confirmed) j["causes"].push_back(CauseJson(c));
    j["selected_causes"].push_back(CauseJson(c));
  }
  j["noise_floor_fit_pct"] = FitJson(d.noise_floor);
  if (d.verdict == diagnose::Verdict::kUnexplained || d.verdict == diagnose::Verdict::kPartlyExplained) {
    j["unexplained"] = {{"heldout_fit_pct", FitJson(d.extended_heldout)},
                        {"evidence", d.extended_check.Evidence()}};
  }
  // Additions beyond the contract's minimum (allowed: add, never rename).
  j["noise_sigma"] = {{"z_m", JsonNumber(d.sigma_z)}, {"pitch_rad", JsonNumber(d.sigma_pitch)}};
  {  // each candidate's probability of being present (diagnose.h EffectProbabilities) and its inputs
    const diagnose::ProbabilityOptions po;
    nlohmann::ordered_json p = nlohmann::ordered_json::object();
    for (const diagnose::EffectProbability& e : d.probabilities) p[effects::EffectName(e.effect)] = JsonNumber(e.probability);
    j["effect_probability"] = p;
    nlohmann::ordered_json models = nlohmann::ordered_json::array();
    for (const diagnose::VisitedModel& m : d.visited) {
      nlohmann::ordered_json fx = nlohmann::ordered_json::array(), ms = nlohmann::ordered_json::array();
      for (effects::EffectId id : m.effects) fx.push_back(effects::EffectName(id));
      for (double v : m.selection_ms) ms.push_back(v);
      models.push_back({{"effects", fx}, {"selection_ms", ms}});
    }
    j["effect_probability_inputs"] = {{"prior", JsonNumber(po.prior)},
                                      {"samples_per_unit", JsonNumber(po.samples_per_unit)},
                                      {"models", models}};
  }
  j["verdict_inputs"] = VerdictInputsJson(d);
  j["residual_tests"] = {{"base", d.base_check.Evidence()}, {"extended", d.extended_check.Evidence()}};
  j["selection_trials"] = d.selection_trials;
  j["training_trials"] = d.training_trials;
  j["split"] = d.split;
  // The extended model: the causes' joint fit (the base model when none) and its GM (the base
  // model's, or identified again under the marker lever found).
  {
    nlohmann::ordered_json effects = nlohmann::ordered_json::array();
    for (effects::EffectId id : d.extended.effects) effects.push_back(effects::EffectName(id));
    nlohmann::ordered_json params = nlohmann::ordered_json::object();
    for (const auto& [name, value] : d.extended_parameters) params[name] = JsonNumber(value);
    nlohmann::ordered_json alpha = nlohmann::ordered_json::array();
    for (double a : d.chair.gm->alpha) alpha.push_back(JsonNumber(a));
    j["extended_model"] = {{"effects", effects},
                           {"parameters", params},
                           {"gm", {{"identified_under_marker_lever", d.gm_under_marker},
                                   {"identified_under_cushion", d.base_under_cushion},
                                   {"alpha", alpha}}}};
  }
  j["base_model"] = {{"source", base_source},
                     {"k_z", JsonNumber(d.base.params.lm.k_z)},
                     {"c_z", JsonNumber(d.base.params.lm.c_z)},
                     {"k_theta", JsonNumber(d.base.params.lm.k_theta)},
                     {"c_theta", JsonNumber(d.base.params.lm.c_theta)}};
  const auto& r = d.residuals;
  j["residuals"] = {
      {"base_fit_pct_all_trials", FitJson(r.fit)},
      {"whiteness_outside_99", {{"z", r.whiteness_z.outside}, {"pitch", r.whiteness_pitch.outside}}},
      {"input_ccf_outside_99", {{"z", r.input_z.outside}, {"pitch", r.input_pitch.outside}}},
      {"power_above_6hz", {{"z", JsonNumber(r.high_band_z)}, {"pitch", JsonNumber(r.high_band_pitch)}}},
      {"scale", {{"z", JsonNumber(r.scale_z.scale)}, {"pitch", JsonNumber(r.scale_pitch.scale)}}},
      {"lag_s", {{"z", JsonNumber(r.scale_z.lag_s)}, {"pitch", JsonNumber(r.scale_pitch.lag_s)}}},
      {"space_lock", JsonNumber(r.located.space_lock)},
      {"time_lock", JsonNumber(r.located.time_lock)}};
  j["seconds"] = JsonNumber(seconds);
  return j;
}

void PlotResiduals(const diagnose::TrialAnalysis& t, const std::string& cause,
                   const std::filesystem::path& file) {
  const std::size_t n = t.t.size();
  std::vector<double> tz(n), tp(n), ebz(n), ebp(n), eez(n), eep(n), mz(n), mp(n), bz(n), bp(n),
      xz(n), xp(n);
  for (std::size_t k = 0; k < n; ++k) {
    tz[k] = t.t[k] - t.t[0];
    mz[k] = 1e3 * (t.z[k] - t.z_base[0]);
    bz[k] = 1e3 * (t.z_base[k] - t.z_base[0]);
    xz[k] = 1e3 * (t.z_ext[k] - t.z_base[0]);
    mp[k] = 1e3 * t.pitch[k];
    bp[k] = 1e3 * t.pitch_base[k];
    xp[k] = 1e3 * t.pitch_ext[k];
    ebz[k] = 1e3 * (t.z[k] - t.z_base[k]);
    eez[k] = 1e3 * (t.z[k] - t.z_ext[k]);
    ebp[k] = 1e3 * (t.pitch[k] - t.pitch_base[k]);
    eep[k] = 1e3 * (t.pitch[k] - t.pitch_ext[k]);
  }
  std::string words = cause;  // the effect's id in words: tyre_compliance -> tyre compliance
  std::replace(words.begin(), words.end(), '_', ' ');
  const std::string ext = "model with " + words;
  const std::string base = "base model (seed 000)";
  std::vector<plot::SharedXPanel> panels{
      {"chair height at the marker: measured and modelled", "height [mm]",
       {{"measured", mz, 0x222222}, {base, bz, 0x0072B2}, {ext, xz, 0xD55E00}}},
      {"height: what each model misses (measured - model)", "height error [mm]",
       {{base, ebz, 0x0072B2}, {ext, eez, 0xD55E00}}},
      {"chair pitch (nose up +): measured and modelled", "pitch [mrad]",
       {{"measured", mp, 0x222222}, {base, bp, 0x0072B2}, {ext, xp, 0xD55E00}}},
      {"pitch: what each model misses (measured - model)", "pitch error [mrad]",
       {{base, ebp, 0x0072B2}, {ext, eep, 0xD55E00}}}};
  plot::WriteSharedXFigure(file, tz, panels, "time [s]", 1100, 240);
}

void PlotLocated(const diagnose::LocatedResidual& loc, const std::filesystem::path& file) {
  auto milli = [](std::vector<double> v) {
    for (double& x : v) x *= 1e3;
    return v;
  };
  std::vector<plot::SharedXPanel> panels{
      {"where the base model's pitch error sits around the obstacle's edges (mean near each slope change, "
       "signed so that ramp feet and crests add up)",
       "pitch error [mrad]",
       {{"slower trials", milli(loc.slow_pitch), 0x0072B2}, {"faster trials", milli(loc.fast_pitch), 0xD55E00}}},
      {"the same for the height error: curves that agree between slow and fast trials are fixed in "
       "space (the wheels and the ground), not in time (a resonance)",
       "height error [mm]",
       {{"slower trials", milli(loc.slow_z), 0x0072B2}, {"faster trials", milli(loc.fast_z), 0xD55E00}}}};
  plot::WriteSharedXFigure(file, loc.distance, panels,
                           "wheel's distance past the nearest slope change of the obstacle [m]", 1100, 280);
}

std::string ProbabilityBar(double p, int width) {
  const int filled = static_cast<int>(std::lround(std::clamp(p, 0.0, 1.0) * width));
  std::string bar;
  for (int k = 0; k < width; ++k) bar += k < filled ? "█" : "·";
  return bar;
}

std::string ProbabilityBars(const Diagnosis& d) {
  if (d.probabilities.empty()) return "";
  std::string md = "## How likely each effect is\n\nThe probability that each effect of the catalogue is "
                   "present, from the selection trials' errors of every model the ranking and forward "
                   "selection fitted (docs/diagnosis.md, \"How likely each effect is\"):\n\n```\n";
  std::vector<diagnose::EffectProbability> sorted = d.probabilities;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& a, const auto& b) { return a.probability > b.probability; });
  for (const auto& p : sorted) {
    std::string name = effects::EffectName(p.effect);
    name.resize(std::max<std::size_t>(name.size(), 22), ' ');
    md += name + " " + ProbabilityBar(p.probability, 40) + " " + Fixed(p.probability, 2) + "\n";
  }
  return md + "```\n\n";
}

std::string DiagnosisMarkdown(const Diagnosis& d, const std::string& base_source,
                     const std::vector<std::string>& plots, double seconds) {
  const auto& r = d.residuals;
  std::string md = "# Diagnosis report\n\n";
  md += "pwsim diagnose on " + std::to_string(d.trials.size()) + " trials (" +
        Fixed(seconds, 1) + " s). Base model: geometric + lumped model of the paper, " + base_source +
        ", K and C re-identified by output error on the training trials. Held out of every fit: " +
        d.split + " (" + std::to_string(d.heldout_trials.size()) + " trials).\n\n";
  md += "## Verdict: **" + std::string(diagnose::VerdictName(d.verdict)) + "**, cause: **" + d.cause + "**\n\n";
  switch (d.verdict) {
    case diagnose::Verdict::kAdequate:
      md += "The base model's residual on the held-out trials cannot be told from the measurement "
            "noise: there is nothing to explain.\n\n";
      break;
    case diagnose::Verdict::kUnexplained:
      md += "The base model is measurably wrong, and no extension of the catalogue earns its "
            "parameters: **the cause is not in the catalogue** (cause `none` here does NOT mean the "
            "model is fine).\n\n";
      break;
    case diagnose::Verdict::kExplained:
      md += "The causes found bring the held-out residual down to the noise.\n\n";
      break;
    case diagnose::Verdict::kPartlyExplained:
      md += "The causes found earn their parameters, but a structured residual is left.\n\n";
      break;
  }
  // One gain (diagnose.h): the share of the error above the noise that adding the cause to the
  // model before it removes; on the held-out trials with its 90 % interval (one-sided 95 % bounds).
  auto cause_line = [&](const diagnose::Cause& c) {
    return "- `" + std::string(effects::EffectName(c.effect)) + "`: " + effects::EffectDescription(c.effect) +
           "; held-out gain " + Fixed(c.heldout_gain_pct, 1) + " % (90 % interval " +
           Fixed(c.heldout_gain_lower_pct, 1) + " to " + Fixed(c.heldout_gain_upper_pct, 1) + " %; " +
           std::to_string(c.report_trials_improved) + " of " + std::to_string(c.report_trials) +
           " report trials improved), selection gain " + Fixed(100.0 * c.selection_gain, 1) +
           " %, probability " + Fixed(ProbabilityOf(d, c.effect), 2) + ".\n";
  };
  bool any_found = false, any_unconfirmed = false;
  for (const diagnose::Cause& c : d.causes) (c.confirmed ? any_found : any_unconfirmed) = true;
  if (any_found) {
    md += "Found (each earned its parameters on the selection trials, and the held-out trials confirm it: "
          "its held-out gain's lower bound is above 0). The gain is the share of the error above the noise "
          "that adding the cause to the model before it removes:\n\n";
    for (const diagnose::Cause& c : d.causes)
      if (c.confirmed) md += cause_line(c);
  }
  if (any_unconfirmed) {
    md += std::string(any_found ? "\n" : "") +
          "Chosen on the selection trials but **not confirmed** by the held-out trials (not found: the "
          "held-out gain's lower bound is not above 0):\n\n";
    for (const diagnose::Cause& c : d.causes)
      if (!c.confirmed) md += cause_line(c);
  }
  md += std::string("\nNoise (from the data: ") +
        (d.noise.z.from_rest ? "rest windows, variogram and MAD" : "4th differences, white") + "): Z " + Significant(1e3 * d.sigma_z, 3) + " mm, pitch " +
        Significant(1e3 * d.sigma_pitch, 3) + " mrad; noise floor on the held-out trials: Z " +
        Fixed(d.noise_floor.z, 1) + " %, pitch " + Fixed(d.noise_floor.pitch, 1) + " %.\n\n";
  md += "- Base model, residual tests (selection + held-out trials): " + d.base_check.Evidence() + "\n";
  md += "- Extended model, residual tests: " + d.extended_check.Evidence() + "\n\n";
  md += "| held-out fitness (MATLAB compare) | Z [%] | pitch [%] |\n|---|---|---|\n";
  md += "| base model | " + Fixed(d.base_heldout.z, 1) + " | " + Fixed(d.base_heldout.pitch, 1) + " |\n";
  md += "| noise floor | " + Fixed(d.noise_floor.z, 1) + " | " + Fixed(d.noise_floor.pitch, 1) + " |\n";
  md += "| extended model (" + d.cause + ") | " + Fixed(d.extended_heldout.z, 1) + " | " +
        Fixed(d.extended_heldout.pitch, 1) + " |\n\n";
  md += "(The paper reports 79.3 % for Z and 57.6 % for pitch on its real chair.)\n\n";
  md += ProbabilityBars(d);
  md += "## Ranking\n\nEach extension alone, against the base model. Its gain is the share of the error "
        "above the noise that it removes. It earns its parameters when ΔBIC (training) < " +
        Fixed(d.options.bic_threshold, 0) + " and its gain on the selection trials is at least " +
        Fixed(100.0 * d.options.min_selection_gain, 0) + " %; the held-out gain (90 % interval) is the "
        "same quantity on trials that played no part in any choice.\n\n";
  md += "| # | effect | earns | selection gain | held-out gain [90 % interval] | probability | ΔBIC | held-out fit Z / pitch [%] | parameters | evidence |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  int rank = 1;
  for (const RankEntry& e : d.ranking) {
    std::string params;
    for (const auto& [name, value] : e.parameters) {
      if (!params.empty()) params += ", ";
      params += name + " " + Significant(value, 4);
    }
    md += "| " + std::to_string(rank++) + " | " + effects::EffectName(e.effect) + " | " +
          (e.earns ? "yes" : "no") + " | " + Fixed(100.0 * e.selection_gain, 1) + " % | " +
          Fixed(e.heldout_gain.pct, 1) + " % [" + Fixed(e.heldout_gain.lower_pct, 1) + ", " +
          Fixed(e.heldout_gain.upper_pct, 1) + "] | " + Fixed(ProbabilityOf(d, e.effect), 2) + " | " +
          Fixed(e.delta_bic, 0) + " | " + Fixed(e.heldout.z, 1) + " / " + Fixed(e.heldout.pitch, 1) +
          " | " + params + " | " + e.evidence + " |\n";
  }
  md += "\n## Residual analysis of the base model\n\n";
  md += "- Fitness over all trials: Z " + Fixed(r.fit.z, 1) + " %, pitch " + Fixed(r.fit.pitch, 1) + " %.\n";
  md += "- Whiteness (residual autocorrelation, lags 1-25, 99 % bound " + Fixed(r.whiteness_pitch.bound, 3) +
        "): " + std::to_string(r.whiteness_z.outside) + " Z lags and " +
        std::to_string(r.whiteness_pitch.outside) + " pitch lags outside (an output-error model "
        "need not have white residuals; independence from the input matters more).\n";
  md += "- Residual vs own GM input (lags -25..25, coloured-input 99 % bound): Z " +
        std::to_string(r.input_z.outside) + " lags outside (max |r| " + Fixed(r.input_z.worst, 2) +
        " at lag " + std::to_string(r.input_z.worst_lag) + "), pitch " +
        std::to_string(r.input_pitch.outside) + " (max |r| " + Fixed(r.input_pitch.worst, 2) +
        " at lag " + std::to_string(r.input_pitch.worst_lag) + ").\n";
  md += "- Cross-channel (e_Z vs θ_GM, e_θ vs Z_GM): max |r| " + Fixed(r.cross_z.worst, 2) + ", " +
        Fixed(r.cross_pitch.worst, 2) + ".\n";
  md += "- Residual spectra: power above 6 Hz Z " + Fixed(100 * r.high_band_z, 0) + " %, pitch " +
        Fixed(100 * r.high_band_pitch, 0) + " % (pitch peak " + Fixed(r.peak_hz_pitch, 1) + " Hz).\n";
  md += "- Measured on predicted: Z scale " + Fixed(r.scale_z.scale, 3) + ", lag " +
        Fixed(1e3 * r.scale_z.lag_s, 0) + " ms; pitch scale " + Fixed(r.scale_pitch.scale, 3) +
        ", lag " + Fixed(1e3 * r.scale_pitch.lag_s, 0) + " ms.\n";
  md += "- Located residual: slow/fast profiles correlate " + Fixed(r.located.space_lock, 2) +
        " in space vs " + Fixed(r.located.time_lock, 2) + " in time.\n\n";
  md += "| drive phase | samples | RMS residual Z [mm] | RMS residual pitch [mrad] |\n|---|---|---|---|\n";
  for (const auto& p : r.phases) {
    md += "| " + p.phase + " | " + std::to_string(p.samples) + " | " + Fixed(1e3 * p.z, 2) + " | " +
          Fixed(1e3 * p.pitch, 2) + " |\n";
  }
  md += "\n## Plots\n\n![located residual](" + plots.front() + ")\n\n";
  for (std::size_t k = 1; k < plots.size(); ++k) md += "![held-out trial](" + plots[k] + ")\n\n";
  return md;
}

void RemoveDiagnosisReport(const std::filesystem::path& out) {
  for (const char* name : {"diagnosis.json", "diagnosis.md"}) std::filesystem::remove(out / name);
  if (std::filesystem::is_directory(out / "plots")) {
    for (const auto& entry : std::filesystem::directory_iterator(out / "plots"))
      if (entry.path().filename().string().rfind("residual-", 0) == 0 ||
          entry.path().filename().string().rfind("located-residual", 0) == 0)
        std::filesystem::remove(entry.path());
  }
}

void WriteDiagnosisReport(const std::filesystem::path& out, const Diagnosis& d,
                          const std::string& base_source, double seconds, long long max_plots) {
  RemoveDiagnosisReport(out);
  std::filesystem::create_directories(out / "plots");
  std::vector<std::string> plots{"plots/located-residual.png"};
  std::vector<const diagnose::TrialAnalysis*> plotted;
  for (const auto& t : d.trials) {
    if (!t.heldout || static_cast<long long>(plotted.size()) >= max_plots) continue;
    plots.push_back("plots/residual-" + t.name + ".png");
    plotted.push_back(&t);
  }
  // One gnuplot process per figure: the figures are drawn concurrently (each its own files).
  diagnose::ParallelFor(plots.size(), d.options.threads, [&](std::size_t i) {
    if (i == 0) PlotLocated(d.residuals.located, out / plots.front());
    else PlotResiduals(*plotted[i - 1], d.cause, out / plots[i]);
  });
  WriteFileAtomically(out / "diagnosis.md", DiagnosisMarkdown(d, base_source, plots, seconds));
  WriteFileAtomically(out / "diagnosis.json", DiagnosisJson(d, base_source, seconds).dump(2) + "\n");
}

}  // namespace pwsim::report
