#pragma once
// TrialTable: named columns of per-tick values, written as CSV with the unit in each column
// name (t_s, x_m, pitch_rad, ...). Each stage of the pipeline appends its own columns.

#include <filesystem>
#include <string>
#include <vector>

namespace pwsim {

class TrialTable {
 public:
  explicit TrialTable(std::size_t rows) : rows_(rows) {}

  std::size_t rows() const { return rows_; }
  /// Appends a column. @pre values.size() == rows(), name unique.
  void Add(std::string name, std::vector<double> values);
  const std::vector<double>& Column(const std::string& name) const;
  bool Has(const std::string& name) const;
  const std::vector<std::string>& names() const { return names_; }

  /// Writes CSV (header row, then one row per tick, shortest round-trip numbers) atomically;
  /// `decimate` keeps every n-th row.
  void WriteCsv(const std::filesystem::path& file, int decimate = 1) const;

 private:
  std::size_t rows_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> columns_;
};

}  // namespace pwsim
