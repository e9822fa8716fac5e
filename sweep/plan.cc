#include "sweep/plan.h"

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "engine/atomic_file.h"
#include "engine/input_error.h"
#include "engine/number_format.h"

namespace pwsim::sweep {
namespace {

namespace fs = std::filesystem;

/// Every string scalar that contains '/' and names an existing path relative to `base` is made
/// absolute, so the copy in the task folder still finds what the original referred to.
void AbsolutisePaths(YAML::Node node, const fs::path& base) {
  if (node.IsScalar()) {
    const std::string text = node.Scalar();
    if (text.find('/') == std::string::npos || fs::path(text).is_absolute()) return;
    std::error_code error;
    const fs::path resolved = (base / text).lexically_normal();
    if (fs::exists(resolved, error)) node = resolved.string();
    return;
  }
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) AbsolutisePaths(node[i], base);
  } else if (node.IsMap()) {
    for (auto item : node) AbsolutisePaths(item.second, base);
  }
}

/// Sets `value` at `variable.path` in `root` (the parent was checked by the sweep reader).
void SetAt(YAML::Node root, const Variable& variable, const YAML::Node& value,
           const fs::path& sweep_file) {
  YAML::Node node;
  node.reset(root);
  for (std::size_t i = 0; i + 1 < variable.path.size(); ++i) {
    YAML::Node next;
    if (node.IsSequence()) {
      next.reset(node[std::stoul(variable.path[i])]);
    } else {
      next.reset(node[variable.path[i]]);
    }
    if (!next.IsDefined() || !(next.IsMap() || next.IsSequence())) {
      throw InputError(sweep_file.string(), variable.line, variable.key,
                       "a key whose parent exists in the input", "no such parent");
    }
    node.reset(next);
  }
  const std::string& last = variable.path.back();
  if (node.IsSequence()) {
    node[std::stoul(last)] = YAML::Clone(value);
  } else {
    node[last] = YAML::Clone(value);
  }
}

std::string Hex(std::uint64_t value, int digits) {
  static const char* kDigits = "0123456789abcdef";
  std::string text(static_cast<std::size_t>(digits), '0');
  for (int i = digits - 1; i >= 0; --i) {
    text[static_cast<std::size_t>(i)] = kDigits[value & 0xF];
    value >>= 4;
  }
  return text;
}

nlohmann::ordered_json SlurmJson(const SlurmSettings& s) {
  return {{"partition", s.partition}, {"account", s.account}, {"qos", s.qos},
          {"time", s.time},           {"mem", s.mem},         {"cpus_per_task", s.cpus_per_task},
          {"extra", s.extra}};
}

}  // namespace

std::uint64_t Fnv1a64(const std::string& bytes) {
  std::uint64_t hash = 14695981039346656037ULL;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 1099511628211ULL;
  }
  return hash;
}

fs::path TaskDir(const fs::path& dir, std::size_t index) {
  return dir / "tasks" / std::to_string(index);
}

nlohmann::ordered_json ManifestJson(const Manifest& manifest) {
  nlohmann::ordered_json json;
  json["format"] = "pwsim-sweep-manifest/1";
  json["name"] = manifest.name;
  json["sweep_file"] = manifest.sweep_file.string();
  json["command"] = manifest.command;
  json["variables"] = manifest.variables;
  nlohmann::ordered_json gather = nlohmann::ordered_json::array();
  for (const GatherField& g : manifest.gather) {
    std::string path;
    for (const auto& part : g.path) path += (path.empty() ? "" : ".") + part;
    nlohmann::ordered_json entry{{"name", g.name}, {"file", g.file}, {"path", path}};
    if (g.csv()) {
      entry["column"] = g.column;
      nlohmann::ordered_json row = nlohmann::ordered_json::array();
      for (const auto& [key, value] : g.row) row.push_back({key, value});
      entry["row"] = row;
    }
    gather.push_back(entry);
  }
  json["gather"] = gather;
  json["retries"] = manifest.retries;
  json["timeout_s"] = manifest.timeout_s;
  json["slurm"] = SlurmJson(manifest.slurm);
  nlohmann::ordered_json tasks = nlohmann::ordered_json::array();
  for (const Task& task : manifest.tasks) {
    tasks.push_back({{"index", task.index}, {"id", task.id}, {"values", task.values}, {"argv", task.argv}});
  }
  json["tasks"] = tasks;
  return json;
}

