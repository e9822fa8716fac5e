#include "engine/input_error.h"

#include <utility>

namespace pwsim {
namespace {

std::string Compose(const std::string& file, int line, const std::string& field,
                    const std::string& expected, const std::string& got) {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line);
  std::string message = where + ": field '" + field + "': expected " + expected;
  if (!got.empty()) message += ", got " + got;
  return message;
}

}  // namespace

InputError::InputError(std::string file, int line, std::string field, std::string expected,
                       std::string got)
    : std::runtime_error(Compose(file, line, field, expected, got)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)),
      expected_(std::move(expected)),
      got_(std::move(got)) {}

void RequireReadableFile(const std::filesystem::path& file, const std::string& what) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  if (status.type() == std::filesystem::file_type::not_found) {
    throw InputError(file.string(), 0, "(file)", what, "no such file");
  }
  if (status.type() == std::filesystem::file_type::directory) {
    throw InputError(file.string(), 0, "(file)", what, "a path that is a directory");
  }
}

}  // namespace pwsim
