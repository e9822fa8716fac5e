#pragma once
// printf-style text for the diagnosis' evidence strings and split descriptions.

#include <cstdio>
#include <string>

namespace pwsim::diagnose {

template <typename... Args>
std::string Format(const char* fmt, Args... args) {
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer), fmt, args...);
  return buffer;
}

}  // namespace pwsim::diagnose
