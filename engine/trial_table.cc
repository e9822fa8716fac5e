#include "engine/trial_table.h"

#include <algorithm>

#include "engine/atomic_file.h"
#include "engine/check.h"
#include "engine/number_format.h"

namespace pwsim {

void TrialTable::Add(std::string name, std::vector<double> values) {
  PWSIM_DEMAND(values.size() == rows_);
  PWSIM_DEMAND(!Has(name));
  names_.push_back(std::move(name));
  columns_.push_back(std::move(values));
}

bool TrialTable::Has(const std::string& name) const {
  return std::find(names_.begin(), names_.end(), name) != names_.end();
}

const std::vector<double>& TrialTable::Column(const std::string& name) const {
  const auto found = std::find(names_.begin(), names_.end(), name);
  PWSIM_DEMAND(found != names_.end());
  return columns_[static_cast<std::size_t>(found - names_.begin())];
}

void TrialTable::WriteCsv(const std::filesystem::path& file, int decimate) const {
  PWSIM_DEMAND(decimate >= 1);
  AtomicFileWriter writer(file);
  std::ofstream& out = writer.stream();
  for (std::size_t c = 0; c < names_.size(); ++c) out << (c ? "," : "") << names_[c];
  out << "\n";
  std::string line;
  for (std::size_t r = 0; r < rows_; r += static_cast<std::size_t>(decimate)) {
    line.clear();
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      if (c) line += ',';
      line += FormatDouble(columns_[c][r]);
    }
    line += '\n';
    out << line;
  }
  writer.Commit();
}

}  // namespace pwsim
