#include "report/format.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace pwsim::report {

std::string Fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "n/a";
  std::ostringstream out;
  out << std::fixed << std::setprecision(decimals) << value;
  return out.str();
}

std::string Significant(double value, int digits) {
  if (!std::isfinite(value)) return "n/a";
  std::ostringstream out;
  out << std::setprecision(digits) << value;
  return out.str();
}

nlohmann::ordered_json JsonNumber(double value) {
  if (!std::isfinite(value)) return nullptr;
  if (std::abs(value) >= 1.0 || value == 0.0) return std::round(value * 1000.0) / 1000.0;
  return std::stod(Significant(value, 6));
}

}  // namespace pwsim::report
