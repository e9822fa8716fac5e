// pwsim diagnose TRIAL_DIR... --out DIR: finds what the identified base model gets wrong on
// measured trials, names the cause among the effect ids of measured-trials.md, extends and
// re-identifies the model and measures the gain on held-out trials (engine/diagnose/).
// Writes DIR/diagnosis.json (pwsim-diagnosis/1) and DIR/diagnosis.md with plots. Wiring and
// reporting only. Stale outputs are removed before the inputs are read; diagnosis.json is
// written last, so a failed run never leaves a report that looks complete.

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "app/commands.h"
#include "engine/atomic_file.h"
#include "engine/diagnose/diagnose.h"
#include "engine/effects/effect_catalog.h"
#include "engine/measured/measured_trial.h"
#include "app/plot_png.h"

namespace pwsim::app {
namespace {

using diagnose::Diagnosis;
using diagnose::RankEntry;

std::string Fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "n/a";
  std::ostringstream out;
  out << std::fixed << std::setprecision(decimals) << value;
  return out.str();
}

std::string Sig(double value, int digits) {
  if (!std::isfinite(value)) return "n/a";
  std::ostringstream out;
  out << std::setprecision(digits) << value;
  return out.str();
}

/// JSON number rounded to 1e-3 (1e-6 relative for large or small values); null when not finite.
nlohmann::ordered_json JsonNumber(double value) {
  if (!std::isfinite(value)) return nullptr;
  if (std::abs(value) >= 1.0 || value == 0.0) return std::round(value * 1000.0) / 1000.0;
  return std::stod(Sig(value, 6));
}

nlohmann::ordered_json FitJson(const diagnose::FitPct& fit) {
  return {{"z", JsonNumber(fit.z)}, {"pitch", JsonNumber(fit.pitch)}};
}

std::vector<effects::EffectId> ParseCandidates(const std::string& text) {
  if (text == "all") return {effects::AllEffects().begin(), effects::AllEffects().end()};
  std::vector<effects::EffectId> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto id = effects::ParseEffect(item);
    if (!id) {
      throw std::invalid_argument("option --effects: expected 'all' or a comma list of " +
                                  effects::EffectNameList() + ", got '" + item + "'");
    }
    out.push_back(*id);
  }
  if (out.empty()) throw std::invalid_argument("option --effects: expected at least one effect id");
  return out;
}

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
                            {"heldout_gain", JsonNumber(e.heldout_gain)},
                            {"selection_gain", JsonNumber(e.selection_gain)},
                            {"earns", e.earns}});
  }
  j["heldout_fit_pct"] = {{"base", FitJson(d.base_heldout)}, {"extended", FitJson(d.extended_heldout)}};
  j["heldout_trials"] = d.heldout_trials;
  // Additions of measured-trials.md (v1).
  j["verdict"] = diagnose::VerdictName(d.verdict);
  j["causes"] = nlohmann::ordered_json::array();
  for (const diagnose::Cause& c : d.causes) {
    j["causes"].push_back({{"effect", effects::EffectName(c.effect)},
                           {"heldout_gain_pct", JsonNumber(c.heldout_gain_pct)},
                           {"selection_gain_pct", JsonNumber(100.0 * c.selection_gain)},
                           {"delta_bic", JsonNumber(c.delta_bic)}});
  }
  j["noise_floor_fit_pct"] = FitJson(d.noise_floor);
  j["noise_sigma"] = {{"z_m", JsonNumber(d.sigma_z)}, {"pitch_rad", JsonNumber(d.sigma_pitch)}};
  if (d.verdict == diagnose::Verdict::kUnexplained || d.verdict == diagnose::Verdict::kPartlyExplained) {
    j["unexplained"] = {{"heldout_fit_pct", FitJson(d.extended_heldout)},
                        {"evidence", d.extended_check.Evidence()}};
  }
  j["residual_tests"] = {{"base", d.base_check.Evidence()}, {"extended", d.extended_check.Evidence()}};
  j["selection_trials"] = d.selection_trials;
  // Additions beyond the contract's minimum (allowed: add, never rename).
  j["training_trials"] = d.training_trials;
  j["split"] = d.split;
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

