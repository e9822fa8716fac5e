#pragma once
// The output folder of one pwsim command: what the command writes there replaces what the last
// pwsim command wrote there, and nothing else (docs/command-line.md, "Output folders").
//
// Every command that writes a folder records the files it wrote in DIR/.pwsim-outputs.json
// (format pwsim-outputs/1: the command line and the files, relative to DIR). Before the
// command writes anything, OutputFolder's constructor removes every file listed in that record,
// whichever command wrote it (a car run into a folder that held a chair run leaves none of the
// chair's visual_check.* beside the car's summary), then the folders those files emptied, then
// the record. A file pwsim did not write (no record lists it) is never touched.
//
// Commit() lists the files now under DIR that are new or changed since the constructor (size
// or modification time), writes the record and returns the list: the one list of written files
// every command prints (Print). A command that throws before Commit() leaves no record and
// none of its partial outputs: the destructor removes them, so nothing is left looking complete.
//
//   OutputFolder folder(OutDir(args), "run");
//   ... write into folder.dir() ...
//   folder.Print(std::cout, "pwsim run");   // commits

#include <cstdint>
#include <filesystem>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace pwsim::app {

class OutputFolder {
 public:
  /// The record's name inside an output folder.
  static constexpr const char* kRecord = ".pwsim-outputs.json";

  /// Claims `dir` for `command` (e.g. "run", "study plan"): creates it, removes the outputs the
  /// record there lists. @throws InputError when `dir` is an existing file, or its record is
  /// not a pwsim-outputs/1 file (nothing is removed then).
  OutputFolder(std::filesystem::path dir, std::string command);
  /// Without Commit(): removes what this run wrote, and the folder when this run created it and
  /// it is empty again (best effort, never throws).
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  /// The files removed by the constructor (relative to dir), sorted.
  const std::vector<std::filesystem::path>& removed() const { return removed_; }

  /// Records and returns the files written since the constructor (paths dir/..., sorted).
  /// Idempotent: a second call returns the same list.
  const std::vector<std::filesystem::path>& Commit();
  /// Commits, then prints "PREFIX: wrote N files in DIR:" and one line per file; beyond
  /// `max_listed` files, each sub-folder of DIR is one line "DIR/SUB/ (N files)".
  void Print(std::ostream& out, const std::string& prefix, std::size_t max_listed = 24);

 private:
  struct Stamp {
    std::uintmax_t size{0};
    std::filesystem::file_time_type time{};
    bool operator==(const Stamp&) const = default;
  };
  std::map<std::filesystem::path, Stamp> Scan() const;
  void RemoveFiles(const std::vector<std::filesystem::path>& relative);

  std::filesystem::path dir_;
  std::string command_;
  std::map<std::filesystem::path, Stamp> before_;
  std::vector<std::filesystem::path> removed_;
  std::vector<std::filesystem::path> written_;
  bool created_{false};  ///< the folder did not exist before
  bool committed_{false};
};

}  // namespace pwsim::app
