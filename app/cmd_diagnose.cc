// pwsim diagnose TRIAL_DIR... --out DIR: finds what the identified base model gets wrong on
// measured trials, names the cause among the effect ids of measured-trials.md, extends and
// re-identifies the model and measures the gain on held-out trials (sysid/diagnose/).
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
#include "app/output_folder.h"
#include "app/progress.h"
#include "sysid/diagnose/diagnose.h"
#include "sysid/effects/effect_catalog.h"
#include "sysid/measured/measured_trial.h"
#include "report/diagnosis_report.h"
#include "report/format.h"

namespace pwsim::app {
namespace {

using diagnose::Diagnosis;
using diagnose::RankEntry;
using report::Fixed;

std::vector<effects::EffectId> ParseCandidates(const std::string& text) {
  if (text == "all") return {effects::AllEffects().begin(), effects::AllEffects().end()};
  std::vector<effects::EffectId> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto id = effects::ParseEffect(item);
    if (!id) {
      throw UsageError("option --effects: expected 'all' or a comma list of " +
                                  effects::EffectNameList() + ", got '" + item + "'");
    }
    out.push_back(*id);
  }
  if (out.empty()) throw UsageError("option --effects: expected at least one effect id");
  return out;
}

}  // namespace

const CommandSpec& DiagnoseSpec() {
  static const CommandSpec spec{
      "diagnose",
      "pwsim diagnose TRIAL_DIR... [options]",
      "Find what the base model gets wrong on measured trials, name the cause, extend the model "
      "and measure the gain on held-out trials (diagnosis.json, diagnosis.md).",
      {
          OutOption("diagnose", "diagnosis.json, diagnosis.md, plots/"),
          {"effects", "LIST", "-", "all", "candidate effect ids, comma separated"},
          {"min-gain", "G", "-", "0.10",
           "gain an extension must reach on the selection trials to earn: the share of their error above the "
           "noise it removes (the held-out gain is measured, never used to choose)"},
          {"bic-threshold", "B", "-", "-10", "ΔBIC an extension must beat (training trials)"},
          {"max-causes", "N", "-", "3", "forward selection stops after this many causes"},
          {"rest-window", "S", "s", "0.25", "initial window taken as rest (centring; least noise window)"},
          {"rho-max", "R", "sigma", "0.75", "verdict (a),(c): structured RMS allowed, in noise stds"},
          {"rho-local", "R", "sigma", "1.5", "verdict (b): structured RMS allowed in the worst window"},
          {"window-s", "S", "s", "0.5", "verdict (b): window length"},
          {"input-r-max", "R", "-", "0.4", "verdict (d): correlation with the GM input allowed"},
          {"clip-sigma", "C", "sigma", "5", "verdict (a),(b): residuals clipped at C noise stds (outliers)"},
          {"threads", "N", "-", "2", "threads for the candidate fits (results identical for any N)"},
          {"max-plots", "N", "-", "3", "held-out trials to plot"},
          QuietOption(),
      },
      "TRIAL_DIR  measured trial folders (trial.yaml, chair, terrain, mocap), at least 2"};
  return spec;
}

