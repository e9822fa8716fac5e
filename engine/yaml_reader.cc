#include "engine/yaml_reader.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "engine/input_error.h"

namespace pwsim {
namespace {

std::string FormatBound(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string Quote(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsScalar()) return "\"" + node.Scalar() + "\"";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a mapping";
  return "an unreadable value";
}

/// Strict number parse: the whole scalar must be a finite decimal number.
std::optional<double> ParseNumber(const std::string& text) {
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (*begin == '+') ++begin;
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

/// yaml-cpp keeps both entries of a key written twice in one mapping and node[key] returns the
/// first, so the second would be ignored silently: refuse it, naming both lines.
void RefuseDuplicateKeys(const YAML::Node& node, const std::string& label, const std::string& path) {
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      RefuseDuplicateKeys(node[i], label, path + "[" + std::to_string(i) + "]");
    }
    return;
  }
  if (!node.IsMap()) return;
  std::unordered_map<std::string, int> first_line;
  for (const auto& entry : node) {
    if (!entry.first.IsScalar()) continue;
    const std::string& key = entry.first.Scalar();
    const std::string field = path.empty() ? key : path + "." + key;
    const int line = LineOf(entry.first);
    const auto [seen, fresh] = first_line.emplace(key, line);
    if (!fresh) {
      throw InputError(label, line, field, "each key once in a mapping",
                       "\"" + key + "\" again (first on line " + std::to_string(seen->second) + ")");
    }
    RefuseDuplicateKeys(entry.second, label, field);
  }
}

}  // namespace

bool Range::Contains(double value) const {
  if (!std::isfinite(value)) return false;
  if (min_open ? !(value > min) : !(value >= min)) return false;
  if (max_open ? !(value < max) : !(value <= max)) return false;
  return true;
}

std::string Range::Describe() const {
  std::string text = "a finite number";
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max) {
    text = "a number in " + std::string(min_open ? "(" : "[") + FormatBound(min) + ", " +
           FormatBound(max) + (max_open ? ")" : "]");
  } else if (has_min) {
    text = "a number " + std::string(min_open ? "> " : ">= ") + FormatBound(min);
  } else if (has_max) {
    text = "a number " + std::string(max_open ? "< " : "<= ") + FormatBound(max);
  }
  if (!unit.empty()) text += " " + unit;
  return text;
}

YamlDocument LoadYamlFile(const std::filesystem::path& file) {
  RequireReadableFile(file, "a readable YAML file");
  std::ifstream in(file);
  if (!in) {
    throw InputError(file.string(), 0, "(file)", "a readable YAML file", "no such file");
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return LoadYamlString(buffer.str(), file.string());
}

YamlDocument LoadYamlString(const std::string& text, const std::string& label) {
  try {
    YAML::Node root = YAML::Load(text);
    if (!root.IsDefined() || root.IsNull()) {
      throw InputError(label, 0, "(document)", "a YAML mapping", "an empty document");
    }
    RefuseDuplicateKeys(root, label, "");
    return {label, root};
  } catch (const YAML::Exception& error) {
    throw InputError(label, error.mark.line + 1, "(syntax)", "valid YAML", error.msg);
  }
}

int LineOf(const YAML::Node& node) {
  if (!node.IsDefined()) return 0;
  const int line = node.Mark().line;
  return line >= 0 ? line + 1 : 0;
}

YamlMap::YamlMap(YAML::Node node, std::filesystem::path file, std::string path, int parent_line)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {
  line_ = LineOf(node_);
  if (line_ == 0) line_ = parent_line;
  if (!node_.IsMap()) {
    throw InputError(file_.string(), line_, path_.empty() ? "(document)" : path_, "a mapping",
                     Quote(node_));
  }
}

std::string YamlMap::FieldName(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

int YamlMap::LineOfKey(const std::string& key) const {
  for (const auto& entry : node_) {
    if (entry.first.Scalar() == key) {
      const int line = LineOf(entry.first);
      return line > 0 ? line : line_;
    }
  }
  return line_;
}

void YamlMap::Fail(const std::string& key, const std::string& expected,
                   const std::string& got) const {
  throw InputError(file_.string(), LineOfKey(key), FieldName(key), expected, got);
}

bool YamlMap::Has(const std::string& key) const { return static_cast<bool>(node_[key]); }

YAML::Node YamlMap::Get(const std::string& key) {
  read_.insert(key);
  YAML::Node value = node_[key];
  if (!value) Fail(key, "this required field", "nothing (missing)");
  return value;
}

double YamlMap::Number(const std::string& key, const Range& range) {
  return ScalarNumber(Get(key), file_, FieldName(key), range);
}

double YamlMap::NumberOr(const std::string& key, double fallback, const Range& range) {
  read_.insert(key);
  return Has(key) ? Number(key, range) : fallback;
}

int YamlMap::Integer(const std::string& key, long long min, long long max) {
  YAML::Node value = Get(key);
  const std::string expected =
      "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (!value.IsScalar()) Fail(key, expected, Quote(value));
  long long parsed = 0;
  const std::string& text = value.Scalar();
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), parsed);
  if (ec != std::errc() || ptr != text.data() + text.size() || parsed < min || parsed > max) {
    Fail(key, expected, Quote(value));
  }
  return static_cast<int>(parsed);
}

