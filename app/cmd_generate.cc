// pwsim generate --out DIR [options]: synthetic measured trials in the folder format of
// measured-trials.md (synth/generate.h), from a truth chair and the paper's protocol.

#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "app/commands.h"
#include "app/output_folder.h"
#include "app/progress.h"
#include "engine/chair.h"
#include "engine/number_format.h"
#include "synth/effect_truth_model.h"
#include "synth/generate.h"

namespace pwsim::app {
namespace {


std::vector<double> ParseList(const std::string& option, const std::string& text) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const std::optional<double> value = ParseFiniteNumber(item);
    if (!value) {
      throw UsageError("option --" + option +
                                  ": expected comma-separated numbers, got \"" + text + "\"");
    }
    values.push_back(*value);
  }
  if (values.empty()) throw UsageError("option --" + option + ": expected a list");
  return values;
}

/// A number option in [lo, hi] (NaN refused), else a usage error naming it, its range and unit.
double RangedDouble(const ParsedArgs& args, const std::string& option, double lo, double hi,
                    const std::string& unit) {
  const double value = args.GetDouble(option);
  if (!(value >= lo && value <= hi)) {
    std::ostringstream message;
    message << "option --" << option << ": expected a number in [" << lo << ", " << hi << "]"
            << (unit.empty() ? "" : " " + unit) << ", got " << args.Get(option);
    throw UsageError(message.str());
  }
  return value;
}

/// Every value of a list option in [lo, hi].
std::vector<double> RangedList(const ParsedArgs& args, const std::string& option, double lo,
                               double hi, const std::string& unit) {
  std::vector<double> values = ParseList(option, args.Get(option));
  for (double v : values) {
    if (!(v >= lo && v <= hi)) {
      std::ostringstream message;
      message << "option --" << option << ": expected numbers in [" << lo << ", " << hi << "] "
              << unit << ", got " << v;
      throw UsageError(message.str());
    }
  }
  return values;
}

/// --effect-params: NAME=VALUE,... with VALUE a number.
std::map<std::string, double> ParseEffectParams(const std::string& text) {
  std::map<std::string, double> overrides;
  std::stringstream items(text);
  for (std::string item; std::getline(items, item, ',');) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw UsageError("option --effect-params: expected NAME=VALUE,... with VALUE a number, got '" +
                       item + "'");
    }
    const std::optional<double> number = ParseFiniteNumber(item.substr(eq + 1));
    if (!number) {
      throw UsageError("option --effect-params: expected NAME=VALUE,... with VALUE a number, got '" +
                       item + "'");
    }
    overrides[item.substr(0, eq)] = *number;
  }
  return overrides;
}

}  // namespace

const CommandSpec& GenerateSpec() {
  static const CommandSpec spec{
      "generate",
      "pwsim generate [--out DIR] [options]",
      "Write synthetic measured trials (paper protocol) in the measured-trials folder format.",
      {
          OutOption("generate", "one sub-folder per trial"),
          {"truth", "CHAIR", "-", "", "truth chair (pwsim-chair/1 with gm and lm); default Table I"},
          {"speeds", "LIST", "m/s", "0.6,1.2,1.8,2.4", "programmed cruise speeds"},
          {"loads", "LIST", "kg", "0,50,100", "loads M_u"},
          {"cushion", "WHICH", "-", "both", "with | without | both (speed cushion on the path)"},
          {"repeats", "N", "-", "1", "repeats of each condition"},
          {"accel", "A", "m/s^2", "0.8", "programmed acceleration and deceleration"},
          {"rate-hz", "HZ", "Hz", "100", "mocap frame rate"},
          {"rate-max-hz", "HZ", "Hz", "0", "if above --rate-hz: a random rate per trial in between"},
          {"noise-mm", "MM", "mm", "0.3", "std of mocap position noise"},
          {"noise-pitch-mrad", "MRAD", "mrad", "0.5", "std of mocap pitch noise"},
          {"noise-low-pass-hz", "HZ", "Hz", "0", "mocap noise through a 2nd-order Butterworth low-pass (0: white)"},
          {"noise-drift", "D", "-", "0", "random-walk drift of the mocap noise, in noise stds after 1 s"},
          {"noise-outliers", "F", "-", "0", "share of frames with an outlier of 10 noise stds"},
          {"drop-fraction", "F", "-", "0", "share of frames where the body is not tracked"},
          {"z-offset-m", "M", "m", "0", "altitude of the tracked origin on the flat floor"},
          {"mocap-format", "FMT", "-", "both", "csv | qtm-6d-tsv | both | alternate"},
          {"body", "NAME", "-", "wheelchair", "6D body name in QTM files"},
          {"prefix", "TEXT", "-", "", "prefix of every trial folder name"},
          {"seed", "N", "-", "1", "random seed (same seed, same files)"},
          {"effect", "ID", "-", "", "hidden effect in the truth (an effect id of measured-trials.md)"},
          {"strength", "S", "-", "1", "strength of the hidden effect (1 = moderate, 0 = off)"},
          {"effect-params", "LIST", "-", "", "NAME=VALUE,... overrides of the hidden effect's parameters"},
          QuietOption(),
      },
      ""};
  return spec;
}