/// Measured, base and extended model of one held-out trial, and both residuals.
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
  const std::string ext = "extended (" + cause + ")";
  std::vector<PlotPanel> panels{
      {"Z: measured vs models", "mm",
       {{"measured", mz, 0x222222}, {"base", bz, 0x1f77b4}, {ext, xz, 0xd62728}}},
      {"Z residual before/after", "mm", {{"base", ebz, 0x1f77b4}, {ext, eez, 0xd62728}}},
      {"pitch: measured vs models", "mrad",
       {{"measured", mp, 0x222222}, {"base", bp, 0x1f77b4}, {ext, xp, 0xd62728}}},
      {"pitch residual before/after", "mrad", {{"base", ebp, 0x1f77b4}, {ext, eep, 0xd62728}}}};
  WritePlotPng(file, tz, panels, "t [s]", 1000, 220);
}

void PlotLocated(const diagnose::LocatedResidual& loc, const std::filesystem::path& file) {
  auto milli = [](std::vector<double> v) {
    for (double& x : v) x *= 1e3;
    return v;
  };
  std::vector<PlotPanel> panels{
      {"pitch residual x sign of slope change vs wheel position from a terrain breakpoint", "mrad",
       {{"slow trials", milli(loc.slow_pitch), 0x1f77b4}, {"fast trials", milli(loc.fast_pitch), 0xd62728}}},
      {"Z residual x sign of slope change vs wheel position from a terrain breakpoint", "mm",
       {{"slow trials", milli(loc.slow_z), 0x1f77b4}, {"fast trials", milli(loc.fast_z), 0xd62728}}}};
  WritePlotPng(file, loc.distance, panels, "wheel position from the terrain breakpoint [m]", 1000, 260);
}