namespace {
void PlanTasks(const SweepSpec& spec, const fs::path& dir, const std::vector<Variable>& variables,
               const std::map<std::string, YAML::Node>& originals, const InputCheck& check,
               Manifest& manifest);
}  // namespace

Manifest Plan(const SweepSpec& spec, const fs::path& dir_in, bool force, const InputCheck& check) {
  const fs::path dir = fs::absolute(dir_in).lexically_normal();
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw InputError(dir.string(), 0, "--out", "a folder for the plan", "an existing file");
  }
  if (fs::exists(dir) && !fs::is_empty(dir)) {
    if (!force) {
      throw InputError(dir.string(), 0, "--out", "an empty or new folder (or --force to replace the plan there)",
                       "a folder that is not empty");
    }
    // remove the previous plan: manifest first, so a half-removed folder is never taken as planned
    fs::remove(dir / "manifest.json");
    for (const char* name : {"tasks", "results.csv", "missing.txt", "plots", "slurm", "local", "sweep.yaml"}) {
      fs::remove_all(dir / name);
    }
  }
  const bool created = !fs::exists(dir);
  fs::create_directories(dir);

  Manifest manifest;
  manifest.dir = dir;
  manifest.name = spec.name;
  manifest.sweep_file = spec.file;
  manifest.command = spec.command;
  manifest.gather = spec.gather;
  manifest.retries = spec.retries;
  manifest.timeout_s = spec.timeout_s;
  manifest.slurm = spec.slurm;
  const std::vector<Variable> variables = spec.Variables();
  for (const Variable& v : variables) manifest.variables.push_back(v.key);

  // the originals, with their relative paths made absolute once
  std::map<std::string, YAML::Node> originals;
  for (const auto& [name, path] : spec.inputs) {
    YAML::Node root = YAML::LoadFile(path.string());
    AbsolutisePaths(root, path.parent_path());
    originals[name] = root;
  }

  try {
    PlanTasks(spec, dir, variables, originals, check, manifest);
  } catch (...) {
    fs::remove_all(dir / "tasks");  // a refused plan leaves no task folders behind
    std::error_code error;
    if (created && fs::is_empty(dir, error)) fs::remove(dir, error);  // nor a folder it made
    throw;
  }
  {
    std::ifstream in(spec.file);
    std::stringstream text;
    text << in.rdbuf();
    WriteFileAtomically(dir / "sweep.yaml", text.str());
  }
  WriteFileAtomically(dir / "manifest.json", ManifestJson(manifest).dump(1) + "\n");
  return manifest;
}

