// pwsim generate --out DIR [options]: synthetic measured trials in the folder format of
// measured-trials.md (synth/generate.h), from a truth chair and the paper's protocol.

#include <filesystem>
#include <map>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "app/commands.h"
#include "engine/chair.h"
#include "synth/effect_truth_model.h"
#include "synth/generate.h"

namespace pwsim::app {
namespace {

std::vector<double> ParseList(const std::string& option, const std::string& text) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size()) {
      throw UsageError("option --" + option +
                                  ": expected comma-separated numbers, got \"" + text + "\"");
    }
    values.push_back(value);
  }
  if (values.empty()) throw UsageError("option --" + option + ": expected a list");
  return values;
}

}  // namespace

const CommandSpec& GenerateSpec() {
  static const CommandSpec spec{
      "generate",
      "pwsim generate --out DIR [options]",
      "Write synthetic measured trials (paper protocol) in the measured-trials folder format.",
      {
          {"out", "DIR", "-", "out/trials", "output folder: one sub-folder per trial"},
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
          {"drop-fraction", "F", "-", "0", "share of frames where the body is not tracked"},
          {"z-offset-m", "M", "m", "0", "altitude of the tracked origin on the flat floor"},
          {"mocap-format", "FMT", "-", "both", "csv | qtm-6d-tsv | both | alternate"},
          {"body", "NAME", "-", "wheelchair", "6D body name in QTM files"},
          {"prefix", "TEXT", "-", "", "prefix of every trial folder name"},
          {"seed", "N", "-", "1", "random seed (same seed, same files)"},
          {"effect", "ID", "-", "", "hidden effect in the truth (an effect id of measured-trials.md)"},
          {"strength", "S", "-", "1", "strength of the hidden effect (1 = moderate, 0 = off)"},
          {"effect-params", "LIST", "-", "", "NAME=VALUE,... overrides of the hidden effect's parameters"},
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
  config.speeds = ParseList("speeds", args.Get("speeds"));
  config.loads = ParseList("loads", args.Get("loads"));
  const std::string cushion = args.Get("cushion");
  if (cushion != "with" && cushion != "without" && cushion != "both") {
    throw UsageError("option --cushion: expected with, without or both");
  }
  config.with_cushion = cushion != "without";
  config.without_cushion = cushion != "with";
  const long long repeats = args.GetInt("repeats");
  if (repeats < 1 || repeats > 100) throw UsageError("option --repeats: 1..100");
  config.repeats = static_cast<int>(repeats);
  config.accel = args.GetDouble("accel");
  config.rate_hz = args.GetDouble("rate-hz");
  config.rate_max_hz = args.GetDouble("rate-max-hz");
  config.noise_position = args.GetDouble("noise-mm") * 1e-3;
  config.noise_pitch = args.GetDouble("noise-pitch-mrad") * 1e-3;
  config.drop_fraction = args.GetDouble("drop-fraction");
  config.z_offset = args.GetDouble("z-offset-m");
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
    std::map<std::string, double> overrides;
    std::stringstream items(args.Get("effect-params"));
    for (std::string item; std::getline(items, item, ',');) {
      const std::size_t eq = item.find('=');
      if (eq == std::string::npos) {
        throw UsageError("option --effect-params: expected NAME=VALUE, got '" + item + "'");
      }
      overrides[item.substr(0, eq)] = std::stod(item.substr(eq + 1));
    }
    config.truth_model = effects::MakeEffectTruthModel(*effect, strength, config.truth, overrides);
  }

  const TrialSet set = GenerateTrialSet(config);
  const std::filesystem::path out = args.Get("out");
  WriteTrialSet(set, out);
  std::size_t untracked = 0;
  for (const SyntheticTrial& trial : set.trials) {
    untracked += static_cast<std::size_t>(trial.measured.track.untracked_frames);
  }
  std::cout << "pwsim generate: " << set.trials.size() << " trials (truth model '"
            << set.truth_model_id << "', chair '" << set.truth.name << "') in " << out.string()
            << "\n  speeds " << args.Get("speeds") << " m/s, loads " << args.Get("loads")
            << " kg, cushion " << cushion << ", repeats " << repeats << ", mocap "
            << args.Get("mocap-format") << ", " << untracked << " untracked frames\n";
  return 0;
}

}  // namespace pwsim::app
