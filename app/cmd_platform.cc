// pwsim platform identify|diagnose|frequency-response: identification, diagnosis and frequency
// response of platform axes from recordings (shared/spec/platform-data.md). Wiring only: the
// methods are in sysid/platform/, the reports in report/platform_report.*.

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "app/commands.h"
#include "report/platform_report.h"
#include "sysid/platform/axis_diagnose.h"
#include "sysid/platform/axis_recording.h"
#include "sysid/platform/frequency_response.h"
#include "sysid/platform/idim.h"

namespace pwsim::app {
namespace {

namespace sp = sysid::platform;

std::vector<std::string> SplitList(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

std::vector<sp::AxisRecording> ReadAll(const std::vector<std::string>& files) {
  std::vector<sp::AxisRecording> out;
  for (const std::string& f : files) out.push_back(sp::ReadAxisRecording(f));
  return out;
}

void RemoveOld(const std::vector<std::filesystem::path>& files) {
  for (const auto& f : files) std::filesystem::remove(f);
}

void PrintWritten(const std::string& verb, const std::vector<std::filesystem::path>& files) {
  for (const auto& f : files) std::cout << "pwsim platform " << verb << ": wrote " << f.string() << "\n";
}

sp::IdimOptions IdimFromArgs(const ParsedArgs& args) {
  sp::IdimOptions o;
  o.lowpass_cutoff_hz = args.GetDouble("cutoff-hz");
  if (!(o.lowpass_cutoff_hz > 0.0))
    throw UsageError("option --cutoff-hz: expected a frequency > 0 Hz, got " + args.Get("cutoff-hz"));
  o.decimation = static_cast<int>(args.GetInt("decimation", 1, 100));
  o.end_border_samples = static_cast<int>(args.GetInt("end-border", 0, 1000000));
  return o;
}

sp::AxisDiagnoseOptions DiagnoseFromArgs(const ParsedArgs& args) {
  sp::AxisDiagnoseOptions o;
  o.idim = IdimFromArgs(args);
  o.holdout_fraction = args.GetDouble("holdout", 0.05, 0.95);
  o.selection_fraction = args.GetDouble("selection", 0.05, 0.95);
  o.block_s = args.GetDouble("block-s", 0.05, 3600.0);
  return o;
}

}  // namespace

const CommandSpec& PlatformSpec() {
  static const CommandSpec spec{
      "platform",
      "pwsim platform identify|diagnose|frequency-response RECORDING... --out DIR [options]",
      "Identify, diagnose or measure the frequency response of platform axes from recordings.",
      {
          {"out", "DIR", "-", "", "output folder (required)"},
          {"validate", "FILE[,FILE...]", "-", "",
           "recordings held out for the cross-test / diagnosis (comma-separated)"},
          {"model", "NAME", "-", "",
           "identify: axis-base | axis-asymmetric | friction | rail-yaw (default by joints)"},
          {"order", "N", "-", "0", "frequency-response: fit only this order (2 or 3; 0 = both)"},
          {"sweeps", "N", "-", "0", "frequency-response: equal sweeps per recording (0 = auto)"},
          {"holdout", "F", "-", "0.3",
           "diagnose without --validate: report share of each recording (0.05..0.95), read "
           "only to report"},
          {"selection", "F", "-", "0.3",
           "diagnose: selection share of what is not reported (0.05..0.95), which takes every "
           "decision; the rest is fitted"},
          {"block-s", "S", "s", "1",
           "diagnose: length of the contiguous blocks dealt to training, selection and report"},
          {"cutoff-hz", "HZ", "Hz", "100", "zero-phase low-pass on position"},
          {"decimation", "N", "-", "10", "parallel decimation factor"},
          {"end-border", "N", "samples", "0",
           "identify: samples dropped at the end (0 = reference method; use 49 for a recording "
           "that ends in fast motion)"},
      },
      "identify|diagnose|frequency-response, then recordings: pwsim-axis-trial/1 .yaml files "
      "or EMPS .mat files"};
  return spec;
}

int PlatformCommand(const ParsedArgs& args) {
  const auto& pos = args.positional();
  if (pos.empty())
    throw UsageError("expected a sub-command: identify, diagnose or frequency-response");
  const std::string verb = pos[0];
  const std::vector<std::string> files(pos.begin() + 1, pos.end());
  if (files.empty()) throw UsageError(verb + ": expected at least one RECORDING");
  if (args.Get("out").empty()) throw UsageError("option --out DIR is required");
  const std::filesystem::path out = args.Get("out");
  const std::vector<std::string> validate = SplitList(args.Get("validate"));

  if (verb == "identify") {
    const std::string model = args.Get("model");
    const auto& names = sp::ModelNames();
    if (!model.empty() && std::find(names.begin(), names.end(), model) == names.end()) {
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : " | ") + n;
      throw UsageError("option --model: expected " + list + ", got " + model);
    }
    RemoveOld(report::PlatformIdentifyOutputs(out));
    const sp::PlatformFit fit =
        sp::IdentifyPlatform(ReadAll(files), ReadAll(validate), args.Get("model"), IdimFromArgs(args));
    std::filesystem::create_directories(out);
    PrintWritten(verb, report::WritePlatformIdentifyReport(fit, out));
    std::cout << "pwsim platform identify: model " << fit.model.name << ", relative error "
              << fit.ls.relative_error_pct << " %, cond " << fit.ls.condition_number << ", "
              << fit.ls.rows << " rows\n";
    for (const auto& v : fit.validation)
      std::cout << "pwsim platform identify: cross-test " << v.recording << " "
                << v.relative_error_pct << " %\n";
    return 0;
  }
  if (verb == "diagnose") {
    RemoveOld(report::PlatformDiagnoseOutputs(out));
    const sp::AxisDiagnoseOptions o = DiagnoseFromArgs(args);
    const sp::AxisDiagnosis d = sp::DiagnoseAxis(ReadAll(files), ReadAll(validate), o);
    std::filesystem::create_directories(out);
    PrintWritten(verb, report::WritePlatformDiagnosisReport(d, out));
    std::cout << "pwsim platform diagnose: verdict " << diagnose::VerdictName(d.verdict)
              << ", cause " << d.cause << ", report-row (held-out) relative error "
              << d.heldout_base_pct << " % -> " << d.heldout_extended_pct << " % (noise floor "
              << d.noise_floor_pct << " %)\n";
    for (const sp::AxisCause& c : d.causes)
      std::cout << "pwsim platform diagnose: cause " << sp::AxisEffectId(c.effect) << " gain "
                << c.heldout_gain_pct << " % (se " << c.heldout_gain_se_pct << " %, "
                << (c.confirmed ? "confirmed" : "not confirmed") << ")\n";
    return 0;
  }
  if (verb == "frequency-response") {
    RemoveOld(report::PlatformFrequencyOutputs(out));
    sp::FrequencyResponseOptions o;
    o.sweeps = static_cast<int>(args.GetInt("sweeps", 0, 10000));
    const long long order = args.GetInt("order");
    if (order != 0 && order != 2 && order != 3)
      throw UsageError("option --order: expected 2, 3 or 0 (both), got " + args.Get("order"));
    if (order != 0) o.orders = {static_cast<int>(order)};
    const auto joints = sp::EstimateFrequencyResponse(ReadAll(files), o);
    std::filesystem::create_directories(out);
    PrintWritten(verb, report::WriteFrequencyResponseReport(joints, out));
    for (const auto& j : joints)
      std::cout << "pwsim platform frequency-response: " << j.joint << " bandwidth "
                << j.bandwidth_rad_s << " rad/s\n";
    return 0;
  }
  throw UsageError("unknown sub-command '" + verb +
                              "' (expected identify, diagnose or frequency-response)");
}

}  // namespace pwsim::app
