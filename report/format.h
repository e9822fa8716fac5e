#pragma once
// Numbers in human-read reports (markdown, console tables) and in report JSON. Files that
// other programs read back bit for bit (trial.csv, YAML) use engine/number_format.h instead.

#include <nlohmann/json.hpp>

#include <string>

namespace pwsim::report {

/// `value` with `decimals` digits after the point ("n/a" when not finite).
std::string Fixed(double value, int decimals);

/// `value` with `digits` significant digits, %g style ("n/a" when not finite).
std::string Significant(double value, int digits);

/// A JSON number for reports: rounded to 1e-3 when |value| >= 1 (or 0), else to 6 significant
/// digits; null when not finite (JSON has neither NaN nor infinity).
nlohmann::ordered_json JsonNumber(double value);

}  // namespace pwsim::report
