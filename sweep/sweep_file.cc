#include "sweep/sweep_file.h"

#include <glob.h>

#include <algorithm>
#include <set>
#include <stdexcept>

#include "engine/input_error.h"
#include "engine/yaml_reader.h"

namespace pwsim::sweep {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxTasks = 1000000;

bool IsIdentifier(const std::string& text) {
  if (text.empty() || !(std::isalpha(static_cast<unsigned char>(text[0])) || text[0] == '_')) return false;
  return std::all_of(text.begin(), text.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

std::vector<std::string> SplitDots(const std::string& text) {
  std::vector<std::string> parts;
  std::string current;
  for (char c : text) {
    if (c == '.') {
      parts.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  parts.push_back(current);
  return parts;
}

std::string Describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsScalar()) return "\"" + node.Scalar() + "\"";
  if (node.IsSequence()) return "a list";
  return "a mapping";
}

std::string FlowText(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  YAML::Emitter out;
  out.SetSeqFormat(YAML::Flow);
  out.SetMapFormat(YAML::Flow);
  out << node;
  return out.c_str();
}

/// A string that contains '/' and names an existing path relative to `base` becomes absolute.
std::string AbsolutiseIfPath(const std::string& text, const fs::path& base) {
  if (text.find('/') == std::string::npos || text.find('{') != std::string::npos) return text;
  const fs::path candidate(text);
  if (candidate.is_absolute()) return text;
  std::error_code error;
  const fs::path resolved = (base / candidate).lexically_normal();
  if (!fs::exists(resolved, error)) return text;
  return resolved.string();
}

class Reader {
 public:
  Reader(const fs::path& file, const std::vector<std::string>& known_commands)
      : known_commands_(known_commands) {
    spec_.file = fs::absolute(file).lexically_normal();
    base_ = spec_.file.parent_path();
  }

  SweepSpec Read() {
    const YamlDocument document = LoadYamlFile(spec_.file);
    YamlMap root(document.root, spec_.file, "");
    root.RequireFormat("pwsim-sweep/1");
    ReadName(root);
    spec_.description = root.StringOr("description", "");
    ReadCommand(root);
    ReadInputs(root);
    ReadArguments(root);
    if (root.Has("set")) ReadSet(root);
    if (root.Has("list")) ReadList(root);
    if (root.Has("grid")) ReadGrid(root);
    ReadGather(root);
    spec_.retries = root.IntegerOr("retries", 2, 0, 100);
    spec_.timeout_s = root.NumberOr("timeout_s", 0.0, Range::Closed(0.0, 1e7, "s"));
    if (root.Has("slurm")) ReadSlurm(root);
    root.Finish();  // a misspelt section is named before anything is said about missing ones
    if (!root.Has("grid") && !root.Has("list")) {
      root.Fail("grid", "a grid: or a list: of variations (one task per combination)", "neither");
    }
    CheckPlaceholders(root);
    if (spec_.TaskCount() > kMaxTasks) {
      root.Fail(root.Has("grid") ? "grid" : "list",
                "at most " + std::to_string(kMaxTasks) + " tasks",
                std::to_string(spec_.TaskCount()) + " combinations");
    }
    return spec_;
  }

 private:
  [[noreturn]] void FailAt(int line, const std::string& field, const std::string& expected,
                           const std::string& got) const {
    throw InputError(spec_.file.string(), line, field, expected, got);
  }

  void ReadName(YamlMap& root) {
    spec_.name = root.String("name");
    const bool ok = std::all_of(spec_.name.begin(), spec_.name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    });
    if (!ok) root.Fail("name", "letters, digits, '_', '-' or '.' only", "\"" + spec_.name + "\"");
  }

  void ReadCommand(YamlMap& root) {
    const YAML::Node node = root.Raw("command");
    const int line = root.LineOfKey("command");
    if (node.IsScalar()) {
      std::string word;
      for (char c : node.Scalar() + " ") {
        if (c == ' ' || c == '\t') {
          if (!word.empty()) spec_.command.push_back(word);
          word.clear();
        } else {
          word += c;
        }
      }
    } else if (node.IsSequence()) {
      for (std::size_t i = 0; i < node.size(); ++i) {
        if (!node[i].IsScalar() || node[i].Scalar().empty()) {
          FailAt(LineOf(node[i]), "command[" + std::to_string(i) + "]", "a word", Describe(node[i]));
        }
        spec_.command.push_back(node[i].Scalar());
      }
    }
    std::string known;
    for (const std::string& name : known_commands_) {
      if (name != "sweep") known += (known.empty() ? "" : ", ") + name;
    }
    if (spec_.command.empty()) {
      FailAt(line, "command", "a pwsim command as a list of words, e.g. [run] (one of: " + known + ")",
             node.IsSequence() ? "an empty list" : Describe(node));
    }
    const std::string& first = spec_.command.front();
    const bool ok = first != "sweep" && std::find(known_commands_.begin(), known_commands_.end(),
                                                  first) != known_commands_.end();
    if (!ok) FailAt(line, "command", "a pwsim command (one of: " + known + ")", "\"" + first + "\"");
  }

  void ReadInputs(YamlMap& root) {
    if (!root.Has("inputs")) return;
    const YAML::Node node = root.Raw("inputs");
    if (!node.IsMap()) FailAt(root.LineOfKey("inputs"), "inputs", "a mapping NAME: FILE", Describe(node));
    for (const auto& item : node) {
      const std::string name = item.first.Scalar();
      const std::string field = "inputs." + name;
      const int line = LineOf(item.first);
      if (!IsIdentifier(name) || IsBuiltin(name)) {
        FailAt(line, field, "an input name (letters, digits, '_'; not out, index or id)", "\"" + name + "\"");
      }
      if (!item.second.IsScalar() || item.second.Scalar().empty()) {
        FailAt(line, field, "the path of a YAML file", Describe(item.second));
      }
      const fs::path path = (base_ / item.second.Scalar()).lexically_normal();
      if (!fs::is_regular_file(path)) {
        FailAt(line, field, "an existing YAML file (relative to the sweep file)",
               "\"" + item.second.Scalar() + "\" (" + path.string() + " not found)");
      }
      const YamlDocument input = LoadYamlFile(path);  // syntax errors name that file
      if (!input.root.IsMap()) FailAt(line, field, "a YAML file holding a mapping", path.string());
      spec_.inputs[name] = path;
      spec_.input_lines[name] = line;
      input_roots_[name] = input.root;
    }
  }

  void ReadArguments(YamlMap& root) {
    if (!root.Has("arguments")) return;
    const YAML::Node node = root.Sequence("arguments");
    for (std::size_t i = 0; i < node.size(); ++i) {
      if (!node[i].IsScalar()) {
        FailAt(LineOf(node[i]), "arguments[" + std::to_string(i) + "]", "a word", Describe(node[i]));
      }
      spec_.arguments.push_back(AbsolutiseIfPath(node[i].Scalar(), base_));
      spec_.argument_lines.push_back(LineOf(node[i]));
    }
  }

  bool IsBuiltin(const std::string& name) const {
    const auto& builtins = BuiltinPlaceholders();
    return std::find(builtins.begin(), builtins.end(), name) != builtins.end();
  }

  Variable ParseVariable(const std::string& key, const std::string& field, int line) {
    Variable variable;
    variable.key = key;
    variable.line = line;
    const std::vector<std::string> parts = SplitDots(key);
    std::string inputs;
    for (const auto& [name, path] : spec_.inputs) inputs += (inputs.empty() ? "" : ", ") + name;
    if (parts.size() == 1) {
      if (!IsIdentifier(key) || IsBuiltin(key) || spec_.inputs.count(key) > 0) {
        FailAt(line, field,
               "a placeholder name (letters, digits, '_'; not out, index, id or an input) or "
               "INPUT.key.path with INPUT one of: " + (inputs.empty() ? "(no inputs)" : inputs),
               "\"" + key + "\"");
      }
      return variable;
    }
    if (spec_.inputs.count(parts[0]) == 0) {
      FailAt(line, field, "INPUT.key.path with INPUT one of the inputs: " +
                              (inputs.empty() ? "(no inputs declared)" : inputs),
             "\"" + key + "\"");
    }
    for (const std::string& part : parts) {
      if (part.empty()) FailAt(line, field, "a dotted key without empty parts", "\"" + key + "\"");
    }
    variable.input = parts[0];
    variable.path.assign(parts.begin() + 1, parts.end());
    // the parent of the key must exist in the input: a typo is caught here, not on the cluster
    YAML::Node node = YAML::Clone(input_roots_.at(variable.input));
    std::string walked = variable.input;
    for (std::size_t i = 0; i + 1 < variable.path.size(); ++i) {
      const std::string& part = variable.path[i];
      YAML::Node next;
      if (node.IsMap()) {
        next = node[part];
      } else if (node.IsSequence()) {
        std::size_t index = 0;
        try {
          index = std::stoul(part);
        } catch (const std::exception&) {
          FailAt(line, field, "a list index at '" + walked + "." + part + "' (" + walked + " is a list)",
                 "\"" + part + "\"");
        }
        if (index < node.size()) next = node[index];
      }
      if (!next.IsDefined() || !(next.IsMap() || next.IsSequence())) {
        FailAt(line, field,
               "a key whose parent '" + walked + "." + part + "' is a mapping or list in " +
                   spec_.inputs.at(variable.input).string(),
               next.IsDefined() ? Describe(next) : "no such key");
      }
      node.reset(next);
      walked += "." + part;
    }
    if (node.IsSequence()) {
      const std::string& last = variable.path.back();
      const bool number = !last.empty() && std::all_of(last.begin(), last.end(), [](char c) { return c >= '0' && c <= '9'; });
      if (!number || std::stoul(last) >= node.size()) {
        FailAt(line, field, "an index below " + std::to_string(node.size()) + " of the list '" + walked + "'",
               "\"" + last + "\"");
      }
    }
    return variable;
  }

  Value MakeValue(const YAML::Node& node, bool placeholder, const std::string& field) {
    if (placeholder && !node.IsScalar()) {
      FailAt(LineOf(node), field, "a single value (a placeholder is one word)", Describe(node));
    }
    if (!node.IsDefined() || node.IsNull()) FailAt(LineOf(node), field, "a value", "nothing");
    Value value;
    value.line = LineOf(node);
    if (node.IsScalar()) {
      const std::string text = AbsolutiseIfPath(node.Scalar(), base_);
      value.node = text == node.Scalar() ? YAML::Clone(node) : YAML::Node(text);
      value.text = text;
    } else {
      value.node = YAML::Clone(node);
      value.text = FlowText(node);
    }
    return value;
  }

  std::vector<Value> ReadValues(const YAML::Node& node, const Variable& variable,
                                const std::string& field) {
    const bool placeholder = variable.input.empty();
    std::vector<Value> values;
    if (node.IsSequence()) {
      for (std::size_t i = 0; i < node.size(); ++i) {
        values.push_back(MakeValue(node[i], placeholder, field + "[" + std::to_string(i) + "]"));
      }
    } else if (node.IsMap() && node["glob"]) {
      if (!placeholder) FailAt(LineOf(node), field, "a list of values (glob: is for placeholders)", "glob:");
      YamlMap map(node, spec_.file, field);
      const std::string pattern = map.String("glob");
      map.Finish();
      const fs::path full = fs::path(pattern).is_absolute() ? fs::path(pattern) : base_ / pattern;
      glob_t matches{};
      const int status = ::glob(full.c_str(), 0, nullptr, &matches);
      for (std::size_t i = 0; status == 0 && i < matches.gl_pathc; ++i) {
        Value value;
        value.text = fs::path(matches.gl_pathv[i]).lexically_normal().string();
        value.node = YAML::Node(value.text);
        value.line = LineOf(node);
        values.push_back(value);
      }
      ::globfree(&matches);
      if (values.empty()) {
        FailAt(LineOf(node), field + ".glob", "a pattern matching at least one path",
               "\"" + pattern + "\" (nothing matches " + full.string() + ")");
      }
    } else if (node.IsMap()) {
      YamlMap map(node, spec_.file, field);
      const int from = map.Integer("from", -1000000000, 1000000000);
      const int to = map.Integer("to", from, 1000000000);
      const int step = map.IntegerOr("step", 1, 1, 1000000000);
      map.Finish();
      if ((static_cast<long long>(to) - from) / step + 1 > static_cast<long long>(kMaxTasks)) {
        FailAt(LineOf(node), field, "at most " + std::to_string(kMaxTasks) + " values", "more");
      }
      for (long long v = from; v <= to; v += step) {
        Value value;
        value.text = std::to_string(v);
        value.node = YAML::Node(value.text);
        value.line = LineOf(node);
        values.push_back(value);
      }
    } else {
      FailAt(LineOf(node), field,
             "a list of values, {from: A, to: B, step: S} of integers or {glob: PATTERN}",
             Describe(node));
    }
    if (values.empty()) FailAt(LineOf(node), field, "at least one value", "an empty list");
    return values;
  }

  void CheckNew(const Variable& variable, const std::string& field) {
    if (!seen_.insert(variable.key).second) {
      FailAt(variable.line, field, "each variable once (in grid:, list: or set:)",
             "\"" + variable.key + "\" again");
    }
  }

  void ReadSet(YamlMap& root) {
    const YAML::Node node = root.Raw("set");
    if (!node.IsMap()) FailAt(root.LineOfKey("set"), "set", "a mapping KEY: VALUE", Describe(node));
    for (const auto& item : node) {
      const std::string key = item.first.Scalar();
      const std::string field = "set." + key;
      Override entry;
      entry.target = ParseVariable(key, field, LineOf(item.first));
      if (entry.target.input.empty()) {
        FailAt(entry.target.line, field, "INPUT.key.path (set: overrides input files)", "\"" + key + "\"");
      }
      CheckNew(entry.target, field);
      entry.value = MakeValue(item.second, false, field);
      spec_.set.push_back(entry);
    }
  }

  void ReadGrid(YamlMap& root) {
    const YAML::Node node = root.Raw("grid");
    if (!node.IsMap() || node.size() == 0) {
      FailAt(root.LineOfKey("grid"), "grid", "a mapping KEY: [values...]", Describe(node));
    }
    for (const auto& item : node) {
      const std::string key = item.first.Scalar();
      const std::string field = "grid." + key;
      Variable variable = ParseVariable(key, field, LineOf(item.first));
      CheckNew(variable, field);
      spec_.grid_values.push_back(ReadValues(item.second, variable, field));
      spec_.grid_variables.push_back(variable);
    }
  }

  void ReadList(YamlMap& root) {
    const YAML::Node node = root.Sequence("list");
    if (node.size() == 0) FailAt(root.LineOfKey("list"), "list", "at least one entry", "an empty list");
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string field = "list[" + std::to_string(i) + "]";
      const YAML::Node entry = node[i];
      if (!entry.IsMap() || entry.size() == 0) {
        FailAt(LineOf(entry), field, "a mapping KEY: VALUE", Describe(entry));
      }
      std::vector<std::string> keys;
      for (const auto& item : entry) keys.push_back(item.first.Scalar());
      if (i == 0) {
        for (const auto& item : entry) {
          const std::string key = item.first.Scalar();
          Variable variable = ParseVariable(key, field + "." + key, LineOf(item.first));
          CheckNew(variable, field + "." + key);
          spec_.list_variables.push_back(variable);
        }
      }
      std::vector<std::string> expected;
      for (const Variable& v : spec_.list_variables) expected.push_back(v.key);
      std::vector<std::string> sorted_keys = keys, sorted_expected = expected;
      std::sort(sorted_keys.begin(), sorted_keys.end());
      std::sort(sorted_expected.begin(), sorted_expected.end());
      if (sorted_keys != sorted_expected) {
        auto join = [](const std::vector<std::string>& words) {
          std::string text;
          for (const auto& w : words) text += (text.empty() ? "" : ", ") + w;
          return text;
        };
        FailAt(LineOf(entry), field, "the same keys as list[0] (" + join(expected) + ")", join(keys));
      }
      std::vector<Value> row;
      for (const Variable& variable : spec_.list_variables) {
        row.push_back(MakeValue(entry[variable.key], variable.input.empty(), field + "." + variable.key));
      }
      spec_.list_rows.push_back(row);
    }
  }

  void ReadGather(YamlMap& root) {
    const YAML::Node node = root.Raw("gather");
    if (!node.IsMap() || node.size() == 0) {
      FailAt(root.LineOfKey("gather"), "gather",
             "a mapping NAME: {file: F.json, path: dotted.path} or {file: F.csv, row: {...}, column: C} (at least one field)", Describe(node));
    }
    std::set<std::string> names;
    for (const auto& item : node) {
      GatherField gather;
      gather.name = item.first.Scalar();
      gather.line = LineOf(item.first);
      const std::string field = "gather." + gather.name;
      if (!IsIdentifier(gather.name) || gather.name == "index" || gather.name == "id" ||
          gather.name == "status" || gather.name == "attempts" || seen_.count(gather.name) > 0) {
        FailAt(gather.line, field,
               "a column name (letters, digits, '_'; not index, id, status, attempts or a variable)",
               "\"" + gather.name + "\"");
      }
      if (!item.second.IsMap()) FailAt(gather.line, field, "a mapping {file: F.json, path: a.b}", Describe(item.second));
      YamlMap map(item.second, spec_.file, field, gather.line);
      gather.file = map.String("file");
      if (fs::path(gather.file).is_absolute() || gather.file.find("..") != std::string::npos) {
        map.Fail("file", "a file inside the task's output folder (relative, no '..')", "\"" + gather.file + "\"");
      }
      if (fs::path(gather.file).extension() == ".csv") {
        gather.column = map.String("column");
        if (map.Has("row")) {
          const YAML::Node row = map.Raw("row");
          if (!row.IsMap()) FailAt(map.LineOfKey("row"), field + ".row", "a mapping COLUMN: VALUE", Describe(row));
          for (const auto& cell : row) {
            if (!cell.second.IsScalar()) {
              FailAt(LineOf(cell.first), field + ".row." + cell.first.Scalar(), "one value", Describe(cell.second));
            }
            gather.row.emplace_back(cell.first.Scalar(), cell.second.Scalar());
          }
        }
      } else {
        const std::string path = map.String("path");
        gather.path = SplitDots(path);
        for (const std::string& part : gather.path) {
          if (part.empty()) map.Fail("path", "a dotted path without empty parts", "\"" + path + "\"");
        }
      }
      map.Finish();
      spec_.gather.push_back(gather);
    }
  }

  void ReadSlurm(YamlMap& root) {
    YamlMap slurm = root.Map("slurm");
    SlurmSettings& s = spec_.slurm;
    s.partition = slurm.StringOr("partition", "");
    s.account = slurm.StringOr("account", "");
    s.qos = slurm.StringOr("qos", "");
    s.time = slurm.StringOr("time", "");
    s.mem = slurm.StringOr("mem", "");
    s.cpus_per_task = slurm.IntegerOr("cpus_per_task", 1, 1, 4096);
    if (slurm.Has("extra")) {
      const YAML::Node extra = slurm.Sequence("extra");
      for (std::size_t i = 0; i < extra.size(); ++i) {
        if (!extra[i].IsScalar() || extra[i].Scalar().rfind("--", 0) != 0) {
          FailAt(LineOf(extra[i]), "slurm.extra[" + std::to_string(i) + "]",
                 "an sbatch option word such as --qos=normal", Describe(extra[i]));
        }
        s.extra.push_back(extra[i].Scalar());
      }
    }
    for (const std::string* word : {&s.partition, &s.account, &s.qos, &s.time, &s.mem}) {
      if (word->find_first_of(" \t\n'\"") != std::string::npos) {
        FailAt(slurm.line(), "slurm", "option values without spaces or quotes", "\"" + *word + "\"");
      }
    }
    slurm.Finish();
  }

  void CheckPlaceholders(YamlMap& root) {
    std::set<std::string> defined(BuiltinPlaceholders().begin(), BuiltinPlaceholders().end());
    std::set<std::string> used;
    for (const auto& [name, path] : spec_.inputs) defined.insert(name);
    for (const Variable& v : spec_.Variables()) {
      if (v.input.empty()) defined.insert(v.key);
    }
    auto check = [&](const std::string& text, int line, const std::string& field) {
      std::vector<std::string> names;
      try {
        names = PlaceholdersIn(text);
      } catch (const std::invalid_argument& error) {
        FailAt(line, field, "balanced {placeholders} ({{ for a literal brace)", "\"" + text + "\"");
      }
      for (const std::string& name : names) {
        if (defined.count(name) == 0) {
          std::string list;
          for (const auto& d : defined) list += (list.empty() ? "" : ", ") + d;
          FailAt(line, field, "a placeholder among: " + list, "{" + name + "}");
        }
        used.insert(name);
      }
    };
    for (std::size_t i = 0; i < spec_.arguments.size(); ++i) {
      check(spec_.arguments[i], root.LineOfKey("arguments"), "arguments[" + std::to_string(i) + "]");
    }
    for (const Override& entry : spec_.set) {
      if (entry.value.node.IsScalar()) check(entry.value.text, entry.value.line, "set." + entry.target.key);
    }
    for (const auto& [name, path] : spec_.inputs) {
      if (used.count(name) == 0) {
        FailAt(root.LineOfKey("inputs"), "inputs." + name,
               "an input passed to the command as {" + name + "} in arguments: or set:", "unused");
      }
    }
    for (const Variable& v : spec_.Variables()) {
      if (v.input.empty() && used.count(v.key) == 0) {
        FailAt(v.line, v.key, "a placeholder used as {" + v.key + "} in arguments: or set:", "unused");
      }
    }
  }

  const std::vector<std::string>& known_commands_;
  SweepSpec spec_;
  fs::path base_;
  std::map<std::string, YAML::Node> input_roots_;
  std::set<std::string> seen_;
};

}  // namespace

