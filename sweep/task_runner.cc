#include "sweep/task_runner.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "engine/atomic_file.h"
#include "engine/input_error.h"
#include "sweep/process.h"

namespace pwsim::sweep {
namespace {

namespace fs = std::filesystem;

long long ParseIndex(const std::string& name, const std::string& text) {
  long long value = -1;
  std::size_t used = 0;
  try {
    value = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || value < 0) {
    throw std::invalid_argument(name + ": expected a non-negative integer, got \"" + text + "\"");
  }
  return value;
}

/// Claims the next attempt number by creating attempt-K.log exclusively.
int ClaimAttempt(const fs::path& task_dir, fs::path& log) {
  for (int attempt = 1; attempt < 100000; ++attempt) {
    log = task_dir / ("attempt-" + std::to_string(attempt) + ".log");
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd >= 0) {
      ::close(fd);
      return attempt;
    }
    if (errno != EEXIST) {
      throw std::runtime_error("cannot create " + log.string() + ": " + std::strerror(errno));
    }
  }
  throw std::runtime_error("too many attempts in " + task_dir.string());
}

std::string LastLine(const fs::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return last.size() > 300 ? last.substr(0, 300) + "..." : last;
}

std::string Join(const std::vector<std::string>& words) {
  std::string text;
  for (const auto& w : words) text += (text.empty() ? "" : " ") + w;
  return text;
}

}  // namespace

int ExitCodeFor(TaskStatus status) {
  switch (status) {
    case TaskStatus::kOk: return kExitOk;
    case TaskStatus::kBadInput: return kExitBadInput;
    case TaskStatus::kRetryable: return kExitRetryable;
  }
  return kExitRetryable;
}

const char* StatusName(TaskStatus status) {
  switch (status) {
    case TaskStatus::kOk: return "ok";
    case TaskStatus::kBadInput: return "bad_input";
    case TaskStatus::kRetryable: return "retryable";
  }
  return "retryable";
}

std::map<std::string, std::string> IndexEnvironment() {
  std::map<std::string, std::string> env;
  for (const char* name : {"SLURM_ARRAY_TASK_ID", "OAR_ARRAY_INDEX", "PWSIM_SWEEP_INDEX_OFFSET"}) {
    if (const char* value = std::getenv(name)) env[name] = value;
  }
  return env;
}

std::size_t TaskIndex(std::optional<long long> flag, const std::map<std::string, std::string>& env) {
  if (flag) {
    if (*flag < 0) throw std::invalid_argument("option --index: expected an integer >= 0");
    return static_cast<std::size_t>(*flag);
  }
  long long index = -1;
  if (env.count("SLURM_ARRAY_TASK_ID") > 0) {
    index = ParseIndex("SLURM_ARRAY_TASK_ID", env.at("SLURM_ARRAY_TASK_ID"));
  } else if (env.count("OAR_ARRAY_INDEX") > 0) {
    index = ParseIndex("OAR_ARRAY_INDEX", env.at("OAR_ARRAY_INDEX")) - 1;  // OAR counts from 1
    if (index < 0) throw std::invalid_argument("OAR_ARRAY_INDEX: expected an integer >= 1");
  } else {
    throw std::invalid_argument(
        "no task index: pass --index N or run inside a job array (SLURM_ARRAY_TASK_ID, OAR_ARRAY_INDEX)");
  }
  if (env.count("PWSIM_SWEEP_INDEX_OFFSET") > 0) {
    index += ParseIndex("PWSIM_SWEEP_INDEX_OFFSET", env.at("PWSIM_SWEEP_INDEX_OFFSET"));
  }
  return static_cast<std::size_t>(index);
}

std::optional<nlohmann::json> JsonAt(const nlohmann::json& json, const std::vector<std::string>& path) {
  const nlohmann::json* node = &json;
  for (const std::string& part : path) {
    if (node->is_object()) {
      const auto it = node->find(part);
      if (it == node->end()) return std::nullopt;
      node = &*it;
    } else if (node->is_array()) {
      std::size_t used = 0;
      std::size_t index = 0;
      try {
        index = std::stoul(part, &used);
      } catch (const std::exception&) {
        return std::nullopt;
      }
      if (used != part.size() || index >= node->size()) return std::nullopt;
      node = &(*node)[index];
    } else {
      return std::nullopt;
    }
  }
  return *node;
}

