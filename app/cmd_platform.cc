// pwsim platform identify|diagnose|frequency-response: identification, diagnosis and frequency
// response of platform axes from recordings (shared/spec/platform-data.md); describe: a platform
// file's mechanism (mca/mechanism.h). Wiring only: the methods are in sysid/platform/ and
// mca/platform.*, the reports in report/platform_report.*.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "app/commands.h"
#include "app/output_folder.h"
#include "app/progress.h"
#include "engine/number_format.h"
#include "mca/platform.h"
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

/// `pwsim platform describe FILE [--pose ...] [--margin F] [--out DIR]`: the mechanism of a
/// platform file (mca::DescribePlatform), a pose checked against it, and drawing data.
int Describe(const ParsedArgs& args, const std::vector<std::string>& files) {
  if (files.size() != 1) throw UsageError("describe: expected one platform FILE (pwsim-platform/1)");
  const mca::PlatformSpec p = mca::ReadPlatformFile(files[0]);
  const mca::Mechanism& m = p.mechanism;
  const double margin = args.GetDouble("margin", 0.0, 0.45);
  std::cout << mca::DescribePlatform(p, margin);
  mca::DofArray pose{};
  if (args.Has("pose")) {
    std::vector<double> values;
    for (const std::string& item : SplitList(args.Get("pose"))) {
      const std::optional<double> v = ParseFiniteNumber(item);
      if (!v) throw UsageError("option --pose: expected 6 numbers, got '" + item + "'");
      values.push_back(*v);
    }
    if (values.size() != 6) {
      throw UsageError("option --pose: expected 6 comma-separated numbers SURGE_M,SWAY_M,HEAVE_M,ROLL_DEG,PITCH_DEG,YAW_DEG");
    }
    for (int k = 0; k < 6; ++k) pose[static_cast<std::size_t>(k)] = values[static_cast<std::size_t>(k)] * (k >= 3 ? mca::kDegToRad : 1.0);
    const std::string why = m.Reachability(pose, margin);
    if (!why.empty()) {
      throw std::runtime_error("pose " + args.Get("pose") + " (m, m, m, deg, deg, deg) is not reachable on " + p.name +
                               " with a " + std::to_string(static_cast<int>(100.0 * margin + 0.5)) + " % stroke margin: " + why);
    }
    mca::ActuatorVector q, use, f;
    m.Inverse(pose, &q);
    m.StrokeUse(q, &use);
    const bool forces = m.ActuatorForces(pose, m.PayloadWrench(pose), &f);
    std::cout << "pose " << args.Get("pose") << " (m, m, m, deg, deg, deg): reachable\n";
    char line[160];
    for (int i = 0; i < m.actuator_count(); ++i) {
      const bool rotary = m.actuator(i).kind == mca::ActuatorKind::kRotary;
      std::snprintf(line, sizeof line, "  %-17s %9.4f %-3s  stroke use %5.1f %%", m.actuator(i).name.c_str(),
                    q[i] * (rotary ? 1.0 / mca::kDegToRad : 1.0), rotary ? "deg" : "m", 100.0 * use[i]);
      std::cout << line;
      if (forces) {
        std::snprintf(line, sizeof line, "  static force %8.1f %s", std::abs(f[i]) < 0.05 ? 0.0 : f[i], rotary ? "N m" : "N");
        std::cout << line;
      }
      std::cout << "\n";
    }
  }
  if (!args.Has("out")) return 0;
  // drawing data (scripts/platform-drawings.sh): one gnuplot block per item
  const std::filesystem::path out = args.Get("out");
  std::filesystem::create_directories(out);
  const std::filesystem::path geometry = out / ("platform_" + p.name + "_geometry.dat");
  std::ofstream g(geometry);
  g << "# " << p.name << ": x y z [m] in B, id (actuator index; -1 pivot to head, -2 plate outline, -3 base\n"
       "# outline, -4 turntable rim and heading); index 0 at neutral, index 1 at --pose\n";
  for (const mca::DofArray& x : {mca::DofArray{}, pose}) {
    for (int i = 0; i < m.actuator_count(); ++i) {
      const mca::Actuator& a = m.actuator(i);
      Eigen::Vector3d base, plate;
      if (m.LegEndpoints(i, x, &base, &plate)) {
        g << base.x() << " " << base.y() << " " << base.z() << " " << i << "\n"
          << plate.x() << " " << plate.y() << " " << plate.z() << " " << i << "\n\n";
      } else if (a.kind == mca::ActuatorKind::kRail) {  // the rail's whole stroke, in the yawed frame
        const double yaw = x[static_cast<std::size_t>(mca::Index(mca::Dof::kYaw))];
        const Eigen::Vector3d axis = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                     Eigen::Vector3d::Unit(mca::Index(a.dof));
        for (double end : {a.limits.min, a.limits.max}) {
          const Eigen::Vector3d e = end * axis;
          g << e.x() << " " << e.y() << " " << e.z() << " " << i << "\n";
        }
        g << "\n";
      }
    }
    // outlines: the plate anchors (id −2) and base anchors (id −3) in angular order, closed
    for (const bool plate_side : {true, false}) {
      std::vector<std::pair<double, Eigen::Vector3d>> ring;
      for (int i = 0; i < m.actuator_count(); ++i) {
        Eigen::Vector3d base, plate;
        if (!m.LegEndpoints(i, x, &base, &plate)) continue;
        const Eigen::Vector3d& local = plate_side ? m.actuator(i).plate_anchor : m.actuator(i).base_anchor;
        ring.emplace_back(std::atan2(local.y(), local.x()), plate_side ? plate : base);
      }
      if (ring.size() < 3) continue;
      std::sort(ring.begin(), ring.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      ring.push_back(ring.front());
      for (const auto& [angle, point] : ring) {
        g << point.x() << " " << point.y() << " " << point.z() << " " << (plate_side ? -2 : -3) << "\n";
      }
      g << "\n";
    }
    // a rotary stage about z: its turntable rim (id −4), radius just outside the base anchors
    if (m.Moves(mca::Dof::kYaw) && !m.leg_axes()[static_cast<std::size_t>(mca::Index(mca::Dof::kYaw))]) {
      double radius = 0.5;
      for (int i = 0; i < m.actuator_count(); ++i) {
        if (m.actuator(i).kind == mca::ActuatorKind::kLeg) {
          radius = std::max(radius, m.actuator(i).base_anchor.head<2>().norm() + 0.08);
        }
      }
      const double yaw = x[static_cast<std::size_t>(mca::Index(mca::Dof::kYaw))];
      for (int k = 0; k <= 72; ++k) {
        const double a = 2.0 * mca::kPi * k / 72.0;
        g << radius * std::cos(a) << " " << radius * std::sin(a) << " 0 -4\n";
      }
      g << "\n" << 0.0 << " " << 0.0 << " 0 -4\n"  // the turntable's heading mark
        << radius * std::cos(yaw) << " " << radius * std::sin(yaw) << " 0 -4\n\n";
    }
    // the pivot and the head (head_from_pivot turned with the plate)
    Eigen::Isometry3d plate_frame = Eigen::Isometry3d::Identity();
    plate_frame.rotate(Eigen::AngleAxisd(x[5], Eigen::Vector3d::UnitZ()));
    plate_frame.translate(Eigen::Vector3d(x[0], x[1], m.pivot_height() + x[2]));
    plate_frame.rotate(Eigen::AngleAxisd(-x[4], Eigen::Vector3d::UnitY()));
    plate_frame.rotate(Eigen::AngleAxisd(x[3], Eigen::Vector3d::UnitX()));
    const Eigen::Vector3d head = plate_frame * Eigen::Vector3d(p.head_from_pivot[0], p.head_from_pivot[1], p.head_from_pivot[2]);
    const Eigen::Vector3d pivot = plate_frame.translation();
    g << pivot.x() << " " << pivot.y() << " " << pivot.z() << " -1\n"
      << head.x() << " " << head.y() << " " << head.z() << " -1\n\n\n";
  }
  std::cout << "pwsim platform describe: wrote " << geometry.string() << "\n";
  if (m.Moves(mca::Dof::kRoll) && m.Moves(mca::Dof::kPitch) && p.Has(mca::Dof::kRoll) && p.Has(mca::Dof::kPitch)) {
    const std::filesystem::path slice = out / ("platform_" + p.name + "_slice.dat");
    std::ofstream w(slice);
    w << "# " << p.name << ": roll [deg], pitch [deg], reachable with a " << 100.0 * margin
      << " % margin (0/1), largest stroke use; one block per heave [m]\n";
    const double heave_travel = p.Has(mca::Dof::kHeave) ? p.limits(mca::Dof::kHeave).travel : 0.0;
    w << "# box: roll_deg " << p.limits(mca::Dof::kRoll).travel / mca::kDegToRad << " pitch_deg "
      << p.limits(mca::Dof::kPitch).travel / mca::kDegToRad << " heave_m " << heave_travel << "\n";
    for (double heave : {0.0, 0.5 * heave_travel, -0.5 * heave_travel}) {
      mca::DofArray base{};
      base[static_cast<std::size_t>(mca::Index(mca::Dof::kHeave))] = heave;
      w << "# heave " << heave << "\n";
      int row = 0;
      for (const mca::WorkspacePoint& pt : mca::WorkspaceSlice(p, mca::Dof::kRoll, mca::Dof::kPitch, base, 1.5, 121, margin)) {
        w << pt.pose[3] / mca::kDegToRad << " " << pt.pose[4] / mca::kDegToRad << " " << (pt.reachable ? 1 : 0) << " "
          << pt.stroke_use << "\n";
        if (++row % 121 == 0) w << "\n";
      }
      w << "\n";
    }
    std::cout << "pwsim platform describe: wrote " << slice.string() << "\n";
  }
  return 0;
}

}  // namespace