const std::vector<std::string>& BuiltinPlaceholders() {
  static const std::vector<std::string> names{"out", "index", "id"};
  return names;
}

std::vector<Variable> SweepSpec::Variables() const {
  std::vector<Variable> all = list_variables;
  all.insert(all.end(), grid_variables.begin(), grid_variables.end());
  return all;
}

std::size_t SweepSpec::TaskCount() const {
  std::size_t count = list_rows.empty() ? 1 : list_rows.size();
  for (const auto& values : grid_values) {
    if (values.empty()) return 0;
    if (count > kMaxTasks) return count;
    count *= values.size();
  }
  return count;
}

SweepSpec ReadSweepFile(const fs::path& file, const std::vector<std::string>& known_commands) {
  return Reader(file, known_commands).Read();
}

namespace {

/// Walks `text`, calling `literal(c)` for plain characters and `name(n)` for placeholders.
template <typename Literal, typename Name>
void ScanPlaceholders(const std::string& text, Literal literal, Name name) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '{' && i + 1 < text.size() && text[i + 1] == '{') {
      literal('{');
      ++i;
    } else if (c == '}' && i + 1 < text.size() && text[i + 1] == '}') {
      literal('}');
      ++i;
    } else if (c == '{') {
      const std::size_t end = text.find('}', i);
      if (end == std::string::npos) throw std::invalid_argument("unbalanced '{' in \"" + text + "\"");
      name(text.substr(i + 1, end - i - 1));
      i = end;
    } else if (c == '}') {
      throw std::invalid_argument("unbalanced '}' in \"" + text + "\"");
    } else {
      literal(c);
    }
  }
}

}  // namespace

std::string Substitute(const std::string& text, const std::map<std::string, std::string>& values) {
  std::string out;
  ScanPlaceholders(
      text, [&](char c) { out += c; },
      [&](const std::string& name) {
        const auto it = values.find(name);
        if (it == values.end()) throw std::out_of_range("unknown placeholder {" + name + "}");
        out += it->second;
      });
  return out;
}

std::vector<std::string> PlaceholdersIn(const std::string& text) {
  std::vector<std::string> names;
  ScanPlaceholders(text, [](char) {}, [&](const std::string& name) { names.push_back(name); });
  return names;
}

}  // namespace pwsim::sweep
