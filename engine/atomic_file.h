#pragma once
// Files that are either complete or absent: content goes to "<name>.partial" and is renamed
// into place only once fully written, so a crash never leaves a half file that looks whole.

#include <filesystem>
#include <fstream>
#include <string>

namespace pwsim {

/// Writes `content` to `file` atomically (temporary + rename). Creates parent folders.
/// @throws std::runtime_error naming the file if writing fails.
void WriteFileAtomically(const std::filesystem::path& file, const std::string& content);

/// A streaming writer with the same guarantee: Commit() renames; destruction without
/// Commit() removes the partial file.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::filesystem::path file);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  std::ofstream& stream() { return out_; }
  void Commit();

 private:
  std::filesystem::path file_;
  std::filesystem::path partial_;
  std::ofstream out_;
  bool committed_{false};
};

}  // namespace pwsim
