#pragma once
// InputError: bad input found at load time (error kind 2). The message always names the
// file, the line (0 when the input has no lines), the field and what was expected, e.g.
//   scenes/x.yaml:12: field 'drive.speed_mps': expected a number in (0, 4] m/s, got "fast"

#include <filesystem>
#include <stdexcept>
#include <string>

namespace pwsim {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, std::string field, std::string expected,
             std::string got);

  const std::string& file() const { return file_; }
  int line() const { return line_; }                 ///< 1-based; 0 = no line
  const std::string& field() const { return field_; }
  const std::string& expected() const { return expected_; }
  const std::string& got() const { return got_; }

 private:
  std::string file_;
  int line_{0};
  std::string field_;
  std::string expected_;
  std::string got_;
};

/// Refuses, before a reader opens it, a `file` that does not exist, is a directory or is not a
/// regular file (a FIFO or /dev/stdin is accepted: a sweep task may read its input from a pipe).
/// `what` names what was expected, e.g. "a YAML file", "a candump log".
/// @throws InputError (file, line 0, field "(file)", WHAT, "a path that is a directory" |
/// "no such file").
void RequireReadableFile(const std::filesystem::path& file, const std::string& what);

}  // namespace pwsim
