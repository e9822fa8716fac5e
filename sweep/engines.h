#pragma once
// Engines that run the tasks of a planned sweep, each task as `pwsim sweep run DIR --index N`
// (the same contract everywhere), resubmitting a retryable failure a bounded number of times.
// Tasks whose result.json already says "ok" are not run again, so a submit resumes a sweep.
//
// local: a process pool on this machine; at most K tasks at a time; waits on child exit.
// slurm: writes DIR/slurm/sweep.sbatch and submits it with `sbatch --array=LIST%K`; polls
//        `squeue` until the array has left the queue, reads the final states with `sacct`
//        (when the cluster keeps accounting), and resubmits the retryable tasks as a new array.

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "sweep/plan.h"

namespace pwsim::sweep {

struct EngineOptions {
  std::filesystem::path pwsim_exe;  ///< the executable the tasks run (absolute)
  int max_parallel{0};              ///< K: tasks at a time; 0 = local: cores, slurm: no limit
  int retries{-1};                  ///< resubmissions per task; -1 = the sweep file's
  double poll_s{10.0};              ///< slurm: time between squeue queries
  std::size_t max_array_size{0};    ///< slurm: 0 = read MaxArraySize from `scontrol show config`
  std::vector<std::string> sbatch_options;  ///< slurm: more sbatch words for this submission
  std::ostream* log{nullptr};       ///< progress lines (may be null)
  /// Told ("run the tasks", tasks finished, tasks to run) at the start and as tasks end for good
  /// (ok, bad input, or failed after their retries): local as each ends, slurm at each poll of
  /// the queue; none: not told.
  std::function<void(std::string_view stage, int done, int total)> progress;
};

struct SubmitReport {
  std::vector<std::size_t> ok;         ///< done (now or before)
  std::vector<std::size_t> bad_input;  ///< refused: not retried
  std::vector<std::size_t> failed;     ///< still failing after the retries
  int rounds{0};                       ///< slurm: arrays submitted; local: task launches
  std::vector<std::string> job_ids;    ///< slurm: the array job ids
  bool complete() const { return bad_input.empty() && failed.empty(); }
};

SubmitReport SubmitLocal(const Manifest& manifest, const EngineOptions& options);
SubmitReport SubmitSlurm(const Manifest& manifest, const EngineOptions& options);

/// The Slurm batch script of `manifest` (what DIR/slurm/sweep.sbatch holds).
std::string SlurmBatchScript(const Manifest& manifest, const std::filesystem::path& pwsim_exe);

/// "0-3,7,9-10": the compact --array list of sorted indices.
std::string ArrayList(const std::vector<std::size_t>& indices);

/// The retry decision of an engine after a run of task `index`: reads its result.json.
/// Returns "ok", "bad_input" or "retryable" (missing or unreadable result: retryable).
std::string ResultStatus(const std::filesystem::path& dir, std::size_t index);

}  // namespace pwsim::sweep