int YamlMap::IntegerOr(const std::string& key, int fallback, long long min, long long max) {
  read_.insert(key);
  return Has(key) ? Integer(key, min, max) : fallback;
}

bool YamlMap::Bool(const std::string& key) {
  YAML::Node value = Get(key);
  if (value.IsScalar()) {
    const std::string& text = value.Scalar();
    if (text == "true") return true;
    if (text == "false") return false;
  }
  Fail(key, "true or false", Quote(value));
}

bool YamlMap::BoolOr(const std::string& key, bool fallback) {
  read_.insert(key);
  return Has(key) ? Bool(key) : fallback;
}

std::string YamlMap::String(const std::string& key) {
  YAML::Node value = Get(key);
  if (!value.IsScalar() || value.Scalar().empty()) Fail(key, "a non-empty string", Quote(value));
  return value.Scalar();
}

std::string YamlMap::StringOr(const std::string& key, const std::string& fallback) {
  read_.insert(key);
  return Has(key) ? String(key) : fallback;
}

std::string YamlMap::Choice(const std::string& key, const std::vector<std::string>& allowed) {
  YAML::Node value = Get(key);
  std::string expected = "one of";
  for (std::size_t i = 0; i < allowed.size(); ++i) {
    expected += (i == 0 ? " " : ", ") + allowed[i];
  }
  if (!value.IsScalar()) Fail(key, expected, Quote(value));
  for (const auto& option : allowed) {
    if (value.Scalar() == option) return option;
  }
  Fail(key, expected, Quote(value));
}

std::string YamlMap::ChoiceOr(const std::string& key, const std::string& fallback,
                              const std::vector<std::string>& allowed) {
  read_.insert(key);
  return Has(key) ? Choice(key, allowed) : fallback;
}

std::vector<double> YamlMap::Numbers(const std::string& key, const Range& each,
                                     std::size_t min_count, std::size_t max_count) {
  YAML::Node value = Get(key);
  const std::string expected = "a list of " + std::to_string(min_count) + ".." +
                               std::to_string(max_count) + " numbers";
  if (!value.IsSequence()) Fail(key, expected, Quote(value));
  if (value.size() < min_count || value.size() > max_count) {
    Fail(key, expected, std::to_string(value.size()) + " items");
  }
  std::vector<double> numbers;
  numbers.reserve(value.size());
  for (std::size_t i = 0; i < value.size(); ++i) {
    numbers.push_back(
        ScalarNumber(value[i], file_, FieldName(key) + "[" + std::to_string(i) + "]", each));
  }
  return numbers;
}

YamlMap YamlMap::Map(const std::string& key) {
  return YamlMap(Get(key), file_, FieldName(key), LineOfKey(key));
}

YAML::Node YamlMap::Sequence(const std::string& key) {
  YAML::Node value = Get(key);
  if (!value.IsSequence()) Fail(key, "a list", Quote(value));
  return value;
}

YAML::Node YamlMap::Raw(const std::string& key) { return Get(key); }

void YamlMap::RequireFormat(const std::string& tag) {
  const std::string format = String("format");
  if (format != tag) Fail("format", "\"" + tag + "\"", "\"" + format + "\"");
}

void YamlMap::Finish() const {
  for (const auto& entry : node_) {
    const std::string key = entry.first.Scalar();
    if (read_.count(key) == 0) {
      std::string known;
      for (const auto& name : read_) known += (known.empty() ? "" : ", ") + name;
      throw InputError(file_.string(), LineOf(entry.first), FieldName(key),
                       "a known key (" + (known.empty() ? std::string("none here") : known) + ")",
                       "unknown key \"" + key + "\"");
    }
  }
}

double ScalarNumber(const YAML::Node& node, const std::filesystem::path& file,
                    const std::string& field, const Range& range) {
  if (!node.IsScalar()) throw InputError(file.string(), LineOf(node), field, range.Describe(), Quote(node));
  const auto parsed = ParseNumber(node.Scalar());
  if (!parsed || !range.Contains(*parsed)) {
    throw InputError(file.string(), LineOf(node), field, range.Describe(), Quote(node));
  }
  return *parsed;
}

std::filesystem::path ResolveRelative(const std::filesystem::path& anchor_file,
                                      const std::string& relative) {
  std::filesystem::path target(relative);
  if (target.is_absolute()) return target;
  return anchor_file.parent_path() / target;
}

}  // namespace pwsim
