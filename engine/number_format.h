#pragma once
// Locale-independent, round-trip-exact number formatting for every file pwsim writes:
// the shortest decimal that reads back to the same double, so outputs are bit-reproducible;
// and its reading counterpart for command-line and table cells.

#include <charconv>
#include <cmath>
#include <exception>
#include <optional>
#include <string>

namespace pwsim {

inline std::string FormatDouble(double value) {
  char buffer[32];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return ec == std::errc() ? std::string(buffer, ptr) : std::string("nan");
}

/// The whole of `text` as a finite number ("1.5", "-2e3"), or nothing: empty text, trailing
/// characters, NaN and infinities are not numbers here.
inline std::optional<double> ParseFiniteNumber(const std::string& text) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used == 0 || used != text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

}  // namespace pwsim
