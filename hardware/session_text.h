#pragma once
// Text helpers of the session log: numbers that round-trip exactly, hex payloads, words.

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hardware/can_frame.h"
#include "hardware/hmd_protocol.h"

namespace pwsim::hw {

/// Whole decimal number of at most 18 digits with an optional '-'; false otherwise.
bool ParseI64(std::string_view s, std::int64_t* v);
/// A whole-string floating-point number (or "nan"); false otherwise.
bool ParseF64(const std::string& s, double* v);
/// Whitespace-separated words.
std::vector<std::string> SplitWords(const std::string& line);

std::string HexEncode(std::span<const std::uint8_t> bytes);
bool HexDecode(std::string_view hex, std::vector<std::uint8_t>* bytes);

/// Text lines kept in one reserved buffer, for the per-tick log: appending allocates nothing
/// while the reserved capacity lasts (beyond it the buffer grows: an allocation, never a lost
/// or cut line), and clear() keeps the capacity. A line starts with Line(kind); each of Int,
/// Num, Word, Hex, Frame and PoseNums appends a space and its value, Raw appends text as is.
/// Numbers are written like FormatDouble (shortest round-trip text, std::to_chars).
class LogLines {
 public:
  explicit LogLines(std::size_t reserve_chars = 32 * 1024, std::size_t reserve_lines = 256);

  void clear() {
    text_.clear();
    starts_.clear();
  }
  std::size_t size() const { return starts_.size(); }
  bool empty() const { return starts_.empty(); }
  std::string_view operator[](std::size_t i) const;

  LogLines& Line(char kind);
  LogLines& Int(std::int64_t value);
  LogLines& Num(double value);
  LogLines& Word(std::string_view word);
  LogLines& Raw(std::string_view text);
  LogLines& Hex(std::span<const std::uint8_t> bytes);
  LogLines& Frame(const CanFrame& frame);
  LogLines& PoseNums(const Pose& pose);  ///< the 7 numbers p, q

  class Iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = std::string_view;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = std::string_view;
    Iterator() = default;
    Iterator(const LogLines* lines, std::size_t i) : lines_(lines), i_(i) {}
    std::string_view operator*() const { return (*lines_)[i_]; }
    Iterator& operator++() {
      ++i_;
      return *this;
    }
    Iterator operator++(int) {
      Iterator old = *this;
      ++i_;
      return old;
    }
    bool operator==(const Iterator& o) const { return i_ == o.i_; }

   private:
    const LogLines* lines_{nullptr};
    std::size_t i_{0};
  };
  Iterator begin() const { return {this, 0}; }
  Iterator end() const { return {this, starts_.size()}; }

 private:
  std::string text_;
  std::vector<std::size_t> starts_;
};

}  // namespace pwsim::hw
