#pragma once
// Validated reading of YAML mappings. Every accessor checks presence, type and range and
// throws InputError naming file, line, dotted field path and what was expected; Finish()
// rejects keys nobody asked for, so a typo in a scene file is an error, not a silent default.
//
//   YamlMap drive = scene.Map("drive");
//   double speed_mps = drive.Number("speed_mps", Range::Open0(4.0, "m/s"));
//   drive.Finish();

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace pwsim {

/// An allowed interval for a number; bounds are inclusive unless marked open.
struct Range {
  double min{-std::numeric_limits<double>::infinity()};
  double max{std::numeric_limits<double>::infinity()};
  bool min_open{false};
  bool max_open{false};
  std::string unit;

  static Range Any(std::string unit = "") { return {.unit = std::move(unit)}; }
  static Range Closed(double lo, double hi, std::string unit = "") {
    return {lo, hi, false, false, std::move(unit)};
  }
  /// (0, hi]: strictly positive.
  static Range Positive(double hi, std::string unit = "") {
    return {0.0, hi, true, false, std::move(unit)};
  }
  bool Contains(double value) const;
  std::string Describe() const;  ///< e.g. "a number in (0, 4] m/s"
};

/// A loaded YAML document with the file it came from.
struct YamlDocument {
  std::filesystem::path file;
  YAML::Node root;
};

/// Parses a YAML file; a missing file, a directory, a syntax error or a key written twice in
/// one mapping (which yaml-cpp would keep, the second copy unread) becomes an InputError.
YamlDocument LoadYamlFile(const std::filesystem::path& file);
/// Parses YAML text (for inline tests), with the same checks; `label` stands in for the file name.
YamlDocument LoadYamlString(const std::string& text, const std::string& label);

/// 1-based line of a node (0 when unknown).
int LineOf(const YAML::Node& node);

class YamlMap {
 public:
  /// @throws InputError if `node` is not a mapping.
  YamlMap(YAML::Node node, std::filesystem::path file, std::string path, int parent_line = 0);

  bool Has(const std::string& key) const;
  double Number(const std::string& key, const Range& range);
  double NumberOr(const std::string& key, double fallback, const Range& range);
  int Integer(const std::string& key, long long min, long long max);
  int IntegerOr(const std::string& key, int fallback, long long min, long long max);
  bool Bool(const std::string& key);
  bool BoolOr(const std::string& key, bool fallback);
  std::string String(const std::string& key);
  std::string StringOr(const std::string& key, const std::string& fallback);
  /// One of `allowed` (an enumeration).
  std::string Choice(const std::string& key, const std::vector<std::string>& allowed);
  std::string ChoiceOr(const std::string& key, const std::string& fallback,
                       const std::vector<std::string>& allowed);
  std::vector<double> Numbers(const std::string& key, const Range& each, std::size_t min_count,
                              std::size_t max_count);
  YamlMap Map(const std::string& key);
  /// A sequence node (checked to be one); elements are read by the caller.
  YAML::Node Sequence(const std::string& key);
  /// The raw node (marked as read). Throws if absent.
  YAML::Node Raw(const std::string& key);

  /// Reads `format:` and fails unless it is exactly `tag` (e.g. "pwsim-chair/1").
  void RequireFormat(const std::string& tag);

  /// @throws InputError for the first key that was never read.
  void Finish() const;

  const std::filesystem::path& file() const { return file_; }
  const std::string& path() const { return path_; }
  int line() const { return line_; }
  std::string FieldName(const std::string& key) const;
  int LineOfKey(const std::string& key) const;
  [[noreturn]] void Fail(const std::string& key, const std::string& expected,
                         const std::string& got) const;

 private:
  YAML::Node Get(const std::string& key);

  YAML::Node node_;
  std::filesystem::path file_;
  std::string path_;
  int line_{0};
  std::set<std::string> read_;
};

/// Reads a whole file tagged `format: tag`: `parse(YamlMap&)` reads the fields, then any key it
/// did not read is an error. Returns what `parse` returns.
template <typename Parse>
auto ReadTaggedYamlFile(const std::filesystem::path& file, const std::string& tag, Parse parse) {
  const YamlDocument document = LoadYamlFile(file);
  YamlMap root(document.root, document.file, "");
  root.RequireFormat(tag);
  auto value = parse(root);
  root.Finish();
  return value;
}

/// A number from a scalar node with field naming done by the caller.
double ScalarNumber(const YAML::Node& node, const std::filesystem::path& file,
                    const std::string& field, const Range& range);

/// Resolves `relative` against the folder of `anchor_file`.
std::filesystem::path ResolveRelative(const std::filesystem::path& anchor_file,
                                      const std::string& relative);

}  // namespace pwsim
