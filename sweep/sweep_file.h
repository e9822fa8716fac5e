#pragma once
// The sweep file (`format: pwsim-sweep/1`): one pwsim command run over a grid or list of
// variations, and the result fields to gather from each run. Read and validated completely
// before anything is planned or submitted; a mistake is an InputError naming the sweep file,
// the line, the field and what was expected.
//
//   format: pwsim-sweep/1
//   name: speed_sweep
//   command: [run]                         # pwsim words (checked against the CLI's commands)
//   inputs: {scene: ../speed_cushion.yaml} # YAML files copied into every task folder
//   arguments: ["{scene}", --no-video, --out, "{out}"]
//   set: {scene.drive.stop_x_m: 6}         # fixed overrides, every task
//   grid: {scene.drive.speed_mps: [0.4, 0.8, 1.2]}   # every combination (last key fastest)
//   list: [{seed: 1}, {seed: 2}]           # explicit combinations (crossed with the grid)
//   gather: {peak_heave_m: {file: summary.json, path: peak_heave.excursion_m},
//            heave_gain_1: {file: omct.csv, row: {test: fz_to_fz, frequency: 1}, column: gain}}
//   retries: 2                             # resubmissions of a retryable failure
//   timeout_s: 3600                        # a task running longer is killed (retryable)
//   slurm: {partition: short, account: lab, time: "00:20:00", mem: 2G, cpus_per_task: 1}
//
// A variation key is either dotted, `INPUT.path.in.that.file` (the first word names one of
// `inputs`, the rest a key path inside it; list items by number, `occupant.head_offset_m.2`),
// or a bare placeholder name used as `{name}` in `arguments` or in a string value of `set`.
// Placeholders always available: {out} (the task's output folder), {index}, {id}, and every
// input name (the task's copy of that input). Values: a list, or {from: A, to: B, step: S} of
// integers (seeds), or {glob: "../trials/*"} (paths matching the pattern, sorted).
// Relative paths (a word or value that contains '/' and names an existing file or folder) are
// relative to the file they are written in and are made absolute in the plan.

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace pwsim::sweep {

/// One value of a variable: its YAML node (scalar, list or mapping) and its text form.
struct Value {
  YAML::Node node;
  std::string text;  ///< scalar text, or the flow-style YAML of a list or mapping
  int line{0};       ///< line in the sweep file where it was written
};

/// A swept variable: a dotted override of an input, or a placeholder.
struct Variable {
  std::string key;    ///< as written: "scene.drive.speed_mps" or "seed"
  std::string input;  ///< the input it overrides ("scene"); empty for a placeholder
  std::vector<std::string> path;  ///< key path inside the input (override only)
  int line{0};
};

/// A fixed override applied to every task (the `set:` section).
struct Override {
  Variable target;
  Value value;
};

/// One result field: the value at a dotted `path` of a JSON file in the task's output folder,
/// or (file *.csv) the `column` of the first row of a CSV file whose cells match `row` (a number
/// matches a number of the same value: frequency 1 matches "1.0").
struct GatherField {
  std::string name;  ///< the results.csv column
  std::string file;  ///< relative to the task's output folder, e.g. "summary.json"
  std::vector<std::string> path;  ///< JSON: e.g. {"peak_heave", "excursion_m"}; numbers index arrays
  std::string column;             ///< CSV: the column to read
  std::vector<std::pair<std::string, std::string>> row;  ///< CSV: column = value to match
  int line{0};
  bool csv() const { return !column.empty(); }
};

/// Batch-script settings for Slurm (every field optional; empty = the cluster's default).
struct SlurmSettings {
  std::string partition;
  std::string account;
  std::string qos;
  std::string time;  ///< wall-time limit per task, Slurm syntax ("00:20:00", "2-00:00:00")
  std::string mem;   ///< memory per task, Slurm syntax ("2G")
  int cpus_per_task{1};
  std::vector<std::string> extra;  ///< more sbatch options, each one word ("--qos=normal")
};

struct SweepSpec {
  std::filesystem::path file;  ///< the sweep file (absolute)
  std::string name;
  std::string description;
  std::vector<std::string> command;  ///< pwsim words, e.g. {"run"} or {"platform", "identify"}
  std::map<std::string, std::filesystem::path> inputs;  ///< name -> original file (absolute)
  std::map<std::string, int> input_lines;  ///< name -> its line in the sweep file
  std::vector<std::string> arguments;  ///< after the command words; may hold {placeholders}
  std::vector<int> argument_lines;     ///< each argument's line in the sweep file
  std::vector<Override> set;
  std::vector<Variable> grid_variables;           ///< in file order
  std::vector<std::vector<Value>> grid_values;    ///< per grid variable
  std::vector<Variable> list_variables;           ///< union of the keys of the list entries
  std::vector<std::vector<Value>> list_rows;      ///< per entry, per list variable
  std::vector<GatherField> gather;
  int retries{2};
  double timeout_s{0.0};  ///< 0 = no limit
  SlurmSettings slurm;

  /// Every variable, list variables first then grid variables (the manifest's column order).
  std::vector<Variable> Variables() const;
  /// Number of tasks: (list entries, or 1) x product of the grid sizes.
  std::size_t TaskCount() const;
};

/// Placeholders every task defines besides its variables and inputs.
const std::vector<std::string>& BuiltinPlaceholders();

/// Reads and validates a sweep file. `known_commands` are the first words the pwsim CLI
/// accepts (the command must start with one of them; "sweep" itself is refused).
/// @throws InputError for anything wrong, naming the file, line and field.
SweepSpec ReadSweepFile(const std::filesystem::path& file,
                        const std::vector<std::string>& known_commands);

/// Replaces every {name} in `text` by `values.at(name)`; "{{" stands for a literal "{".
/// @throws std::out_of_range naming the placeholder when it is not in `values`.
std::string Substitute(const std::string& text, const std::map<std::string, std::string>& values);
/// The placeholder names used in `text`, in order.
std::vector<std::string> PlaceholdersIn(const std::string& text);

}  // namespace pwsim::sweep
