#pragma once
// A small declarative command-line parser for the pwsim subcommands. Every option carries its
// unit and default so that `--help` can list them all; unknown options and bad values are
// errors that name the option and what was expected.

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pwsim::app {

/// A usage error: an unknown option, a missing or malformed value, a value out of range. The
/// message names the option. `pwsim` exits with status 2 for it (and 1 for bad input files,
/// InputError, and failures; see app/main.cc for the one transitional exception).
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct OptionSpec {
  std::string name;           ///< without the leading "--"
  std::string value_name;     ///< e.g. "DIR", "N", "WxH"; empty for a flag
  std::string unit;           ///< e.g. "m/s", "-" for none
  std::string default_value;  ///< shown in --help; "" = none
  std::string help;
};

struct CommandSpec {
  std::string name;
  std::string usage;        ///< e.g. "pwsim run [SCENE] [options]"
  std::string summary;      ///< one line
  std::vector<OptionSpec> options;
  std::string positional_help;  ///< describes positional arguments
};

class ParsedArgs {
 public:
  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  std::string Get(const std::string& name) const;  ///< value or the spec's default
  double GetDouble(const std::string& name) const;  ///< a finite number; @throws UsageError
  long long GetInt(const std::string& name) const;  ///< @throws UsageError
  /// The value in [lo, hi]; @throws UsageError naming the option, the range and its unit.
  double GetDouble(const std::string& name, double lo, double hi) const;
  long long GetInt(const std::string& name, long long lo, long long hi) const;
  bool Flag(const std::string& name) const { return Has(name); }
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  friend ParsedArgs Parse(const CommandSpec&, const std::vector<std::string>&);
  const CommandSpec* spec_{nullptr};
  std::map<std::string, std::string> values_;
  std::vector<std::string> positional_;
};

/// Parses `args` (after the subcommand name). "--help" is handled by the caller via WantsHelp.
/// @throws UsageError for unknown options or missing values.
ParsedArgs Parse(const CommandSpec& spec, const std::vector<std::string>& args);
bool WantsHelp(const std::vector<std::string>& args);
std::string HelpText(const CommandSpec& spec);

}  // namespace pwsim::app