int DiagnoseCommand(const ParsedArgs& args) {
  if (args.positional().size() < 2) throw UsageError("expected at least 2 TRIAL_DIR");
  const std::filesystem::path out = OutDir(args);
  diagnose::DiagnoseOptions options;
  options.candidates = ParseCandidates(args.Get("effects"));
  options.min_selection_gain = args.GetDouble("min-gain");
  if (!(options.min_selection_gain >= 0.0 && options.min_selection_gain < 1.0))
    throw UsageError("option --min-gain: expected a number in [0, 1)");
  options.bic_threshold = args.GetDouble("bic-threshold");
  auto ranged = [&](const std::string& name, double lo, double hi) {
    const double v = args.GetDouble(name);
    if (!(v >= lo && v <= hi)) {
      std::ostringstream message;
      message << "option --" << name << ": expected a number in [" << lo << ", " << hi << "], got "
              << args.Get(name);
      throw UsageError(message.str());
    }
    return v;
  };
  const long long max_causes = args.GetInt("max-causes");
  if (max_causes < 0 || max_causes > 8) throw UsageError("option --max-causes: expected 0..8");
  options.max_causes = static_cast<int>(max_causes);
  options.rest_window = ranged("rest-window", 0.02, 5.0);
  options.verdict.rho_max = ranged("rho-max", 0.0, 100.0);
  options.verdict.rho_local = ranged("rho-local", 0.0, 100.0);
  options.verdict.window_s = ranged("window-s", 0.05, 10.0);
  options.verdict.input_r_max = ranged("input-r-max", 0.0, 1.0);
  options.verdict.clip_sigma = ranged("clip-sigma", 1.0, 1e6);
  const long long threads = args.GetInt("threads");
  if (threads < 1 || threads > 64) throw UsageError("option --threads: expected 1..64");
  options.threads = static_cast<int>(threads);
  const long long max_plots = args.GetInt("max-plots");
  if (max_plots < 0) throw UsageError("option --max-plots: expected an integer >= 0");

  // 1. Old results go first (a failed run must not leave a report that looks complete), then
  //    every input is read: a bad file stops here, before anything is written.
  Progress progress("pwsim diagnose", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  options.progress = progress.callback();
  OutputFolder folder(out, "diagnose");  // what the last command wrote there goes
  report::RemoveDiagnosisReport(out);
  progress.Stage("read the trials", static_cast<int>(args.positional().size()));
  std::vector<MeasuredTrial> trials;
  for (const std::string& trial : args.positional()) {
    trials.push_back(ReadMeasuredTrial(trial));
    progress.Report("read the trials", static_cast<int>(trials.size()), static_cast<int>(args.positional().size()));
  }

  // 2. Diagnose.
  const auto started = std::chrono::steady_clock::now();
  std::string base_source;
  const std::vector<effects::TrialRecord> records = diagnose::RecordsFromMeasured(trials, &base_source);
  const Diagnosis d = diagnose::Diagnose(records, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  // 3. Write: stale results first, then plots, the report, and diagnosis.json last.
  progress.Stage("write the report");
  report::WriteDiagnosisReport(out, d, base_source, seconds, max_plots);
  progress.Finish();

  std::cout << "pwsim diagnose: " << trials.size() << " trials, verdict: "
            << diagnose::VerdictName(d.verdict) << ", cause: " << d.cause;
  // Found: earned on the selection trials and confirmed by the held-out ones (diagnose.h).
  auto list = [&](bool confirmed) {
    std::string line;
    for (const diagnose::Cause& c : d.causes)
      if (c.confirmed == confirmed)
        line += std::string(line.empty() ? "" : ", ") + effects::EffectName(c.effect) + " " +
               Fixed(c.heldout_gain_pct, 1) + " % [" + Fixed(c.heldout_gain_lower_pct, 1) + ", " +
               Fixed(c.heldout_gain_upper_pct, 1) + "]";
    return line;
  };
  std::cout << "\n";
  if (!list(true).empty()) std::cout << "  found (held-out gain [90 % interval]): " << list(true) << "\n";
  if (!list(false).empty())
    std::cout << "  chosen on the selection trials, not confirmed on the held-out ones: " << list(false) << "\n";
  std::cout << "  held-out fit (base -> extended): Z " << Fixed(d.base_heldout.z, 1) << " -> "
            << Fixed(d.extended_heldout.z, 1) << " %, pitch " << Fixed(d.base_heldout.pitch, 1)
            << " -> " << Fixed(d.extended_heldout.pitch, 1) << " %\n"
            << "  gain = share of the error above the noise removed; each extension alone against the base:\n"
            << "  " << std::left << std::setw(22) << "effect" << std::right << std::setw(11) << "selection"
            << std::setw(30) << "held-out [90 % interval]" << std::setw(10) << "ΔBIC" << "  P(present)\n";
  for (const RankEntry& e : d.ranking) {
    const std::string heldout = Fixed(e.heldout_gain.pct, 1) + " % [" + Fixed(e.heldout_gain.lower_pct, 1) +
                                ", " + Fixed(e.heldout_gain.upper_pct, 1) + "]";
    std::cout << "  " << std::left << std::setw(22) << effects::EffectName(e.effect) << std::right
              << std::setw(9) << Fixed(100.0 * e.selection_gain, 1) << " %" << std::setw(30) << heldout
              << std::setw(10) << Fixed(e.delta_bic, 0) << "  " << report::ProbabilityBar(report::ProbabilityOf(d, e.effect), 10)
              << " " << Fixed(report::ProbabilityOf(d, e.effect), 2) << (e.earns ? "  earns" : "") << "\n";
  }
  folder.Print(std::cout, "pwsim diagnose");
  return 0;
}

}  // namespace pwsim::app