int GenerateCommand(const ParsedArgs& args) {
  if (!args.positional().empty()) {
    throw UsageError("unexpected argument \"" + args.positional()[0] + "\"");
  }
  GenerateConfig config;
  if (args.Has("truth")) {
    config.truth = ReadChairFile(args.Get("truth"));
    if (!config.truth.gm || !config.truth.lm) {
      throw UsageError("option --truth: the chair needs gm and lm");
    }
  }
  config.speeds = RangedList(args, "speeds", 0.05, 4.0, "m/s");
  config.loads = RangedList(args, "loads", 0.0, 300.0, "kg");
  const std::string cushion = args.Get("cushion");
  if (cushion != "with" && cushion != "without" && cushion != "both") {
    throw UsageError("option --cushion: expected with, without or both");
  }
  config.with_cushion = cushion != "without";
  config.without_cushion = cushion != "with";
  const long long repeats = args.GetInt("repeats");
  if (repeats < 1 || repeats > 100) throw UsageError("option --repeats: 1..100");
  config.repeats = static_cast<int>(repeats);
  config.accel = RangedDouble(args, "accel", 0.05, 5.0, "m/s^2");
  config.rate_hz = RangedDouble(args, "rate-hz", 10.0, 2000.0, "Hz");
  config.rate_max_hz = RangedDouble(args, "rate-max-hz", 0.0, 2000.0, "Hz");
  config.noise_position = RangedDouble(args, "noise-mm", 0.0, 100.0, "mm") * 1e-3;
  config.noise_pitch = RangedDouble(args, "noise-pitch-mrad", 0.0, 100.0, "mrad") * 1e-3;
  config.noise_process.sigma = 1.0;  // scaled per channel by the generator
  config.noise_process.low_pass_hz = RangedDouble(args, "noise-low-pass-hz", 0.0, 0.45 * config.rate_hz, "Hz");
  config.noise_process.drift_per_sqrt_s = RangedDouble(args, "noise-drift", 0.0, 100.0, "");
  config.noise_process.outlier_rate = RangedDouble(args, "noise-outliers", 0.0, 0.2, "");
  config.drop_fraction = RangedDouble(args, "drop-fraction", 0.0, 0.49, "");
  config.z_offset = RangedDouble(args, "z-offset-m", -10.0, 10.0, "m");
  config.mocap_format = ParseMocapFormat(args.Get("mocap-format"));
  config.body = args.Get("body");
  config.name_prefix = args.Get("prefix");
  const long long seed = args.GetInt("seed");
  if (seed < 0) throw UsageError("option --seed: expected an integer >= 0");
  config.seed = static_cast<std::uint64_t>(seed);
  if (args.Has("effect")) {  // hidden effect (diagnosis tests): the extended model as truth
    const auto effect = effects::ParseEffect(args.Get("effect"));
    if (!effect) {
      throw UsageError("option --effect: expected one of " + effects::EffectNameList() +
                                  ", got '" + args.Get("effect") + "'");
    }
    const double strength = args.GetDouble("strength");
    if (!(strength >= 0.0 && strength <= 10.0)) {
      throw UsageError("option --strength: expected a number in [0, 10]");
    }
    const std::map<std::string, double> overrides = ParseEffectParams(args.Get("effect-params"));
    config.truth_model = effects::MakeEffectTruthModel(*effect, strength, config.truth, overrides);
  }

  const std::filesystem::path out = OutDir(args);
  Progress progress("pwsim generate", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  OutputFolder folder(out, "generate");  // what the last command wrote there goes
  progress.Stage("simulate the trials");
  const TrialSet set = GenerateTrialSet(config);
  progress.Stage("write the trials", static_cast<int>(set.trials.size()));
  WriteTrialSet(set, out);
  progress.Finish();
  std::size_t untracked = 0;
  for (const SyntheticTrial& trial : set.trials) {
    untracked += static_cast<std::size_t>(trial.measured.track.untracked_frames);
  }
  std::cout << "pwsim generate: " << set.trials.size() << " trials (truth model '"
            << set.truth_model_id << "', chair '" << set.truth.name << "') in " << out.string()
            << "\n  speeds " << args.Get("speeds") << " m/s, loads " << args.Get("loads")
            << " kg, cushion " << cushion << ", repeats " << repeats << ", mocap "
            << args.Get("mocap-format") << ", " << untracked << " untracked frames\n";
  folder.Print(std::cout, "pwsim generate");
  return 0;
}

}  // namespace pwsim::app
