#pragma once
// Axis recordings (shared/spec/platform-data.md, "An axis recording"): the joints of a motion
// platform measured by a lab, read from
//   - a YAML description `format: pwsim-axis-trial/1` naming a MATLAB `.mat` or a CSV file and
//     which variable/column holds each signal;
//   - a `.mat` file given directly, holding the EMPS names t, qm, qg, vir, gtau (one prismatic
//     joint named `axis`; kp, kv are read when present).
// MATLAB files are read with libmatio (v4, v5 compressed or not, v7.3/HDF5). CSV: a header row
// of column names, `#` lines are comments, one row per sample, numbers only.
// Every problem is an InputError naming the file, the variable/column (and line for CSV) and
// what was expected: a missing variable, a non-numeric or complex one, lengths that differ,
// time that is not uniform (|Δt − mean Δt| > 1 % of mean Δt) or not increasing, NaN or Inf
// samples, an unknown joint kind.
//
// pwsim accepts more than the contract (optional keys): `controller: {kp, kv, command_limit,
// delay_samples}` gives the EMPS-type position loop ν = kv·(kp·(q_r − q) − q̇_f) (each gain a
// {variable: NAME} or {value: X}); with a `.mat` given directly, kp and kv are read from it.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pwsim::sysid::platform {

enum class JointKind { kPrismatic, kRevolute };
const char* JointKindName(JointKind kind);  ///< "prismatic" | "revolute"

struct JointRecording {
  std::string name;
  JointKind kind{JointKind::kPrismatic};
  std::vector<double> position;   ///< [m] or [rad]
  std::vector<double> reference;  ///< [m] or [rad]; empty when not recorded
  std::vector<double> command;    ///< drive command (e.g. V)
  std::vector<double> effort;     ///< [N] or [N m] = command_to_effort · command
  double command_to_effort{1.0};  ///< [N/unit] (the mean when given per sample)
};

/// The EMPS-type position loop the recording was made under (when known):
/// ν_k = kv·(kp·(q_r,k − q_k) − (q_f,k − q_f,k−1)/T), q_f,k = ½(q_k + q_k−1), applied after
/// `delay_samples` samples, saturated to ±command_limit.
struct LoopGains {
  double kp{0.0};             ///< [1/s]
  double kv{0.0};             ///< [command/(m/s)] or [command/(rad/s)]
  double command_limit{10.0};  ///< [command units]
  int delay_samples{1};
};

struct AxisRecording {
  std::filesystem::path file;     ///< what was named on the command line
  std::string experiment{"excitation"};  ///< excitation | step | ramp | chirp
  std::vector<double> t;          ///< [s]
  double dt{0.0};                 ///< [s] mean sampling interval
  std::vector<JointRecording> joints;
  std::optional<LoopGains> loop;
  std::size_t size() const { return t.size(); }
  /// A copy holding samples [begin, end) only (time kept as recorded).
  AxisRecording Slice(std::size_t begin, std::size_t end) const;
};

/// Reads a recording: `.yaml`/`.yml` (the description), `.mat` (EMPS names). A `.csv` needs
/// its YAML description. @throws InputError.
AxisRecording ReadAxisRecording(const std::filesystem::path& file);

/// Writes `recording` as `stem.csv` + `stem.yaml` (pwsim-axis-trial/1, csv), both atomically;
/// columns t, <joint>_q, <joint>_qr (if any), <joint>_u, and the gain as a value.
void WriteAxisRecordingCsv(const AxisRecording& recording, const std::filesystem::path& yaml_file);

}  // namespace pwsim::sysid::platform
