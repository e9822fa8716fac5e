// independent_truth_set: writes a trial set in measured-trials.md's format from the
// independent truth simulator (tests/truth/independent_truth.h), with its truth beside the set
// (DIR.truth.yaml). For tests, benchmarks and scripts/confusion-matrix.sh,
// scripts/evaluate-diagnosis.sh.
//
//   independent_truth_set --out DIR [--effects ID[,ID]] [--seed N]
//                         [--strength S] [--form N]           development variants (AddEffect)
//                         [--draw [--noise KIND]]             law-space draw by seed (law_space.h)
//                         [--speeds a,b,..] [--loads a,b,..] [--rate HZ] [--small-angle]
//
// --draw draws each effect's law, parameters and strength and the measurement noise from the
// seed: `independent_truth_set --draw --seed 1003 --effects cushion_compliance --out DIR`
// regenerates evaluation set 1003 of that row bit for bit. --noise forces the noise kind
// (white, lowpass, drift, outliers, mix).

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tests/truth/independent_truth.h"
#include "tests/truth/law_space.h"

namespace {

std::vector<std::string> Split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty() && item != "none") out.push_back(item);
  return out;
}

/// The whole of `text` as a number, or an error naming the option and the expected form.
double Number(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size())
    throw std::invalid_argument(option + ": expected a number, got '" + text + "'");
  return v;
}

std::uint64_t Count(const std::string& option, const std::string& text) {
  const double v = Number(option, text);
  if (v < 0.0 || v != static_cast<double>(static_cast<std::uint64_t>(v)))
    throw std::invalid_argument(option + ": expected a whole number >= 0, got '" + text + "'");
  return static_cast<std::uint64_t>(v);
}

std::vector<double> Numbers(const std::string& option, const std::string& text) {
  std::vector<double> out;
  for (const std::string& s : Split(text)) out.push_back(Number(option, s));
  if (out.empty()) throw std::invalid_argument(option + ": expected a comma-separated list of numbers");
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    pwsim::truth::TruthSetConfig config;
    std::string out;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "--out") out = next();
      else if (arg == "--effects") config.effects = Split(next());
      else if (arg == "--strength") config.strength = Number(arg, next());
      else if (arg == "--form") config.form = static_cast<int>(Number(arg, next()));
      else if (arg == "--seed") config.seed = Count(arg, next());
      else if (arg == "--speeds") config.speeds = Numbers(arg, next());
      else if (arg == "--loads") config.loads = Numbers(arg, next());
      else if (arg == "--rate") config.rate_hz = Number(arg, next());
      else if (arg == "--small-angle") config.small_angle = true;
      else if (arg == "--draw") config.draw_laws = true;
      else if (arg == "--noise") config.noise_kind = next();
      else throw std::invalid_argument("unknown option " + arg);
    }
    if (out.empty()) throw std::invalid_argument("--out DIR is required");
    if (!config.noise_kind.empty() && !config.draw_laws) throw std::invalid_argument("--noise needs --draw");
    if (!(config.rate_hz > 0.0)) throw std::invalid_argument("--rate: expected a rate > 0 Hz");
    const pwsim::truth::TruthSet set = pwsim::truth::SimulateTruthSet(config);
    pwsim::truth::WriteTruthSet(set, out);
    std::printf("%zu trials in %s\n", set.trials.size(), out.c_str());
    for (const std::string& law : set.laws) std::printf("  %s\n", law.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "independent_truth_set: %s\n", e.what());
    return 2;
  }
}
