#pragma once
// The report of `pwsim diagnose` (measured-trials.md, pwsim-diagnosis/1): diagnosis.json, the
// human report diagnosis.md, and its plots (plot/plot.h: PNG, SVG and the data as CSV):
// plots/located-residual.* (residual against wheel position from a terrain breakpoint) and
// plots/residual-<trial>.* (measured, base and extended model of held-out trials).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sysid/diagnose/diagnose.h"

namespace pwsim::report {

/// diagnosis.json's content.
nlohmann::ordered_json DiagnosisJson(const diagnose::Diagnosis& d, const std::string& base_source,
                                     double seconds);

/// The verdict's inputs, tidy (diagnosis.json's `verdict_inputs`): the limits of the run, the
/// noise model per channel (σ̂, the 4th-difference σ̂, its autocorrelation), and each residual
/// test's statistic and bound for the base and the extended model.
nlohmann::ordered_json VerdictInputsJson(const diagnose::Diagnosis& d);

/// The probability of `id` being present (Diagnosis::probabilities; 0 when not a candidate).
double ProbabilityOf(const diagnose::Diagnosis& d, effects::EffectId id);

/// A text bar of `width` cells, p ∈ [0, 1] of them filled ("█", the rest "·").
std::string ProbabilityBar(double p, int width);

/// diagnosis.md's section of one bar per candidate effect, most probable first.
std::string ProbabilityBars(const diagnose::Diagnosis& d);

/// diagnosis.md's content; `plots` are paths relative to the report, located residual first.
std::string DiagnosisMarkdown(const diagnose::Diagnosis& d, const std::string& base_source,
                              const std::vector<std::string>& plots, double seconds);

/// Measured, base and extended model of one held-out trial, and both residuals.
void PlotResiduals(const diagnose::TrialAnalysis& t, const std::string& cause,
                   const std::filesystem::path& file);

/// The residual against the wheel's distance from a terrain breakpoint, slow vs fast trials.
void PlotLocated(const diagnose::LocatedResidual& loc, const std::filesystem::path& file);

/// Removes an earlier run's diagnosis.json, diagnosis.md and plots: call it BEFORE reading the
/// inputs, so that a run that fails never leaves an old report that looks like its own.
void RemoveDiagnosisReport(const std::filesystem::path& out);

/// Writes everything under `out`: stale reports removed first, then the plots (at most
/// `max_plots` held-out trials), diagnosis.md, and diagnosis.json last.
void WriteDiagnosisReport(const std::filesystem::path& out, const diagnose::Diagnosis& d,
                          const std::string& base_source, double seconds, long long max_plots);

}  // namespace pwsim::report
