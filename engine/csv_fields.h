#pragma once
// The fields of one line of a plain comma-separated file (no quoting): split at every comma,
// each field trimmed of spaces, tabs and carriage returns; a trailing comma gives a last empty
// field, so "a,b," has three fields. And the header of such a file: the first line that is
// neither blank nor a comment ('#' first). One splitter for the ratings, the skill sheets and
// the training runs' lists; numeric tables have their reader in numeric_csv.h.

#include <istream>
#include <sstream>
#include <string>
#include <vector>

namespace pwsim {

inline std::vector<std::string> SplitCsvFields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) {
    const auto begin = field.find_first_not_of(" \t\r"), end = field.find_last_not_of(" \t\r");
    fields.push_back(begin == std::string::npos ? "" : field.substr(begin, end - begin + 1));
  }
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

/// Reads lines from `in` up to the header (the first line neither blank nor starting with '#')
/// and returns its fields; `line_number` counts every line read, `line` holds the header's text.
/// Empty where the file has no such line.
inline std::vector<std::string> ReadCsvHeader(std::istream& in, int& line_number, std::string& line) {
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    return SplitCsvFields(line);
  }
  return {};
}

}  // namespace pwsim
