#pragma once
// A numeric CSV file read whole: a header row naming the columns (any order; every wanted name
// present, no other), then one row of numbers per line (blank lines skipped). Every cell is
// checked by the caller's rule, in row order and, within a row, in the order of `wanted`; a
// failed rule, a cell that is not a finite number, a short or long row, an unknown or missing
// column, or a file without rows is an InputError naming the file, the line and the column.
// One reader for the recorded drives of the car and the recorded joysticks of the chair.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace pwsim {

struct NumericCsv {
  std::vector<std::vector<double>> columns;  ///< one per wanted name, in `wanted` order
};

/// The rule for one cell: "" when `value` is acceptable in column `k` (of `wanted`), else what
/// was expected. `columns` holds the rows read so far (e.g. to ask for a rising time).
using CsvCellRule = std::function<std::string(std::size_t k, double value, const NumericCsv& so_far)>;

/// @throws InputError (file, line, column, expected).
NumericCsv ReadNumericCsv(const std::filesystem::path& file, const std::vector<std::string>& wanted,
                          const CsvCellRule& rule);

}  // namespace pwsim
