#include "app/cli.h"

#include <charconv>
#include <cmath>
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
      throw UsageError("pwsim " + spec.name + ": unknown option --" + name +
                                  " (see pwsim " + spec.name + " --help)");
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
  text += "\noptions:\n";
  for (const OptionSpec& option : spec.options) {
    std::string left = "  --" + option.name;
    if (!option.value_name.empty()) left += " " + option.value_name;
    if (left.size() < 26) left.resize(26, ' ');
    text += left + " " + option.help;
    text += "  [unit: " + (option.unit.empty() ? std::string("-") : option.unit);
    text += "; default: " + (option.default_value.empty() ? std::string("none") : option.default_value) + "]\n";
  }
  text += "  --help                   show this help\n";
  return text;
}

}  // namespace pwsim::app