const CommandSpec& PlatformSpec() {
  static const CommandSpec spec{
      "platform",
      "pwsim platform identify|diagnose|frequency-response RECORDING... [--out DIR] [options]\n"
      "       pwsim platform describe PLATFORM.yaml [--pose S,W,H,R,P,Y] [--margin F] [--out DIR]",
      "Identify, diagnose or measure the frequency response of platform axes from recordings; "
      "describe a platform file's mechanism (actuators, workspace, leg forces) and check a pose.",
      {
          {"out", "DIR", "", "", "output folder (default out/platform-SUBCOMMAND, e.g. out/platform-identify; describe: only with --out, drawing data)"},
          {"pose", "S,W,H,R,P,Y", "m,deg", "",
           "describe: a pose to check (surge, sway, heave m; roll, pitch, yaw deg): refused with the "
           "actuator and its numbers when unreachable"},
          {"margin", "F", "-", "0.05", "describe: stroke margin, share of each stroke kept free at both ends"},
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
          QuietOption(),
      },
      "identify|diagnose|frequency-response, then recordings: pwsim-axis-trial/1 .yaml files "
      "or EMPS .mat files; or describe, then one platform file"};
  return spec;
}

int PlatformCommand(const ParsedArgs& args) {
  const auto& pos = args.positional();
  if (pos.empty())
    throw UsageError("expected a sub-command: identify, diagnose, frequency-response or describe");
  const std::string verb = pos[0];
  const std::vector<std::string> files(pos.begin() + 1, pos.end());
  if (verb == "describe") return Describe(args, files);
  if (files.empty()) throw UsageError(verb + ": expected at least one RECORDING");
  const std::filesystem::path out = OutDir(args, verb);
  const std::vector<std::string> validate = SplitList(args.Get("validate"));
  Progress progress("pwsim platform " + verb, args.Flag("quiet"));  // stages on stderr (app/progress.h)

  if (verb == "identify") {
    const std::string model = args.Get("model");
    const auto& names = sp::ModelNames();
    if (!model.empty() && std::find(names.begin(), names.end(), model) == names.end()) {
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : " | ") + n;
      throw UsageError("option --model: expected " + list + ", got " + model);
    }
    OutputFolder folder(out, "platform identify");  // what the last command wrote there goes
    RemoveOld(report::PlatformIdentifyOutputs(out));
    progress.Stage("read the recordings");
    const std::vector<sp::AxisRecording> recordings = ReadAll(files), held_out = ReadAll(validate);
    progress.Stage("identify the axes");
    const sp::PlatformFit fit = sp::IdentifyPlatform(recordings, held_out, args.Get("model"), IdimFromArgs(args));
    progress.Stage("write the report");
    report::WritePlatformIdentifyReport(fit, out);
    progress.Finish();
    std::cout << "pwsim platform identify: model " << fit.model.name << ", relative error "
              << fit.ls.relative_error_pct << " %, cond " << fit.ls.condition_number << ", "
              << fit.ls.rows << " rows\n";
    for (const auto& v : fit.validation)
      std::cout << "pwsim platform identify: cross-test " << v.recording << " "
                << v.relative_error_pct << " %\n";
    folder.Print(std::cout, "pwsim platform identify");
    return 0;
  }
  if (verb == "diagnose") {
    OutputFolder folder(out, "platform diagnose");  // what the last command wrote there goes
    RemoveOld(report::PlatformDiagnoseOutputs(out));
    const sp::AxisDiagnoseOptions o = DiagnoseFromArgs(args);
    progress.Stage("read the recordings");
    const std::vector<sp::AxisRecording> recordings = ReadAll(files), held_out = ReadAll(validate);
    progress.Stage("diagnose the axes");
    const sp::AxisDiagnosis d = sp::DiagnoseAxis(recordings, held_out, o);
    progress.Stage("write the report");
    report::WritePlatformDiagnosisReport(d, out);
    progress.Finish();
    std::cout << "pwsim platform diagnose: verdict " << diagnose::VerdictName(d.verdict)
              << ", cause " << d.cause << ", report-row (held-out) relative error "
              << d.heldout_base_pct << " % -> " << d.heldout_extended_pct << " % (noise floor "
              << d.noise_floor_pct << " %)\n";
    for (const sp::AxisCause& c : d.causes)
      std::cout << "pwsim platform diagnose: cause " << sp::AxisEffectId(c.effect) << " gain "
                << c.heldout_gain_pct << " % (se " << c.heldout_gain_se_pct << " %, "
                << (c.confirmed ? "confirmed" : "not confirmed") << ")\n";
    folder.Print(std::cout, "pwsim platform diagnose");
    return 0;
  }
  if (verb == "frequency-response") {
    OutputFolder folder(out, "platform frequency-response");  // what the last command wrote there goes
    RemoveOld(report::PlatformFrequencyOutputs(out));
    sp::FrequencyResponseOptions o;
    o.sweeps = static_cast<int>(args.GetInt("sweeps", 0, 10000));
    const long long order = args.GetInt("order");
    if (order != 0 && order != 2 && order != 3)
      throw UsageError("option --order: expected 2, 3 or 0 (both), got " + args.Get("order"));
    if (order != 0) o.orders = {static_cast<int>(order)};
    const auto joints = sp::EstimateFrequencyResponse(ReadAll(files), o);
    report::WriteFrequencyResponseReport(joints, out);
    for (const auto& j : joints)
      std::cout << "pwsim platform frequency-response: " << j.joint << " bandwidth "
                << j.bandwidth_rad_s << " rad/s\n";
    folder.Print(std::cout, "pwsim platform frequency-response");
    return 0;
  }
  throw UsageError("unknown sub-command '" + verb + "'" +
                   DidYouMean(verb, {"identify", "diagnose", "frequency-response", "describe"}) +
                   " (expected identify, diagnose, frequency-response or describe)");
}

}  // namespace pwsim::app
