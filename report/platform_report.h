#pragma once
// Reports of `pwsim platform identify|diagnose|frequency-response` (shared/spec/platform-data.md):
// the JSON files of the contract, a Markdown report, and figures through plot/plot.h.
// Every file is written atomically; a figure that cannot be drawn (no gnuplot) is listed as
// missing in the Markdown report instead of failing the command.

#include <filesystem>
#include <string>
#include <vector>

#include "sysid/platform/axis_diagnose.h"
#include "sysid/platform/frequency_response.h"
#include "sysid/platform/idim.h"

namespace pwsim::report {

/// The files a command writes in DIR (removed before the inputs are read).
std::vector<std::filesystem::path> PlatformIdentifyOutputs(const std::filesystem::path& dir);
std::vector<std::filesystem::path> PlatformDiagnoseOutputs(const std::filesystem::path& dir);
std::vector<std::filesystem::path> PlatformFrequencyOutputs(const std::filesystem::path& dir);

/// platform-fit.json (pwsim-platform-fit/1), identify.md, identify-effort.{png,svg,csv,gp}.
/// Returns the files written.
std::vector<std::filesystem::path> WritePlatformIdentifyReport(
    const sysid::platform::PlatformFit& fit, const std::filesystem::path& dir);

/// diagnosis.json, diagnosis.md and its figures.
std::vector<std::filesystem::path> WritePlatformDiagnosisReport(
    const sysid::platform::AxisDiagnosis& diagnosis, const std::filesystem::path& dir);

/// frequency-response.json (pwsim-frequency-response/1), frequency-response.md, bode figures.
std::vector<std::filesystem::path> WriteFrequencyResponseReport(
    const std::vector<sysid::platform::JointFrequencyResponse>& joints,
    const std::filesystem::path& dir);

}  // namespace pwsim::report
