#include "engine/atomic_file.h"

#include <stdexcept>

namespace pwsim {

AtomicFileWriter::AtomicFileWriter(std::filesystem::path file)
    : file_(std::move(file)), partial_(file_.string() + ".partial") {
  if (file_.has_parent_path()) std::filesystem::create_directories(file_.parent_path());
  out_.open(partial_, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error(file_.string() + ": cannot open for writing");
}

AtomicFileWriter::~AtomicFileWriter() {
  if (!committed_) {
    out_.close();
    std::error_code ignored;
    std::filesystem::remove(partial_, ignored);
  }
}

void AtomicFileWriter::Commit() {
  out_.flush();
  if (!out_) throw std::runtime_error(file_.string() + ": write failed");
  out_.close();
  std::filesystem::rename(partial_, file_);
  committed_ = true;
}

void WriteFileAtomically(const std::filesystem::path& file, const std::string& content) {
  AtomicFileWriter writer(file);
  writer.stream() << content;
  writer.Commit();
}

}  // namespace pwsim
