#include "app/cli.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "engine/number_format.h"

namespace pwsim::app {
namespace {

const OptionSpec* Find(const CommandSpec& spec, const std::string& name) {
  for (const OptionSpec& option : spec.options) {
    if (option.name == name) return &option;
  }
  return nullptr;
}

}  // namespace

std::string ParsedArgs::Get(const std::string& name) const {
  const auto found = values_.find(name);
  if (found != values_.end()) return found->second;
  const OptionSpec* option = spec_ ? Find(*spec_, name) : nullptr;
  return option ? option->default_value : "";
}

double ParsedArgs::GetDouble(const std::string& name) const {
  const std::string text = Get(name);
  double value = 0.0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(value)) {
    throw UsageError("option --" + name + ": expected a number, got \"" + text + "\"");
  }
  return value;
}

double ParsedArgs::GetDouble(const std::string& name, double lo, double hi) const {
  const double value = GetDouble(name);
  if (!(value >= lo && value <= hi)) {
    const OptionSpec* option = spec_ ? Find(*spec_, name) : nullptr;
    const std::string unit = option && option->unit != "-" ? " " + option->unit : "";
    throw UsageError("option --" + name + ": expected " + FormatDouble(lo) + ".." + FormatDouble(hi) +
                     unit + ", got " + Get(name));
  }
  return value;
}

long long ParsedArgs::GetInt(const std::string& name, long long lo, long long hi) const {
  const long long value = GetInt(name);
  if (value < lo || value > hi) {
    throw UsageError("option --" + name + ": expected an integer in " + std::to_string(lo) + ".." +
                     std::to_string(hi) + ", got " + Get(name));
  }
  return value;
}

long long ParsedArgs::GetInt(const std::string& name) const {
  const std::string text = Get(name);
  long long value = 0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size()) {
    throw UsageError("option --" + name + ": expected an integer, got \"" + text + "\"");
  }
  return value;
}

ParsedArgs Parse(const CommandSpec& spec, const std::vector<std::string>& args) {
  ParsedArgs parsed;
  parsed.spec_ = &spec;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg.rfind("--", 0) != 0 || arg == "--") {
      parsed.positional_.push_back(arg);
      continue;
    }
    std::string name = arg.substr(2);
    std::string value;
    bool inline_value = false;
    if (const auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      inline_value = true;
    }
    const OptionSpec* option = Find(spec, name);
    if (!option) {
      std::vector<std::string> names{"help"};
      for (const OptionSpec& known : spec.options) names.push_back(known.name);
      throw UsageError("unknown option --" + name + DidYouMean(name, names, "--") + " (see pwsim " +
                       spec.name + " --help)");
    }
    if (option->value_name.empty()) {
      if (inline_value) throw UsageError("option --" + name + " takes no value");
      parsed.values_[name] = "1";
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= args.size()) {
        throw UsageError("option --" + name + ": expected a value " + option->value_name);
      }
      value = args[++i];
    }
    parsed.values_[name] = value;
  }
  return parsed;
}

bool WantsHelp(const std::vector<std::string>& args) {
  for (const std::string& arg : args) {
    if (arg == "--help" || arg == "-h") return true;
  }
  return false;
}

std::string HelpText(const CommandSpec& spec) {
  std::string text = "usage: " + spec.usage + "\n\n" + spec.summary + "\n";
  if (!spec.positional_help.empty()) text += "\n" + spec.positional_help + "\n";
  text += "\noptions (a flag is off unless given):\n";
  for (const OptionSpec& option : spec.options) {
    std::string left = "  --" + option.name;
    if (!option.value_name.empty()) left += " " + option.value_name;
    if (left.size() < 26) left.resize(26, ' ');
    text += left + " " + option.help;
    if (!option.value_name.empty()) {  // a flag has neither unit nor default
      std::vector<std::string> notes;
      if (!option.unit.empty() && option.unit != "-") notes.push_back("unit: " + option.unit);
      if (!option.default_value.empty()) notes.push_back("default: " + option.default_value);
      if (!notes.empty()) {
        text += "  [" + notes[0];
        for (std::size_t i = 1; i < notes.size(); ++i) text += "; " + notes[i];
        text += "]";
      }
    }
    text += "\n";
  }
  text += "  --help                   show this help\n";
  return text;
}

int EditDistance(const std::string& a, const std::string& b) {
  // d[i][j]: distance between the first i characters of a and the first j of b.
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[n][m];
}

std::string Suggest(const std::string& word, const std::vector<std::string>& candidates) {
  if (word.empty()) return "";
  std::vector<const std::string*> prefixed;
  for (const std::string& candidate : candidates) {
    if (candidate.size() > word.size() && candidate.compare(0, word.size(), word) == 0) {
      prefixed.push_back(&candidate);
    }
  }
  if (prefixed.size() == 1) return *prefixed.front();
  const int limit = word.size() <= 4 ? 1 : 2;
  const std::string* best = nullptr;
  int best_distance = limit + 1;
  for (const std::string& candidate : candidates) {
    const int distance = EditDistance(word, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = &candidate;
    }
  }
  return best ? *best : "";
}

std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates,
                       const std::string& prefix) {
  const std::string suggestion = Suggest(word, candidates);
  return suggestion.empty() ? "" : "; did you mean " + prefix + suggestion + "?";
}

std::string DefaultOutDir(const std::string& command, const std::string& sub) {
  return "out/" + command + (sub.empty() ? "" : "-" + sub);
}

OptionSpec OutOption(const std::string& command, const std::string& contents) {
  return {"out", "DIR", "", DefaultOutDir(command), "output folder: " + contents};
}

std::filesystem::path OutDir(const ParsedArgs& args, const std::string& sub) {
  if (args.Has("out")) {
    const std::string dir = args.Get("out");
    if (dir.empty()) throw UsageError("option --out: expected a folder, got an empty value");
    return dir;
  }
  return DefaultOutDir(args.spec() ? args.spec()->name : "pwsim", sub);
}

std::vector<std::string> SplitOptionList(const std::string& option, const std::string& text,
                                         const std::string& item_words) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.empty()) throw UsageError("option --" + option + ": empty " + item_words + " in \"" + text + "\"");
    items.push_back(item);
  }
  return items;
}

}  // namespace pwsim::app