std::vector<std::vector<std::string>> ParseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string cell;
  bool quoted = false, any = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c == '"') {
      quoted = true;
      any = true;
    } else if (c == ',') {
      row.push_back(cell);
      cell.clear();
      any = true;
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      if (any || !cell.empty()) {
        row.push_back(cell);
        rows.push_back(row);
      }
      row.clear();
      cell.clear();
      any = false;
    } else {
      cell += c;
      any = true;
    }
  }
  if (any || !cell.empty()) {
    row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

namespace {
bool SameCell(const std::string& cell, const std::string& wanted) {
  if (cell == wanted) return true;
  std::size_t used_a = 0, used_b = 0;
  double a = 0.0, b = 0.0;
  try {
    a = std::stod(cell, &used_a);
    b = std::stod(wanted, &used_b);
  } catch (const std::exception&) {
    return false;
  }
  if (used_a != cell.size() || used_b != wanted.size()) return false;
  return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
}
}  // namespace

std::optional<std::string> CsvAt(const std::vector<std::vector<std::string>>& csv, const GatherField& field,
                                 std::string& why) {
  if (csv.empty()) {
    why = field.file + " is empty";
    return std::nullopt;
  }
  const std::vector<std::string>& header = csv.front();
  auto column_of = [&](const std::string& name) -> std::optional<std::size_t> {
    for (std::size_t c = 0; c < header.size(); ++c) {
      if (header[c] == name) return c;
    }
    return std::nullopt;
  };
  const auto target = column_of(field.column);
  if (!target) {
    why = field.file + " has no column '" + field.column + "'";
    return std::nullopt;
  }
  std::vector<std::size_t> keys;
  for (const auto& [key, value] : field.row) {
    const auto c = column_of(key);
    if (!c) {
      why = field.file + " has no column '" + key + "'";
      return std::nullopt;
    }
    keys.push_back(*c);
  }
  for (std::size_t r = 1; r < csv.size(); ++r) {
    bool match = csv[r].size() > *target;
    for (std::size_t k = 0; match && k < keys.size(); ++k) {
      match = csv[r].size() > keys[k] && SameCell(csv[r][keys[k]], field.row[k].second);
    }
    if (match) return csv[r][*target];
  }
  why = field.file + " has no row where";
  for (const auto& [key, value] : field.row) why += " " + key + " = " + value;
  return std::nullopt;
}

std::optional<nlohmann::json> ReadResult(const fs::path& dir, std::size_t index) {
  std::ifstream in(TaskDir(dir, index) / "result.json");
  if (!in) return std::nullopt;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

TaskOutcome RunTask(const Manifest& manifest, std::size_t index, const fs::path& pwsim_exe) {
  if (index >= manifest.tasks.size()) {
    throw InputError((manifest.dir / "manifest.json").string(), 0, "tasks",
                     "a task index below " + std::to_string(manifest.tasks.size()),
                     std::to_string(index));
  }
  const Task& task = manifest.tasks[index];
  const fs::path task_dir = TaskDir(manifest.dir, index);
  const fs::path result_file = task_dir / "result.json";
  // outputs of an earlier attempt go first, so nothing stale is gathered
  fs::remove(result_file);
  fs::remove_all(task_dir / "out");
  fs::create_directories(task_dir);

  TaskOutcome outcome;
  fs::path log;
  outcome.attempt = ClaimAttempt(task_dir, log);
  std::vector<std::string> argv{pwsim_exe.string()};
  argv.insert(argv.end(), task.argv.begin(), task.argv.end());
  {
    std::ofstream header(log, std::ios::app);
    header << "# pwsim sweep " << manifest.name << ", task " << index << " (" << task.id
           << "), attempt " << outcome.attempt << ", in " << task_dir.string() << "\n# "
           << Join(argv) << "\n";
  }

  SpawnOptions options;
  options.cwd = task_dir;
  options.output = log;
  std::string spawn_error;
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = Spawn(argv, options, spawn_error);
  ChildExit exit;
  if (pid < 0) {
    exit.started = false;
    exit.error = spawn_error;
  } else {
    exit = WaitChild(pid, manifest.timeout_s);
  }
  outcome.command_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  outcome.exit_code = exit.exited ? exit.code : -1;
  outcome.signal = exit.signal;

  if (!exit.started) {
    outcome.status = TaskStatus::kRetryable;
    outcome.reason = "could not start the command: " + exit.error;
  } else if (exit.timed_out) {
    outcome.status = TaskStatus::kRetryable;
    outcome.reason = "killed after timeout_s = " + std::to_string(manifest.timeout_s) + " s";
  } else if (!exit.exited) {
    outcome.status = TaskStatus::kRetryable;
    outcome.reason = std::string("killed by signal ") + std::to_string(exit.signal) + " (" +
                     ::strsignal(exit.signal) + ")";
  } else if (exit.code == 1 || exit.code == 2) {
    outcome.status = TaskStatus::kBadInput;
    outcome.reason = "the command exited with status " + std::to_string(exit.code) + ": " + LastLine(log);
  } else if (exit.code != 0) {
    outcome.status = TaskStatus::kRetryable;
    outcome.reason = "the command exited with status " + std::to_string(exit.code) + ": " + LastLine(log);
  } else {
    outcome.status = TaskStatus::kOk;
    std::map<std::string, nlohmann::json> documents;
    for (const GatherField& gather : manifest.gather) {
      if (gather.csv()) {
        std::ifstream in(task_dir / "out" / gather.file);
        std::string why = "out/" + gather.file + " is missing";
        std::optional<std::string> cell;
        if (in) {
          std::stringstream text;
          text << in.rdbuf();
          cell = CsvAt(ParseCsv(text.str()), gather, why);
        }
        if (!cell) {
          outcome.status = TaskStatus::kBadInput;
          outcome.reason = "gather." + gather.name + ": " + why;
          break;
        }
        double number = 0.0;
        std::size_t used = 0;
        try {
          number = std::stod(*cell, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used == cell->size() && !cell->empty()) {
          outcome.fields[gather.name] = number;
        } else {
          outcome.fields[gather.name] = *cell;
        }
        continue;
      }
      if (documents.count(gather.file) == 0) {
        std::ifstream in(task_dir / "out" / gather.file);
        nlohmann::json document;
        if (in) {
          try {
            document = nlohmann::json::parse(in);
          } catch (const nlohmann::json::exception&) {
            document = nullptr;
          }
        }
        documents[gather.file] = document;
      }
      const std::optional<nlohmann::json> value = JsonAt(documents[gather.file], gather.path);
      std::string path;
      for (const auto& part : gather.path) path += (path.empty() ? "" : ".") + part;
      if (!value) {
        outcome.status = TaskStatus::kBadInput;
        outcome.reason = "gather." + gather.name + ": out/" + gather.file +
                         (documents[gather.file].is_null() ? " is missing or not JSON"
                                                           : " has no '" + path + "'");
        break;
      }
      outcome.fields[gather.name] = *value;
    }
  }

  nlohmann::ordered_json result;
  result["format"] = "pwsim-sweep-result/1";
  result["index"] = index;
  result["id"] = task.id;
  result["status"] = StatusName(outcome.status);
  result["reason"] = outcome.reason;
  result["attempt"] = outcome.attempt;
  result["exit_code"] = outcome.exit_code;
  result["signal"] = outcome.signal;
  result["command_s"] = outcome.command_s;
  char host[256] = {};
  ::gethostname(host, sizeof(host) - 1);
  result["host"] = host;
  if (const char* job = std::getenv("SLURM_JOB_ID")) result["slurm_job_id"] = job;
  result["fields"] = outcome.fields;
  WriteFileAtomically(result_file, result.dump(1) + "\n");
  return outcome;
}

}  // namespace pwsim::sweep
