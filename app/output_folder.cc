#include "app/output_folder.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <set>

#include "engine/atomic_file.h"
#include "engine/input_error.h"

namespace pwsim::app {
namespace {

namespace fs = std::filesystem;

/// The files a record lists, each checked to stay inside the folder.
std::vector<fs::path> ReadRecord(const fs::path& record) {
  std::ifstream in(record);
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(record.string(), 0, "(document)",
                     "a pwsim-outputs/1 record (JSON; delete it to keep every file in the folder)", error.what());
  }
  if (!json.is_object() || json.value("format", "") != "pwsim-outputs/1" || !json.contains("files") ||
      !json["files"].is_array()) {
    throw InputError(record.string(), 0, "format", "a pwsim-outputs/1 record with a files list", json.dump().substr(0, 80));
  }
  std::vector<fs::path> files;
  for (const auto& entry : json["files"]) {
    const fs::path file = entry.is_string() ? fs::path(entry.get<std::string>()).lexically_normal() : fs::path();
    if (file.empty() || file.is_absolute() || *file.begin() == "..") {
      throw InputError(record.string(), 0, "files", "paths inside the folder (relative, no '..')", entry.dump());
    }
    files.push_back(file);
  }
  return files;
}

}  // namespace

OutputFolder::OutputFolder(fs::path dir, std::string command) : dir_(std::move(dir)), command_(std::move(command)) {
  if (fs::exists(dir_) && !fs::is_directory(dir_)) {
    throw InputError(dir_.string(), 0, "--out", "a folder for the outputs", "an existing file");
  }
  created_ = !fs::exists(dir_);
  fs::create_directories(dir_);
  const fs::path record = dir_ / kRecord;
  if (fs::exists(record)) {
    std::vector<fs::path> stale = ReadRecord(record);
    std::sort(stale.begin(), stale.end());
    RemoveFiles(stale);
    for (const fs::path& file : stale) {
      if (!fs::exists(dir_ / file)) removed_.push_back(file);
    }
    fs::remove(record);
  }
  before_ = Scan();
}

OutputFolder::~OutputFolder() {
  if (committed_) return;
  try {
    std::vector<fs::path> partial;
    for (const auto& [file, stamp] : Scan()) {
      const auto found = before_.find(file);
      if (found == before_.end() || !(found->second == stamp)) partial.push_back(file);
    }
    RemoveFiles(partial);
    std::error_code error;
    if (created_ && fs::is_empty(dir_, error)) fs::remove(dir_, error);
  } catch (...) {  // a destructor never throws: what could not be removed stays
  }
}

std::map<fs::path, OutputFolder::Stamp> OutputFolder::Scan() const {
  std::map<fs::path, Stamp> files;
  std::error_code error;
  for (fs::recursive_directory_iterator it(dir_, error), end; !error && it != end; it.increment(error)) {
    if (!it->is_regular_file(error)) continue;
    const fs::path relative = it->path().lexically_relative(dir_);
    if (relative == kRecord) continue;
    files[relative] = {it->file_size(error), it->last_write_time(error)};
  }
  return files;
}

void OutputFolder::RemoveFiles(const std::vector<fs::path>& relative) {
  std::set<fs::path> parents;
  std::error_code error;
  for (const fs::path& file : relative) {
    fs::remove(dir_ / file, error);
    for (fs::path parent = file.parent_path(); !parent.empty(); parent = parent.parent_path()) parents.insert(parent);
  }
  // deepest first: a folder emptied by the removal goes too (fs::remove leaves a non-empty one)
  for (auto it = parents.rbegin(); it != parents.rend(); ++it) {
    if (fs::is_directory(dir_ / *it, error) && fs::is_empty(dir_ / *it, error)) fs::remove(dir_ / *it, error);
  }
}

const std::vector<fs::path>& OutputFolder::Commit() {
  if (committed_) return written_;
  nlohmann::ordered_json record{{"format", "pwsim-outputs/1"}, {"command", "pwsim " + command_}};
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const auto& [file, stamp] : Scan()) {
    const auto found = before_.find(file);
    if (found != before_.end() && found->second == stamp) continue;
    written_.push_back(dir_ / file);
    files.push_back(file.generic_string());
  }
  record["files"] = files;
  WriteFileAtomically(dir_ / kRecord, record.dump(1) + "\n");
  committed_ = true;
  return written_;
}

void OutputFolder::Print(std::ostream& out, const std::string& prefix, std::size_t max_listed) {
  const std::vector<fs::path>& files = Commit();
  out << prefix << ": wrote " << files.size() << (files.size() == 1 ? " file" : " files") << " in " << dir_.string()
      << (files.empty() ? "\n" : ":\n");
  std::map<fs::path, std::size_t> per_folder;  // top-level sub-folder -> files in it
  for (const fs::path& file : files) {
    const fs::path relative = file.lexically_relative(dir_);
    if (relative.has_parent_path()) ++per_folder[*relative.begin()];
  }
  const bool every_file = files.size() <= max_listed;
  std::set<fs::path> summarised;
  for (const fs::path& file : files) {
    const fs::path relative = file.lexically_relative(dir_);
    if (!every_file && relative.has_parent_path()) {
      const fs::path top = *relative.begin();
      if (summarised.insert(top).second) {
        out << "  " << (dir_ / top).string() << "/ (" << per_folder[top]
            << (per_folder[top] == 1 ? " file)\n" : " files)\n");
      }
      continue;
    }
    out << "  " << file.string() << "\n";
  }
}

}  // namespace pwsim::app
