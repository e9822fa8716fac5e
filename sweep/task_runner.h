#pragma once
// Runs one task of a planned sweep: `pwsim sweep run DIR [--index N]`.
//
// The task's command is the pwsim executable itself started as a child process in the task
// folder (DIR/tasks/N) with the task's words, so every pwsim command works without being
// linked here. Before it starts, the previous attempt's out/ and result.json are removed; its
// stdout and stderr go to DIR/tasks/N/attempt-K.log (K = 1, 2, ... claimed atomically). After
// it, the gathered fields are read from its JSON outputs and DIR/tasks/N/result.json is written
// atomically, whatever the outcome.
//
// Outcomes and the exit status of `pwsim sweep run`:
//   0  ok          the command succeeded and every field was gathered
//   65 bad input   the plan or the task is wrong, or the command refused its input (pwsim
//                  commands exit 1 on bad input or a deterministic failure, 2 on bad usage),
//                  or a gathered field is missing: running it again cannot help
//   75 retryable   the command was killed by a signal (node failure, out of memory, scancel),
//                  ran past timeout_s, could not be started, or ended with another status
// (65 and 75 are EX_DATAERR and EX_TEMPFAIL of sysexits.h.)

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "sweep/plan.h"

namespace pwsim::sweep {

enum class TaskStatus { kOk, kBadInput, kRetryable };

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 65;
constexpr int kExitRetryable = 75;

int ExitCodeFor(TaskStatus status);
const char* StatusName(TaskStatus status);  ///< "ok", "bad_input", "retryable"

struct TaskOutcome {
  TaskStatus status{TaskStatus::kRetryable};
  std::string reason;       ///< empty when ok
  int attempt{0};           ///< 1 for the first run of this task
  int exit_code{-1};        ///< the command's exit status (-1: did not exit normally)
  int signal{0};            ///< the signal that killed it (0: none)
  double command_s{0.0};    ///< wall time of the command
  nlohmann::ordered_json fields = nlohmann::ordered_json::object();
};

/// The task index from, in this order: `flag` (--index), SLURM_ARRAY_TASK_ID, OAR_ARRAY_INDEX
/// (1-based in OAR, hence minus 1); PWSIM_SWEEP_INDEX_OFFSET is added to an index from the
/// environment (large sweeps split into several arrays). `env` stands in for the environment.
/// @throws std::invalid_argument when none is set or a value is not a non-negative integer.
std::size_t TaskIndex(std::optional<long long> flag, const std::map<std::string, std::string>& env);
/// The variables TaskIndex reads, from the real environment.
std::map<std::string, std::string> IndexEnvironment();

/// Runs task `index` of `manifest` with `pwsim_exe` and writes its result.json.
/// @throws InputError when `index` is outside the plan.
TaskOutcome RunTask(const Manifest& manifest, std::size_t index, const std::filesystem::path& pwsim_exe);

/// Reads the value at `path` in `json` ("a.b.3.c": numbers index arrays); nullopt if absent.
std::optional<nlohmann::json> JsonAt(const nlohmann::json& json, const std::vector<std::string>& path);

/// Splits CSV text into rows of cells (RFC 4180: quoted cells may hold commas, "" is a quote).
std::vector<std::vector<std::string>> ParseCsv(const std::string& text);

/// The `field.column` cell of the first row of `csv` (header first) matching `field.row`.
/// Returns nullopt with `why` set when the column or no row matches.
std::optional<std::string> CsvAt(const std::vector<std::vector<std::string>>& csv, const GatherField& field,
                                 std::string& why);

/// Reads DIR/tasks/N/result.json; nullopt when absent or unreadable.
std::optional<nlohmann::json> ReadResult(const std::filesystem::path& dir, std::size_t index);

}  // namespace pwsim::sweep
