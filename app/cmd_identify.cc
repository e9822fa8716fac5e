// pwsim identify TRIAL_DIR... --out DIR: identifies the chair's GM (α, β) and LM (K, C) from
// measured trials (sysid/identify/identify.h) and writes DIR/identified-chair.yaml,
// DIR/fit.json (measured-trials.md), DIR/identify.md with overlay plots like the paper's
// Fig. 5, and prints the identified table beside Table I (and the truth, when the trial
// set has a truth beside it, <set>.truth-chair.yaml, as generated sets do). Wiring only.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "app/commands.h"
#include "app/output_folder.h"
#include "app/progress.h"
#include "engine/chair.h"
#include "sysid/diagnose/model_check.h"
#include "sysid/identify/identify.h"
#include "sysid/measured/measured_trial.h"
#include "report/format.h"
#include "report/identification_report.h"
#include "synth/generate.h"

namespace pwsim::app {

const CommandSpec& IdentifySpec() {
  static const CommandSpec spec{
      "identify",
      "pwsim identify TRIAL_DIR... [options]",
      "Identify the chair's GM (alpha, beta) and LM (K, C) from measured trials; write fit.json.",
      {
          OutOption("identify", "identified-chair.yaml, fit.json, identify.md, plots/"),
          {"shared-mode", "", "-", "", "one natural frequency and damping ratio for Z and pitch (the paper)"},
          {"reference-load-kg", "KG", "kg", "", "load at which --shared-mode's mode is shared; default: heaviest LM trial"},
          {"passes", "N", "-", "2", "GM/LM alternations (1 = the paper's single pass)"},
          {"all-beta-pairs", "", "-", "", "fit every beta_ij (default: adjacent wheels; 1-3 is nearly collinear)"},
          {"holdout-every", "N", "-", "3", "with only two speeds: hold out every N-th faster trial for validation"},
          {"dt-ms", "MS", "ms", "1", "internal step of the exact lumped model"},
          {"max-plots", "N", "-", "12", "overlay plots to draw (validation trials first)"},
          QuietOption(),
      },
      "TRIAL_DIR  measured-trial folders (trial.yaml, chair, terrain, mocap); e.g. assets/trials-demo/*"};
  return spec;
}

int IdentifyCommand(const ParsedArgs& args) {
  if (args.positional().empty()) throw UsageError("expected at least one TRIAL_DIR");
  const std::filesystem::path out = OutDir(args);
  IdentifyOptions options;
  options.shared_mode = args.Flag("shared-mode");
  if (args.Has("reference-load-kg")) options.reference_load_kg = args.GetDouble("reference-load-kg", 0.0, 1000.0);
  const long long passes = args.GetInt("passes");
  if (passes < 1 || passes > 10) throw UsageError("option --passes: expected 1..10");
  options.passes = static_cast<int>(passes);
  options.all_beta_pairs = args.Flag("all-beta-pairs");
  const double dt_ms = args.GetDouble("dt-ms");
  if (!(dt_ms > 0.0 && dt_ms <= 10.0)) throw UsageError("option --dt-ms: expected (0, 10]");
  options.simulation.dt = dt_ms * 1e-3;
  RoleOptions role_options;
  role_options.holdout_every = static_cast<int>(args.GetInt("holdout-every", 0, 1000));
  const long long max_plots = args.GetInt("max-plots", 0, 10000);

  // 1. Old results go first (a failed run must not leave a report that looks complete), then
  //    every input is read: a bad file stops here, before anything is written.
  Progress progress("pwsim identify", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  OutputFolder folder(out, "identify");  // what the last command wrote there goes
  report::RemoveIdentificationReport(out);
  progress.Stage("read the trials", static_cast<int>(args.positional().size()));
  std::vector<MeasuredTrial> trials;
  for (const std::string& trial : args.positional()) {
    trials.push_back(ReadMeasuredTrial(trial));
    progress.Report("read the trials", static_cast<int>(trials.size()), static_cast<int>(args.positional().size()));
  }
  std::optional<Chair> truth;
  const std::filesystem::path truth_file =
      TruthFileBeside(trials.front().folder.parent_path(), "truth-chair.yaml");
  if (std::filesystem::exists(truth_file)) truth = ReadChairFile(truth_file);

  // 2. Identify.
  const std::vector<TrialRole> roles = AssignRoles(trials, role_options);
  progress.Stage("identify the chair");
  const IdentifyResult result = IdentifyChair(trials, roles, options);
  // Its own residual against the noise (sysid/diagnose/model_check.h), on the validation trials.
  std::vector<bool> judged;
  for (TrialRole role : roles) judged.push_back(role == TrialRole::kValidation);
  const diagnose::ModelCheck check = diagnose::CheckModelOnTrials(trials, result.chair, judged, options.offset_window);
  progress.Stage("write the report");

  // 3. Write: stale results go first, the plots, then the report and fit.json last.
  report::IdentificationReportInput report_input;
  report_input.trials = &trials;
  report_input.roles = &roles;
  report_input.result = &result;
  report_input.options = &options;
  report_input.truth = truth ? &*truth : nullptr;
  report_input.truth_file = truth_file;
  report_input.max_plots = max_plots;
  report_input.check = &check;
  const std::vector<report::ParameterRow> rows = report::WriteIdentificationReport(out, report_input);

  progress.Finish();
  std::cout << "pwsim identify: " << trials.size() << " trials\n\n"
            << report::TextTable(rows, truth.has_value()) << "\nvalidation fit (held out): Z "
            << report::Fixed(result.validation_fit_z, 1) << " %, pitch "
            << report::Fixed(result.validation_fit_pitch, 1) << " %\n"
            << report::ModelCheckText(check, result.validation_fit_z, result.validation_fit_pitch) << "\n";
  folder.Print(std::cout, "pwsim identify");
  return 0;
}

}  // namespace pwsim::app
