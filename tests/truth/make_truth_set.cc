// independent_truth_set: writes a trial set in measured-trials.md's format from the
// independent truth simulator (tests/truth/independent_truth.h), with its truth beside the set
// (DIR.truth.yaml). For tests, benchmarks and scripts/confusion-matrix.sh.
//
//   independent_truth_set --out DIR [--effects ID[,ID]] [--strength S] [--form N] [--seed N]
//                         [--speeds a,b,..] [--loads a,b,..] [--rate HZ] [--small-angle]

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>

#include "tests/truth/independent_truth.h"

namespace {

std::vector<std::string> Split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty() && item != "none") out.push_back(item);
  return out;
}

std::vector<double> Numbers(const std::string& text) {
  std::vector<double> out;
  for (const std::string& s : Split(text)) out.push_back(std::stod(s));
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
      else if (arg == "--strength") config.strength = std::stod(next());
      else if (arg == "--form") config.form = std::stoi(next());
      else if (arg == "--seed") config.seed = std::stoull(next());
      else if (arg == "--speeds") config.speeds = Numbers(next());
      else if (arg == "--loads") config.loads = Numbers(next());
      else if (arg == "--rate") config.rate_hz = std::stod(next());
      else if (arg == "--small-angle") config.small_angle = true;
      else throw std::invalid_argument("unknown option " + arg);
    }
    if (out.empty()) throw std::invalid_argument("--out DIR is required");
    const pwsim::truth::TruthSet set = pwsim::truth::SimulateTruthSet(config);
    pwsim::truth::WriteTruthSet(set, out);
    std::printf("%zu trials in %s\n", set.trials.size(), out.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "independent_truth_set: %s\n", e.what());
    return 2;
  }
}
