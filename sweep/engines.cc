#include "sweep/engines.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <map>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "engine/atomic_file.h"
#include "sweep/process.h"
#include "sweep/task_runner.h"

namespace pwsim::sweep {
namespace {

namespace fs = std::filesystem;

std::vector<std::size_t> NotDone(const Manifest& manifest) {
  std::vector<std::size_t> pending;
  for (const Task& task : manifest.tasks) {
    if (ResultStatus(manifest.dir, task.index) != "ok") pending.push_back(task.index);
  }
  return pending;
}

void Log(const EngineOptions& options, const std::string& line) {
  if (options.log != nullptr) *options.log << line << "\n" << std::flush;
}

std::string Trim(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ' || text.back() == '\r')) text.pop_back();
  return text;
}

std::string Command(const std::vector<std::string>& argv) {
  std::string text;
  for (const auto& word : argv) text += (text.empty() ? "" : " ") + word;
  return text;
}

}  // namespace

std::string ResultStatus(const fs::path& dir, std::size_t index) {
  const std::optional<nlohmann::json> result = ReadResult(dir, index);
  if (!result || !result->contains("status") || !(*result)["status"].is_string()) return "retryable";
  const std::string status = (*result)["status"].get<std::string>();
  return status == "ok" || status == "bad_input" ? status : "retryable";
}

std::string ArrayList(const std::vector<std::size_t>& indices_in) {
  std::vector<std::size_t> indices = indices_in;
  std::sort(indices.begin(), indices.end());
  std::string text;
  for (std::size_t i = 0; i < indices.size();) {
    std::size_t j = i;
    while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
    if (!text.empty()) text += ",";
    text += std::to_string(indices[i]);
    if (j > i) text += "-" + std::to_string(indices[j]);
    i = j + 1;
  }
  return text;
}

SubmitReport SubmitLocal(const Manifest& manifest, const EngineOptions& options) {
  SubmitReport report;
  const int retries = options.retries >= 0 ? options.retries : manifest.retries;
  int parallel = options.max_parallel;
  if (parallel <= 0) parallel = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  const fs::path logs = manifest.dir / "local";
  fs::create_directories(logs);

  std::deque<std::size_t> queue;
  for (std::size_t index : NotDone(manifest)) queue.push_back(index);
  for (const Task& task : manifest.tasks) {
    if (std::find(queue.begin(), queue.end(), task.index) == queue.end()) report.ok.push_back(task.index);
  }
  Log(options, "local: " + std::to_string(queue.size()) + " of " + std::to_string(manifest.tasks.size()) +
                   " tasks to run, at most " + std::to_string(parallel) + " at a time");
  std::map<pid_t, std::size_t> running;
  std::map<std::size_t, int> runs;
  const int to_run = static_cast<int>(queue.size());
  int finished = 0;
  const auto told = [&] {
    if (options.progress) options.progress("run the tasks", finished, to_run);
  };
  told();
  while (!queue.empty() || !running.empty()) {
    while (!queue.empty() && static_cast<int>(running.size()) < parallel) {
      const std::size_t index = queue.front();
      queue.pop_front();
      SpawnOptions spawn;
      spawn.output = logs / (std::to_string(index) + ".out");
      std::string error;
      const pid_t pid = Spawn({options.pwsim_exe.string(), "sweep", "run", manifest.dir.string(),
                               "--index", std::to_string(index)},
                              spawn, error);
      ++runs[index];
      ++report.rounds;
      if (pid < 0) throw std::runtime_error("local: cannot start task " + std::to_string(index) + ": " + error);
      running[pid] = index;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);  // blocks until a task ends
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("local: waitpid: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;  // not one of ours
    const std::size_t index = it->second;
    running.erase(it);
    const ChildExit exit = DecodeStatus(status);
    const std::string result = ResultStatus(manifest.dir, index);
    std::string how = exit.exited ? "exit " + std::to_string(exit.code) : "signal " + std::to_string(exit.signal);
    if (exit.exited && exit.code == kExitOk && result == "ok") {
      report.ok.push_back(index);
      Log(options, "local: task " + std::to_string(index) + " ok");
      ++finished;
    } else if (exit.exited && (exit.code == kExitBadInput || exit.code == 2) ) {
      report.bad_input.push_back(index);
      Log(options, "local: task " + std::to_string(index) + " bad input (" + how + "), not retried; see " +
                       (TaskDir(manifest.dir, index) / "result.json").string());
      ++finished;
    } else if (runs[index] <= retries) {
      queue.push_back(index);
      Log(options, "local: task " + std::to_string(index) + " failed (" + how + "), resubmitted (" +
                       std::to_string(runs[index]) + " of " + std::to_string(retries) + " retries)");
    } else {
      report.failed.push_back(index);
      Log(options, "local: task " + std::to_string(index) + " failed (" + how + ") after " +
                       std::to_string(retries) + " retries");
      ++finished;
    }
    told();
  }
  std::sort(report.ok.begin(), report.ok.end());
  return report;
}

std::string SlurmBatchScript(const Manifest& manifest, const fs::path& pwsim_exe) {
  const SlurmSettings& s = manifest.slurm;
  std::ostringstream script;
  script << "#!/bin/bash\n"
         << "# pwsim sweep '" << manifest.name << "': one array task = one sweep task, N from\n"
         << "# SLURM_ARRAY_TASK_ID (+ PWSIM_SWEEP_INDEX_OFFSET for sweeps split into several arrays).\n"
         << "# Submitted by 'pwsim sweep submit DIR --engine slurm' as: sbatch --array=LIST%K this-file\n"
         << "#SBATCH --job-name=pwsim-" << manifest.name << "\n"
         << "#SBATCH --output=" << (manifest.dir / "slurm" / "logs" / "%A_%a.out").string() << "\n"
         << "#SBATCH --ntasks=1\n"
         << "#SBATCH --cpus-per-task=" << s.cpus_per_task << "\n";
  if (!s.partition.empty()) script << "#SBATCH --partition=" << s.partition << "\n";
  if (!s.account.empty()) script << "#SBATCH --account=" << s.account << "\n";
  if (!s.qos.empty()) script << "#SBATCH --qos=" << s.qos << "\n";
  if (!s.time.empty()) script << "#SBATCH --time=" << s.time << "\n";
  if (!s.mem.empty()) script << "#SBATCH --mem=" << s.mem << "\n";
  for (const std::string& extra : s.extra) script << "#SBATCH " << extra << "\n";
  script << "# exit status: 0 ok, 65 bad input (not retried), 75 retryable\n"
         << "exec " << ShellQuote(pwsim_exe.string()) << " sweep run " << ShellQuote(manifest.dir.string())
         << "\n";
  return script.str();
}

namespace {

std::size_t MaxArraySize(const EngineOptions& options) {
  if (options.max_array_size > 0) return options.max_array_size;
  const Captured config = RunCapture({"scontrol", "show", "config"});
  std::istringstream lines(config.out);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("MaxArraySize", 0) != 0) continue;
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) break;
    try {
      return std::stoul(line.substr(eq + 1));
    } catch (const std::exception&) {
      break;
    }
  }
  return 1001;  // Slurm's default
}

