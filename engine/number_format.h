#pragma once
// Locale-independent, round-trip-exact number formatting for every file pwsim writes:
// the shortest decimal that reads back to the same double, so outputs are bit-reproducible.

#include <charconv>
#include <string>

namespace pwsim {

inline std::string FormatDouble(double value) {
  char buffer[32];
  auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return ec == std::errc() ? std::string(buffer, ptr) : std::string("nan");
}

}  // namespace pwsim
