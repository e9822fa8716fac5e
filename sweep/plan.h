#pragma once
// The plan of a sweep: DIR/manifest.json (one task per combination, in a fixed order, each with
// a deterministic id) and one folder per task, DIR/tasks/N/, holding the task's copies of the
// YAML inputs with its overrides applied (DIR/tasks/N/inputs/NAME.yaml). A task runs with its
// folder as working directory: `pwsim COMMAND... ARGUMENTS...` with {out} = "out".
//
// Order: list entries outermost (in file order), then the grid variables in file order with the
// last one varying fastest. Id: the first 12 hex digits of the 64-bit FNV-1a hash of the
// task's "key=value" lines (variables in manifest order), so a combination keeps its id when
// the sweep grows or is reordered.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "sweep/sweep_file.h"

namespace pwsim::sweep {

struct Task {
  std::size_t index{0};
  std::string id;
  std::vector<std::string> values;  ///< text of each variable's value, manifest.variables order
  std::vector<std::string> argv;    ///< the words after the pwsim executable
};

struct Manifest {
  std::filesystem::path dir;         ///< the sweep folder (absolute)
  std::string name;
  std::filesystem::path sweep_file;  ///< the sweep file it was planned from
  std::vector<std::string> command;
  std::vector<std::string> variables;  ///< the swept keys, list variables then grid variables
  std::vector<GatherField> gather;
  int retries{2};
  double timeout_s{0.0};
  SlurmSettings slurm;
  std::vector<Task> tasks;
};

/// 64-bit FNV-1a (offset basis 14695981039346656037, prime 1099511628211).
std::uint64_t Fnv1a64(const std::string& bytes);

/// DIR/tasks/N.
std::filesystem::path TaskDir(const std::filesystem::path& dir, std::size_t index);

/// Checks one task's copy of an input (DIR/tasks/N/inputs/NAME.yaml) as the swept command will
/// read it, throwing the InputError that command would throw (the CLI reads scenes, platform
/// and chair files with their own readers: a misspelt override key or a value of the wrong
/// kind is refused at plan time, not on the cluster).
using InputCheck = std::function<void(const std::filesystem::path& input_copy)>;

/// Plans `spec` into `dir`: writes the task folders, checks every task's inputs with `check`
/// (when given), then writes DIR/manifest.json last (a plan that stopped half way has no
/// manifest and no task folders). Refuses a `dir` that is not empty unless `force`, in which
/// case the previous plan and results there are removed first.
/// @throws InputError for an override that cannot be applied or that `check` refuses: the
/// sweep file's line and field of the variable (grid.KEY, list[i].KEY, set.KEY) whose value
/// the reader refused, else of the input, with the task's copy, line and field in the
/// expectation; std::runtime_error for I/O.
Manifest Plan(const SweepSpec& spec, const std::filesystem::path& dir, bool force,
              const InputCheck& check = {});

/// Reads DIR/manifest.json. @throws InputError naming the file and field when it is missing
/// or malformed.
Manifest ReadManifest(const std::filesystem::path& dir);

nlohmann::ordered_json ManifestJson(const Manifest& manifest);

}  // namespace pwsim::sweep