/// Submits `indices` as job arrays (split where an index reaches MaxArraySize); returns job ids.
std::vector<std::string> SubmitArrays(const Manifest& manifest, const EngineOptions& options,
                                      const fs::path& script, const std::vector<std::size_t>& indices,
                                      std::size_t max_array) {
  std::map<std::size_t, std::vector<std::size_t>> chunks;  // offset -> array indices
  for (std::size_t index : indices) {
    const std::size_t offset = index / max_array * max_array;
    chunks[offset].push_back(index - offset);
  }
  std::vector<std::string> ids;
  for (const auto& [offset, local] : chunks) {
    std::string array = ArrayList(local);
    if (options.max_parallel > 0) array += "%" + std::to_string(options.max_parallel);
    // the offset travels in sbatch's own environment (exported by default): an --export list
    // other than ALL would make slurmd load a login environment for every task (seconds each)
    std::vector<std::string> argv{"sbatch", "--parsable", "--array=" + array};
    argv.insert(argv.end(), options.sbatch_options.begin(), options.sbatch_options.end());
    argv.push_back(script.string());
    const Captured sbatch = RunCapture(argv, {"PWSIM_SWEEP_INDEX_OFFSET=" + std::to_string(offset)});
    if (!sbatch.exit.started || !sbatch.exit.exited || sbatch.exit.code != 0) {
      throw std::runtime_error("slurm: '" + Command(argv) + "' failed: " +
                               Trim(sbatch.exit.started ? sbatch.err : sbatch.exit.error));
    }
    std::string id = Trim(sbatch.out);
    id = id.substr(0, id.find(';'));  // "JOBID;CLUSTER" on federated clusters
    ids.push_back(id);
    std::ofstream(manifest.dir / "slurm" / "jobs.txt", std::ios::app)
        << id << " offset=" << offset << " array=" << array << "\n";
    Log(options, "slurm: submitted job array " + id + " (--array=" + array +
                     (offset > 0 ? ", offset " + std::to_string(offset) : "") + ")");
  }
  return ids;
}