namespace {

/// "a.b[2].c" -> "a.b.2.c": an InputError's field in the dotted form of a sweep key path.
std::string DottedField(const std::string& field) {
  std::string out;
  for (char c : field) {
    if (c == '[') {
      out += '.';
    } else if (c != ']') {
      out += c;
    }
  }
  return out;
}

/// Where in the sweep file a value of `input` that its reader refused was written: the
/// variable or set: entry whose key path is the refused field or holds it.
struct Origin {
  std::string field;
  int line{0};
};

Origin OriginOf(const SweepSpec& spec, const std::string& input, const std::string& refused_field,
                const std::vector<Variable>& variables, const std::vector<const Value*>& values,
                std::size_t list_row) {
  const std::string refused = DottedField(refused_field);
  auto covers = [&](const Variable& v) {
    if (v.input != input) return false;
    std::string path;
    for (const std::string& part : v.path) path += (path.empty() ? "" : ".") + part;
    return refused == path || refused.rfind(path + ".", 0) == 0;
  };
  for (std::size_t v = 0; v < variables.size(); ++v) {
    if (!covers(variables[v])) continue;
    const bool listed = v < spec.list_variables.size();
    return {(listed ? "list[" + std::to_string(list_row) + "]." : std::string("grid.")) + variables[v].key,
            values[v]->line};
  }
  for (const Override& entry : spec.set) {
    if (covers(entry.target)) return {"set." + entry.target.key, entry.value.line};
  }
  const auto line = spec.input_lines.find(input);
  return {"inputs." + input, line == spec.input_lines.end() ? 0 : line->second};
}

void PlanTasks(const SweepSpec& spec, const fs::path& dir, const std::vector<Variable>& variables,
               const std::map<std::string, YAML::Node>& originals, const InputCheck& check,
               Manifest& manifest) {
  const std::size_t list_count = spec.list_rows.empty() ? 1 : spec.list_rows.size();
  const std::size_t total = spec.TaskCount();
  std::vector<std::size_t> grid_index(spec.grid_variables.size(), 0);
  std::map<std::string, std::size_t> identities;
  for (std::size_t index = 0; index < total; ++index) {
    // the combination: list entry outermost, last grid variable fastest
    std::size_t rest = index;
    for (std::size_t g = spec.grid_variables.size(); g-- > 0;) {
      grid_index[g] = rest % spec.grid_values[g].size();
      rest /= spec.grid_values[g].size();
    }
    const std::size_t list_row = rest % list_count;
    std::vector<const Value*> values;
    if (!spec.list_rows.empty()) {
      for (const Value& v : spec.list_rows[list_row]) values.push_back(&v);
    }
    for (std::size_t g = 0; g < spec.grid_variables.size(); ++g) {
      values.push_back(&spec.grid_values[g][grid_index[g]]);
    }

    Task task;
    task.index = index;
    std::string identity;
    for (std::size_t v = 0; v < variables.size(); ++v) {
      task.values.push_back(values[v]->text);
      identity += variables[v].key + "=" + values[v]->text + "\n";
    }
    task.id = Hex(Fnv1a64(identity), 12);
    const auto [seen, fresh] = identities.emplace(identity, index);
    if (!fresh) {
      std::string combination = identity;
      for (char& c : combination) c = c == '\n' ? ' ' : c;
      throw InputError(spec.file.string(), values.empty() ? 0 : values.front()->line,
                       spec.list_rows.empty() ? "grid" : "list", "each combination once",
                       "task " + std::to_string(index) + " repeats task " + std::to_string(seen->second) +
                           " (" + combination + ")");
    }

    // placeholders: in arguments relative to the task folder, in inputs relative to inputs/
    std::map<std::string, std::string> in_args{{"out", "out"}, {"index", std::to_string(index)}, {"id", task.id}};
    std::map<std::string, std::string> in_inputs = in_args;
    in_inputs["out"] = "../out";
    for (const auto& [name, path] : spec.inputs) {
      const std::string file = name + path.extension().string();
      in_args[name] = "inputs/" + file;
      in_inputs[name] = file;
    }
    for (std::size_t v = 0; v < variables.size(); ++v) {
      if (variables[v].input.empty()) {
        in_args[variables[v].key] = values[v]->text;
        in_inputs[variables[v].key] = values[v]->text;
      }
    }

    const fs::path task_dir = TaskDir(dir, index);
    fs::create_directories(task_dir);
    for (const auto& [name, path] : spec.inputs) {
      YAML::Node copy = YAML::Clone(originals.at(name));
      for (const Override& entry : spec.set) {
        if (entry.target.input != name) continue;
        YAML::Node value = YAML::Clone(entry.value.node);
        if (value.IsScalar()) value = Substitute(entry.value.text, in_inputs);
        SetAt(copy, entry.target, value, spec.file);
      }
      for (std::size_t v = 0; v < variables.size(); ++v) {
        if (variables[v].input == name) SetAt(copy, variables[v], values[v]->node, spec.file);
      }
      YAML::Emitter out;
      out << copy;
      const fs::path copy_file = task_dir / "inputs" / (name + path.extension().string());
      WriteFileAtomically(copy_file, "# pwsim sweep " + spec.name + ", task " + std::to_string(index) + " (" +
                                         task.id + "): copy of " + path.string() + " with overrides\n" +
                                         out.c_str() + "\n");
      if (!check) continue;
      try {
        check(copy_file);
      } catch (const InputError& error) {
        const Origin origin = OriginOf(spec, name, error.field(), variables, values, list_row);
        std::string where = error.file();
        if (error.line() > 0) where += ":" + std::to_string(error.line());
        throw InputError(spec.file.string(), origin.line, origin.field,
                         error.expected() + " (task " + std::to_string(index) + "'s " + name + ", " + where +
                             ", field '" + error.field() + "', as pwsim " + spec.command.front() + " reads it)",
                         error.got());
      }
    }
    for (const std::string& word : spec.command) task.argv.push_back(word);
    for (const std::string& word : spec.arguments) task.argv.push_back(Substitute(word, in_args));
    manifest.tasks.push_back(task);
  }
}
}  // namespace

