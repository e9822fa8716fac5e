#pragma once
// A small declarative command-line parser for the pwsim subcommands. Every option carries its
// unit and default so that `--help` can list them all; unknown options and bad values are
// errors that name the option and what was expected, with a "did you mean" suggestion for a
// misspelt option or command (optimal-string-alignment edit distance, see Suggest).
//
// One convention across commands:
//   - an option with a value shows "[UNIT; default: VALUE]" in --help (each part only when it
//     has one: paths and names carry no unit); a flag (no value) shows neither, it is off
//     unless given;
//   - every command that writes a folder takes `--out DIR`, default out/COMMAND, or
//     out/COMMAND-SUB for a sub-command that writes other things (OutOption, OutDir);
//   - a usage error is printed once as "pwsim COMMAND: MESSAGE" and exits with status 2.

#include <filesystem>
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
  std::string unit;           ///< e.g. "m/s"; "" or "-" for none (paths, names, counts)
  std::string default_value;  ///< shown in --help; "" = none; ignored for a flag
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
  const CommandSpec* spec() const { return spec_; }

 private:
  friend ParsedArgs Parse(const CommandSpec&, const std::vector<std::string>&);
  const CommandSpec* spec_{nullptr};
  std::map<std::string, std::string> values_;
  std::vector<std::string> positional_;
};

/// Parses `args` (after the subcommand name). "--help" is handled by the caller via WantsHelp.
/// @throws UsageError for unknown options (with a suggestion) or missing values.
ParsedArgs Parse(const CommandSpec& spec, const std::vector<std::string>& args);
bool WantsHelp(const std::vector<std::string>& args);
std::string HelpText(const CommandSpec& spec);

/// Optimal string alignment distance between `a` and `b`: the fewest single-character
/// insertions, deletions, substitutions and transpositions of two adjacent characters
/// (a transposition counts 1, so "vidoe" is 1 from "video").
int EditDistance(const std::string& a, const std::string& b);
/// The candidate `word` was most likely meant as: the unique candidate that `word` is a prefix
/// of, else the nearest by EditDistance when that distance is at most 1 for words of up to 4
/// characters, at most 2 for longer ones (ties: the first in `candidates`); "" when none.
std::string Suggest(const std::string& word, const std::vector<std::string>& candidates);
/// "; did you mean PREFIX+SUGGESTION?" or "" (for appending to an error message).
std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates,
                       const std::string& prefix = "");

/// The default output folder of `command` (and `sub`, a sub-command that writes other things
/// than the command alone): out/COMMAND or out/COMMAND-SUB, relative to the working directory.
std::string DefaultOutDir(const std::string& command, const std::string& sub = "");
/// The `--out DIR` option of `command`, default DefaultOutDir(command); `contents` says what
/// goes there (shown in --help).
OptionSpec OutOption(const std::string& command, const std::string& contents);
/// The output folder: --out DIR when given (non-empty), else DefaultOutDir(command, sub).
/// @throws UsageError for an empty --out.
std::filesystem::path OutDir(const ParsedArgs& args, const std::string& sub = "");

/// "pwsim VERSION (git DESCRIBE, commit HASH)": the project version, and what `git describe`
/// and `git rev-parse HEAD` said when the binary was built ("unknown" outside a git checkout).
std::string VersionText();

/// The items of option `option`'s comma-separated value `text` ("a,b,c"), each non-empty: an
/// empty item is a UsageError naming the option, `item_words` (e.g. "name", "run folder") and
/// the value.
std::vector<std::string> SplitOptionList(const std::string& option, const std::string& text,
                                         const std::string& item_words);

}  // namespace pwsim::app