/// Polls squeue until none of `ids` is pending or running.
/// Polls until the arrays `ids` have left the queue; `each_poll` (when given) runs after every
/// query of the queue.
void WaitForArrays(const EngineOptions& options, const std::vector<std::string>& ids,
                   const std::function<void()>& each_poll = {}) {
  std::string list;
  for (const auto& id : ids) list += (list.empty() ? "" : ",") + id;
  const auto interval = std::chrono::duration<double>(std::max(0.01, options.poll_s));
  int failures = 0;  // consecutive: a busy controller times out now and then
  for (;;) {
    const Captured squeue = RunCapture({"squeue", "--noheader", "--jobs=" + list, "--format=%i %T"});
    if (!squeue.exit.started) throw std::runtime_error("slurm: squeue: " + squeue.exit.error);
    if (each_poll) each_poll();
    if (squeue.exit.exited && squeue.exit.code == 0) {
      failures = 0;
      if (Trim(squeue.out).empty()) return;
    } else if (squeue.err.find("Invalid job id") != std::string::npos) {
      return;  // the jobs have left the controller's memory (MinJobAge): they are finished
    } else if (++failures >= 30) {
      throw std::runtime_error("slurm: squeue failed " + std::to_string(failures) +
                               " times in a row: " + Trim(squeue.err) + " (the arrays " + list +
                               " may still run: 'pwsim sweep collect' when they are done)");
    } else {
      Log(options, "slurm: squeue failed (" + Trim(squeue.err) + "), trying again");
    }
    std::this_thread::sleep_for(interval);  // polling the queue is the only way to learn of it
  }
}

/// Final states from sacct, "ID_N STATE EXIT" lines; empty when accounting is off.
std::string FinalStates(const std::vector<std::string>& ids) {
  std::string list;
  for (const auto& id : ids) list += (list.empty() ? "" : ",") + id;
  const Captured sacct = RunCapture({"sacct", "--noheader", "--parsable2", "--allocations",
                                     "--jobs=" + list, "--format=JobID,State,ExitCode"});
  if (!sacct.exit.exited || sacct.exit.code != 0) return "";
  return sacct.out;
}

}  // namespace

SubmitReport SubmitSlurm(const Manifest& manifest, const EngineOptions& options) {
  SubmitReport report;
  const int retries = options.retries >= 0 ? options.retries : manifest.retries;
  const fs::path slurm_dir = manifest.dir / "slurm";
  fs::create_directories(slurm_dir / "logs");
  const fs::path script = slurm_dir / "sweep.sbatch";
  WriteFileAtomically(script, SlurmBatchScript(manifest, options.pwsim_exe));
  fs::permissions(script, fs::perms::owner_exec, fs::perm_options::add);

  std::vector<std::size_t> pending = NotDone(manifest);
  for (const Task& task : manifest.tasks) {
    if (std::find(pending.begin(), pending.end(), task.index) == pending.end()) report.ok.push_back(task.index);
  }
  if (pending.empty()) return report;
  const std::size_t max_array = MaxArraySize(options);
  // progress: the tasks to run that ended for good (a result ok or bad input; failed after the
  // retries once the last round is read)
  const std::vector<std::size_t> to_run = pending;
  const auto told = [&] {
    if (!options.progress) return;
    int ended = static_cast<int>(report.failed.size());
    for (std::size_t index : to_run) ended += ResultStatus(manifest.dir, index) != "retryable" ? 1 : 0;
    options.progress("run the tasks", ended, static_cast<int>(to_run.size()));
  };
  told();
  for (int round = 0; !pending.empty(); ++round) {
    const std::vector<std::string> ids = SubmitArrays(manifest, options, script, pending, max_array);
    report.job_ids.insert(report.job_ids.end(), ids.begin(), ids.end());
    ++report.rounds;
    WaitForArrays(options, ids, told);
    const std::string states = FinalStates(ids);
    if (!states.empty()) {
      std::ofstream(slurm_dir / "states.txt", std::ios::app) << states;
      Log(options, "slurm: sacct:\n" + Trim(states));
    }
    std::vector<std::size_t> again;
    for (std::size_t index : pending) {
      const std::string status = ResultStatus(manifest.dir, index);
      if (status == "ok") {
        report.ok.push_back(index);
      } else if (status == "bad_input") {
        report.bad_input.push_back(index);
      } else if (round < retries) {
        again.push_back(index);
      } else {
        report.failed.push_back(index);
      }
    }
    if (!again.empty()) {
      Log(options, "slurm: tasks " + ArrayList(again) + " failed (no ok result), resubmitting (retry " +
                       std::to_string(round + 1) + " of " + std::to_string(retries) + ")");
    }
    pending = again;
    told();
  }
  std::sort(report.ok.begin(), report.ok.end());
  return report;
}

}  // namespace pwsim::sweep