Manifest ReadManifest(const fs::path& dir_in) {
  const fs::path dir = fs::absolute(dir_in).lexically_normal();
  const fs::path file = dir / "manifest.json";
  std::ifstream in(file);
  if (!in) {
    throw InputError(file.string(), 0, "(file)", "a sweep plan (run 'pwsim sweep plan SWEEP --out DIR')",
                     "no such file");
  }
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(file.string(), 0, "(document)", "valid JSON", error.what());
  }
  std::string field = "format";
  try {
    if (json.at("format").get<std::string>() != "pwsim-sweep-manifest/1") {
      throw InputError(file.string(), 0, "format", "pwsim-sweep-manifest/1", json.at("format").dump());
    }
    Manifest m;
    m.dir = dir;
    field = "name";
    m.name = json.at("name").get<std::string>();
    field = "sweep_file";
    m.sweep_file = json.at("sweep_file").get<std::string>();
    field = "command";
    m.command = json.at("command").get<std::vector<std::string>>();
    field = "variables";
    m.variables = json.at("variables").get<std::vector<std::string>>();
    field = "gather";
    for (const auto& g : json.at("gather")) {
      GatherField gather;
      gather.name = g.at("name").get<std::string>();
      gather.file = g.at("file").get<std::string>();
      if (g.contains("column")) {
        gather.column = g.at("column").get<std::string>();
        for (const auto& cell : g.at("row")) {
          gather.row.emplace_back(cell.at(0).get<std::string>(), cell.at(1).get<std::string>());
        }
        m.gather.push_back(gather);
        continue;
      }
      std::string part;
      for (char c : g.at("path").get<std::string>() + ".") {
        if (c == '.') {
          gather.path.push_back(part);
          part.clear();
        } else {
          part += c;
        }
      }
      m.gather.push_back(gather);
    }
    field = "retries";
    m.retries = json.at("retries").get<int>();
    field = "timeout_s";
    m.timeout_s = json.at("timeout_s").get<double>();
    field = "slurm";
    const auto& s = json.at("slurm");
    m.slurm.partition = s.at("partition").get<std::string>();
    m.slurm.account = s.at("account").get<std::string>();
    m.slurm.qos = s.at("qos").get<std::string>();
    m.slurm.time = s.at("time").get<std::string>();
    m.slurm.mem = s.at("mem").get<std::string>();
    m.slurm.cpus_per_task = s.at("cpus_per_task").get<int>();
    m.slurm.extra = s.at("extra").get<std::vector<std::string>>();
    field = "tasks";
    for (const auto& t : json.at("tasks")) {
      Task task;
      task.index = t.at("index").get<std::size_t>();
      task.id = t.at("id").get<std::string>();
      task.values = t.at("values").get<std::vector<std::string>>();
      task.argv = t.at("argv").get<std::vector<std::string>>();
      if (task.index != m.tasks.size() || task.values.size() != m.variables.size()) {
        throw InputError(file.string(), 0, "tasks[" + std::to_string(m.tasks.size()) + "]",
                         "tasks numbered from 0 with one value per variable", t.dump());
      }
      m.tasks.push_back(task);
    }
    return m;
  } catch (const nlohmann::json::exception& error) {
    throw InputError(file.string(), 0, field, "the field of a pwsim-sweep-manifest/1", error.what());
  }
}

}  // namespace pwsim::sweep
