#pragma once
// Text helpers of the session log: numbers that round-trip exactly, hex payloads, words.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hardware/hmd_protocol.h"

namespace pwsim::hw {

/// " x y z qx qy qz qw", each number in FormatDouble's round-trip form.
std::string PoseText(const Pose& p);
/// Whole decimal number of at most 18 digits with an optional '-'; false otherwise.
bool ParseI64(std::string_view s, std::int64_t* v);
/// A whole-string floating-point number (or "nan"); false otherwise.
bool ParseF64(const std::string& s, double* v);
/// Whitespace-separated words.
std::vector<std::string> SplitWords(const std::string& line);

std::string HexEncode(std::span<const std::uint8_t> bytes);
bool HexDecode(std::string_view hex, std::vector<std::uint8_t>* bytes);

}  // namespace pwsim::hw
