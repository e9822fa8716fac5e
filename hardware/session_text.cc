#include "hardware/session_text.h"

#include <charconv>
#include <cmath>
#include <sstream>


namespace pwsim::hw {

bool ParseI64(std::string_view s, std::int64_t* v) {
  if (s.empty()) return false;
  std::int64_t x = 0;
  bool neg = false;
  std::size_t i = 0;
  if (s[0] == '-') {
    neg = true;
    i = 1;
  }
  if (i >= s.size()) return false;
  if (s.size() - i > 18) return false;  // keeps x inside int64
  for (; i < s.size(); ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    x = x * 10 + (s[i] - '0');
  }
  *v = neg ? -x : x;
  return true;
}

bool ParseF64(const std::string& s, double* v) {
  try {
    std::size_t used = 0;
    *v = std::stod(s, &used);
    return used == s.size();
  } catch (...) {
    return s == "nan" ? (*v = NAN, true) : false;
  }
}

std::vector<std::string> SplitWords(const std::string& line) {
  std::vector<std::string> parts;
  std::istringstream in(line);
  std::string w;
  while (in >> w) parts.push_back(w);
  return parts;
}

std::string HexEncode(std::span<const std::uint8_t> bytes) {
  static const char* kHex = "0123456789abcdef";
  std::string s;
  s.reserve(bytes.size() * 2);
  for (std::uint8_t b : bytes) {
    s.push_back(kHex[b >> 4]);
    s.push_back(kHex[b & 0xF]);
  }
  return s;
}

bool HexDecode(std::string_view hex, std::vector<std::uint8_t>* bytes) {
  if (hex.size() % 2 != 0) return false;
  bytes->clear();
  auto val = [](char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  for (std::size_t i = 0; i < hex.size(); i += 2) {
    const int hi = val(hex[i]);
    const int lo = val(hex[i + 1]);
    if (hi < 0 || lo < 0) return false;
    bytes->push_back(static_cast<std::uint8_t>(hi * 16 + lo));
  }
  return true;
}

LogLines::LogLines(std::size_t reserve_chars, std::size_t reserve_lines) {
  text_.reserve(reserve_chars);
  starts_.reserve(reserve_lines);
}

std::string_view LogLines::operator[](std::size_t i) const {
  const std::size_t end = i + 1 < starts_.size() ? starts_[i + 1] : text_.size();
  return std::string_view(text_).substr(starts_[i], end - starts_[i]);
}

LogLines& LogLines::Line(char kind) {
  starts_.push_back(text_.size());
  text_.push_back(kind);
  return *this;
}

LogLines& LogLines::Int(std::int64_t value) {
  char buffer[24];
  const auto r = std::to_chars(buffer, buffer + sizeof(buffer), value);
  text_.push_back(' ');
  text_.append(buffer, r.ptr);
  return *this;
}

LogLines& LogLines::Num(double value) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof(buffer), value);
  text_.push_back(' ');
  if (r.ec == std::errc())
    text_.append(buffer, r.ptr);
  else
    text_.append("nan");  // as FormatDouble
  return *this;
}

LogLines& LogLines::Word(std::string_view word) {
  text_.push_back(' ');
  text_.append(word);
  return *this;
}

LogLines& LogLines::Raw(std::string_view text) {
  text_.append(text);
  return *this;
}

LogLines& LogLines::Hex(std::span<const std::uint8_t> bytes) {
  static constexpr char kHex[] = "0123456789abcdef";
  text_.push_back(' ');
  for (std::uint8_t b : bytes) {
    text_.push_back(kHex[b >> 4]);
    text_.push_back(kHex[b & 0xF]);
  }
  return *this;
}

LogLines& LogLines::Frame(const CanFrame& frame) {
  std::array<char, kFrameTextMax> buffer{};
  const std::size_t n = FormatFrameText(frame, buffer);
  text_.push_back(' ');
  text_.append(buffer.data(), n);
  return *this;
}

LogLines& LogLines::PoseNums(const Pose& pose) {
  for (double v : pose.p) Num(v);
  for (double v : pose.q) Num(v);
  return *this;
}

}  // namespace pwsim::hw
