#include "sweep/collect.h"

#include <cmath>
#include <limits>

#include "engine/number_format.h"
#include "sweep/task_runner.h"

namespace pwsim::sweep {
namespace {

namespace fs = std::filesystem;

int CountAttempts(const fs::path& task_dir) {
  int count = 0;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(task_dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("attempt-", 0) == 0 && entry.path().extension() == ".log") ++count;
  }
  return count;
}

}  // namespace

std::string CsvCell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

Collection Collect(const Manifest& manifest) {
  Collection collection;
  collection.variables = manifest.variables;
  for (const GatherField& g : manifest.gather) collection.field_names.push_back(g.name);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Task& task : manifest.tasks) {
    ResultRow row;
    row.index = task.index;
    row.id = task.id;
    row.values = task.values;
    row.attempts = CountAttempts(TaskDir(manifest.dir, task.index));
    row.fields.assign(manifest.gather.size(), "");
    row.numbers.assign(manifest.gather.size(), nan);
    const std::optional<nlohmann::json> result = ReadResult(manifest.dir, task.index);
    if (!result) {
      row.status = "missing";
      row.reason = row.attempts == 0 ? "never run" : "no result after " + std::to_string(row.attempts) +
                                                          " attempt(s) (killed, or still running)";
      collection.missing.push_back(task.index);
    } else {
      row.status = result->value("status", "retryable");
      row.reason = result->value("reason", "");
      if (row.status != "ok") collection.failed.push_back(task.index);
      const nlohmann::json fields = result->value("fields", nlohmann::json::object());
      for (std::size_t f = 0; f < manifest.gather.size(); ++f) {
        const auto it = fields.find(manifest.gather[f].name);
        if (it == fields.end()) continue;
        if (it->is_number()) {
          row.numbers[f] = it->get<double>();
          row.fields[f] = FormatDouble(row.numbers[f]);
        } else if (it->is_string()) {
          row.fields[f] = it->get<std::string>();
        } else {
          row.fields[f] = it->dump();
        }
      }
    }
    collection.rows.push_back(row);
  }
  return collection;
}

std::string ResultsCsv(const Collection& collection) {
  std::string csv = "index,id,status,attempts";
  for (const auto& v : collection.variables) csv += "," + CsvCell(v);
  for (const auto& f : collection.field_names) csv += "," + CsvCell(f);
  csv += "\n";
  for (const ResultRow& row : collection.rows) {
    csv += std::to_string(row.index) + "," + row.id + "," + row.status + "," + std::to_string(row.attempts);
    for (const auto& v : row.values) csv += "," + CsvCell(v);
    for (const auto& f : row.fields) csv += "," + CsvCell(f);
    csv += "\n";
  }
  return csv;
}

std::string MissingReport(const Collection& collection) {
  std::string text;
  for (const ResultRow& row : collection.rows) {
    if (row.status == "ok") continue;
    text += "task " + std::to_string(row.index) + " (" + row.id + "): " + row.status + ": " + row.reason + "\n";
  }
  return text;
}

}  // namespace pwsim::sweep