std::string Markdown(const Diagnosis& d, const std::string& base_source,
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
  for (const diagnose::Cause& c : d.causes) {
    md += "- `" + std::string(effects::EffectName(c.effect)) + "`: " +
          effects::EffectDescription(c.effect) + "; removes " + Fixed(c.heldout_gain_pct, 1) +
          " % of the held-out error above noise (chosen on the selection trials: " +
          Fixed(100.0 * c.selection_gain, 1) + " %).\n";
  }
  md += "\nNoise (from the data, 4th differences): Z " + Sig(1e3 * d.sigma_z, 3) + " mm, pitch " +
        Sig(1e3 * d.sigma_pitch, 3) + " mrad; noise floor on the held-out trials: Z " +
        Fixed(d.noise_floor.z, 1) + " %, pitch " + Fixed(d.noise_floor.pitch, 1) + " %.\n\n";
  md += "- Base model residual tests: " + d.base_check.Evidence() + "\n";
  md += "- Extended model residual tests: " + d.extended_check.Evidence() + "\n\n";
  md += "| held-out fitness (MATLAB compare) | Z [%] | pitch [%] |\n|---|---|---|\n";
  md += "| base model | " + Fixed(d.base_heldout.z, 1) + " | " + Fixed(d.base_heldout.pitch, 1) + " |\n";
  md += "| extended model (" + d.cause + ") | " + Fixed(d.extended_heldout.z, 1) + " | " +
        Fixed(d.extended_heldout.pitch, 1) + " |\n\n";
  md += "(The paper reports 79.3 % for Z and 57.6 % for pitch on its real chair.)\n\n";
  md += "## Ranking\n\nAn extension earns its parameters when ΔBIC (training) < -10 and it "
        "removes at least 10 % of the held-out error.\n\n";
  md += "| # | effect | earns | held-out gain | ΔBIC | held-out fit Z / pitch [%] | parameters | evidence |\n";
  md += "|---|---|---|---|---|---|---|---|\n";
  int rank = 1;
  for (const RankEntry& e : d.ranking) {
    std::string params;
    for (const auto& [name, value] : e.parameters) {
      if (!params.empty()) params += ", ";
      params += name + " " + Sig(value, 4);
    }
    md += "| " + std::to_string(rank++) + " | " + effects::EffectName(e.effect) + " | " +
          (e.earns ? "yes" : "no") + " | " + Fixed(100.0 * e.heldout_gain, 1) + " % | " +
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

}  // namespace

const CommandSpec& DiagnoseSpec() {
  static const CommandSpec spec{
      "diagnose",
      "pwsim diagnose TRIAL_DIR... [options]",
      "Find what the base model gets wrong on measured trials, name the cause, extend the model "
      "and measure the gain on held-out trials (diagnosis.json, diagnosis.md).",
      {
          {"out", "DIR", "-", "out/diagnose", "output folder (diagnosis.json, diagnosis.md, plots/)"},
          {"effects", "LIST", "-", "all", "candidate effect ids, comma separated"},
          {"min-gain", "G", "-", "0.10", "share of the held-out error an extension must remove"},
          {"bic-threshold", "B", "-", "-10", "ΔBIC an extension must beat (training trials)"},
          {"threads", "N", "-", "2", "solver threads"},
          {"max-plots", "N", "-", "3", "held-out trials to plot"},
      },
      "TRIAL_DIR  measured trial folders (trial.yaml, chair, terrain, mocap), at least 2"};
  return spec;
}

int DiagnoseCommand(const ParsedArgs& args) {
  if (args.positional().size() < 2) throw std::invalid_argument("expected at least 2 TRIAL_DIR");
  const std::filesystem::path out = args.Get("out");
  diagnose::DiagnoseOptions options;
  options.candidates = ParseCandidates(args.Get("effects"));
  options.min_heldout_gain = args.GetDouble("min-gain");
  if (!(options.min_heldout_gain >= 0.0 && options.min_heldout_gain < 1.0))
    throw std::invalid_argument("option --min-gain: expected a number in [0, 1)");
  options.bic_threshold = args.GetDouble("bic-threshold");
  const long long threads = args.GetInt("threads");
  if (threads < 1 || threads > 64) throw std::invalid_argument("option --threads: expected 1..64");
  options.fit.threads = static_cast<int>(threads);
  const long long max_plots = args.GetInt("max-plots");
  if (max_plots < 0) throw std::invalid_argument("option --max-plots: expected an integer >= 0");

  // 1. Old results go first, so that a run that fails below never leaves a report that looks
  //    complete; then every input is read before anything new is written.
  for (const char* name : {"diagnosis.json", "diagnosis.md"}) std::filesystem::remove(out / name);
  if (std::filesystem::exists(out / "plots")) {
    for (const auto& entry : std::filesystem::directory_iterator(out / "plots"))
      if (entry.path().extension() == ".png") std::filesystem::remove(entry.path());
  }
  std::vector<MeasuredTrial> trials;
  for (const std::string& folder : args.positional()) trials.push_back(ReadMeasuredTrial(folder));

  // 2. Diagnose.
  const auto started = std::chrono::steady_clock::now();
  std::string base_source;
  const std::vector<effects::TrialRecord> records = diagnose::RecordsFromMeasured(trials, &base_source);
  const Diagnosis d = diagnose::Diagnose(records, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  // 3. Write: stale results first, then plots, the report, and diagnosis.json last.
  std::filesystem::create_directories(out / "plots");
  std::vector<std::string> plots{"plots/located-residual.png"};
  PlotLocated(d.residuals.located, out / plots.front());
  long long drawn = 0;
  for (const auto& t : d.trials) {
    if (!t.heldout || drawn >= max_plots) continue;
    plots.push_back("plots/residual-" + t.name + ".png");
    PlotResiduals(t, d.cause, out / plots.back());
    ++drawn;
  }
  WriteFileAtomically(out / "diagnosis.md", Markdown(d, base_source, plots, seconds));
  WriteFileAtomically(out / "diagnosis.json", DiagnosisJson(d, base_source, seconds).dump(2) + "\n");

  std::cout << "pwsim diagnose: " << trials.size() << " trials, verdict: "
            << diagnose::VerdictName(d.verdict) << ", cause: " << d.cause;
  for (std::size_t k = 1; k < d.causes.size(); ++k) std::cout << " + " << effects::EffectName(d.causes[k].effect);
  std::cout << "\n"
            << "  held-out fit (base -> extended): Z " << Fixed(d.base_heldout.z, 1) << " -> "
            << Fixed(d.extended_heldout.z, 1) << " %, pitch " << Fixed(d.base_heldout.pitch, 1)
            << " -> " << Fixed(d.extended_heldout.pitch, 1) << " %\n";
  for (const RankEntry& e : d.ranking) {
    std::cout << "  " << std::left << std::setw(22) << effects::EffectName(e.effect) << " gain "
              << std::right << std::setw(6) << Fixed(100.0 * e.heldout_gain, 1) << " %  ΔBIC "
              << std::setw(9) << Fixed(e.delta_bic, 0) << (e.earns ? "  earns" : "") << "\n";
  }
  std::cout << "  " << (out / "diagnosis.json").string() << "\n  " << (out / "diagnosis.md").string()
            << "\n";
  return 0;
}

}  // namespace pwsim::app
