#pragma once
// The report of `pwsim identify` (measured-trials.md, pwsim-fit/1): fit.json, the identified
// chair YAML, identify.md with the identified parameters beside Table I (and the truth, when
// given), per-trial fitness, and overlay plots like the paper's Fig. 5 (plot/plot.h).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "sysid/diagnose/model_check.h"
#include "sysid/identify/identify.h"
#include "sysid/measured/measured_trial.h"

namespace pwsim::report {

/// One parameter of the identified chair beside Table I and, when known, the truth.
struct ParameterRow {
  std::string name;
  std::string unit;
  double identified{0.0};
  double table_one{0.0};
  std::optional<double> truth;
};

/// α_i, β_ij (adjacent and others) and K, C per axis of `identified`.
std::vector<ParameterRow> ParameterRows(const Chair& identified, const Chair* truth);

/// The console table printed by `pwsim identify`.
std::string TextTable(const std::vector<ParameterRow>& rows, bool with_truth);

/// The same as a markdown table.
std::string MarkdownTable(const std::vector<ParameterRow>& rows, bool with_truth);

/// The overlay figure of one trial, like Fig. 5: GM input, Z and θ, measured vs model.
void PlotTrial(const MeasuredTrial& trial, const Chair& chair, const TrialComparison& cmp,
               const std::filesystem::path& file);

/// What the identification report is made of.
struct IdentificationReportInput {
  const std::vector<MeasuredTrial>* trials{nullptr};
  const std::vector<TrialRole>* roles{nullptr};
  const IdentifyResult* result{nullptr};
  const IdentifyOptions* options{nullptr};
  const Chair* truth{nullptr};               ///< nullptr when no truth is known
  std::filesystem::path truth_file;          ///< where the truth came from
  long long max_plots{12};
  const diagnose::ModelCheck* check{nullptr};  ///< the model's residual against the noise; none: not checked
};

/// What the check of the identified model says, for the console and identify.md: the noise and
/// its floor beside the fitness, the structured RMS, and, where the model is measurably wrong,
/// that it is and that `pwsim diagnose` is the next step. `fit_z`, `fit_pitch`: the fitness on
/// the judged trials [%].
std::string ModelCheckText(const diagnose::ModelCheck& check, double fit_z, double fit_pitch);

/// Writes under `out`: stale outputs removed first, the overlay plots, identified-chair.yaml,
/// identify.md, and fit.json last. Returns the parameter rows (for the console table).
/// Removes an earlier run's fit.json, identify.md and identified-chair.yaml: call it BEFORE
/// reading the inputs, so that a failed run never leaves an old report that looks like its own.
void RemoveIdentificationReport(const std::filesystem::path& out);

std::vector<ParameterRow> WriteIdentificationReport(const std::filesystem::path& out,
                                                    const IdentificationReportInput& in);

}  // namespace pwsim::report
