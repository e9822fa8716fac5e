#include "engine/numeric_csv.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "engine/input_error.h"

namespace pwsim {
namespace {

std::vector<std::string> SplitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' ')) cell.pop_back();
    while (!cell.empty() && cell.front() == ' ') cell.erase(cell.begin());
    cells.push_back(cell);
  }
  return cells;
}

}  // namespace

NumericCsv ReadNumericCsv(const std::filesystem::path& file, const std::vector<std::string>& wanted,
                          const CsvCellRule& rule) {
  RequireReadableFile(file, "a readable CSV file");
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), 0, "(file)", "a readable CSV file", "cannot open");
  std::string line;
  std::string names;
  for (std::size_t k = 0; k < wanted.size(); ++k) names += (k ? ", " : "") + wanted[k];
  if (!std::getline(in, line)) throw InputError(file.string(), 1, "header", "a header row " + names, "an empty file");
  const std::vector<std::string> header = SplitCells(line);
  std::vector<std::size_t> column(wanted.size(), header.size());
  for (std::size_t i = 0; i < header.size(); ++i) {
    const auto found = std::find(wanted.begin(), wanted.end(), header[i]);
    if (found == wanted.end()) throw InputError(file.string(), 1, header[i], "one of " + names, "an unknown column");
    column[static_cast<std::size_t>(found - wanted.begin())] = i;
  }
  for (std::size_t k = 0; k < wanted.size(); ++k) {
    if (column[k] == header.size()) throw InputError(file.string(), 1, wanted[k], "a column named " + wanted[k], "missing");
  }
  NumericCsv table;
  table.columns.resize(wanted.size());
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> cells = SplitCells(line);
    if (cells.size() != header.size()) {
      throw InputError(file.string(), line_number, "row", std::to_string(header.size()) + " cells",
                       std::to_string(cells.size()) + " cells");
    }
    for (std::size_t k = 0; k < wanted.size(); ++k) {
      const std::string& text = cells[column[k]];
      double value = 0.0;
      const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
      const bool number = ec == std::errc() && ptr == text.data() + text.size() && std::isfinite(value);
      const std::string expected = number ? rule(k, value, table) : "a finite number";
      if (!expected.empty()) throw InputError(file.string(), line_number, wanted[k], expected, "\"" + text + "\"");
      table.columns[k].push_back(value);
    }
  }
  if (table.columns[0].empty()) throw InputError(file.string(), line_number, "rows", "at least one data row", "none");
  return table;
}

}  // namespace pwsim
