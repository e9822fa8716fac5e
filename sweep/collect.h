#pragma once
// Gathers the results of a sweep: one row per task with its variables, its status and the
// gathered fields (read from each task's result.json), and the tasks still missing or failed.

#include <filesystem>
#include <string>
#include <vector>

#include "sweep/plan.h"

namespace pwsim::sweep {

struct ResultRow {
  std::size_t index{0};
  std::string id;
  std::string status;  ///< ok, bad_input, retryable (failed) or missing (no result.json)
  int attempts{0};     ///< attempt-K.log files in the task folder
  std::string reason;
  std::vector<std::string> values;  ///< per variable
  std::vector<std::string> fields;  ///< per gathered field, "" when absent
  std::vector<double> numbers;      ///< per gathered field, NaN unless a number
};

struct Collection {
  std::vector<std::string> variables;
  std::vector<std::string> field_names;
  std::vector<ResultRow> rows;
  std::vector<std::size_t> missing;  ///< no result.json
  std::vector<std::size_t> failed;   ///< a result.json that is not ok
  bool complete() const { return missing.empty() && failed.empty(); }
};

Collection Collect(const Manifest& manifest);

/// results.csv: index,id,status,attempts,<variables>,<fields> (RFC 4180 quoting).
std::string ResultsCsv(const Collection& collection);

/// The text of missing.txt: one line per missing or failed task with its reason.
std::string MissingReport(const Collection& collection);

/// A value as a CSV cell (quoted when it holds a comma, quote or newline).
std::string CsvCell(const std::string& text);

}  // namespace pwsim::sweep
