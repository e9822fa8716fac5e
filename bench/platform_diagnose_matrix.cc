// Hidden-effect matrix of the axis diagnosis: for every case of tests/sysid/platform/
// hidden_effects.h (one effect of the spec's table each, the command delay, and no effect)
// and seeds 1..N, simulate a recording dealt into training and selection blocks and a report
// recording (`--validate`) with the independent truth (tests/sysid/platform/truth_axis.*),
// diagnose, and tabulate the cause named, the first confirmed one (rows: truth, columns:
// cause) with the verdicts. Prints Markdown; with --cases, one line per case first
// (verdict, every cause with its report gain, uncertainty and confirmation).
// usage: platform_diagnose_matrix [N] [--cases]
#include <chrono>
#include <cstdio>
#include <map>
#include <string>

#include "sysid/platform/axis_diagnose.h"
#include "tests/sysid/platform/hidden_effects.h"

int main(int argc, char** argv) {
  namespace sp = pwsim::sysid::platform;
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 5;
  const bool cases = argc > 2 && std::string(argv[2]) == "--cases";
  std::vector<std::string> columns{"none"};
  for (sp::AxisEffect e : sp::AllAxisEffects()) columns.push_back(sp::AxisEffectId(e));
  std::map<std::string, std::map<std::string, int>> counts;
  std::map<std::string, std::map<std::string, int>> verdicts;
  std::vector<std::string> rows;
  double seconds = 0.0;
  int runs = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    for (const auto& c : pwsim::test::HiddenAxisCases(static_cast<std::uint64_t>(seed))) {
      if (seed == 1) rows.push_back(c.effect);
      auto train = c.params, held = c.params;
      train.duration = 20.0;
      held.duration = 12.0;
      held.seed = c.params.seed + 100;
      const auto a = pwsim::test::SimulateTruthAxis(train);
      const auto b = pwsim::test::SimulateTruthAxis(held);
      const auto t0 = std::chrono::steady_clock::now();
      const sp::AxisDiagnosis d = sp::DiagnoseAxis({a}, {b});
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ++runs;
      counts[c.effect][d.cause]++;
      if (cases) {
        std::printf("seed %d, %s: %s, report %.3f -> %.3f %% (floor %.3f %%)", seed, c.effect.c_str(),
                    pwsim::diagnose::VerdictName(d.verdict), d.heldout_base_pct,
                    d.heldout_extended_pct, d.noise_floor_pct);
        for (const sp::AxisCause& k : d.causes)
          std::printf("; %s sel %.1f %%, report %.1f ± %.1f %%%s", sp::AxisEffectId(k.effect),
                      k.selection_gain_pct, k.heldout_gain_pct, k.heldout_gain_se_pct,
                      k.confirmed ? "" : " (not confirmed)");
        std::printf("\n");
      }
      verdicts[c.effect][pwsim::diagnose::VerdictName(d.verdict)]++;
    }
  }
  std::printf("Hidden-effect matrix: independent truth (tests/sysid/platform/truth_axis.*), %d "
              "seeds, a 20 s recording (training + selection blocks) and a 12 s report "
              "recording each; rows = hidden effect, columns = the first confirmed cause.\n\n"
              "| truth → found |",
              seeds);
  for (const auto& c : columns) std::printf(" %s |", c.c_str());
  std::printf(" verdicts |\n|---|");
  for (std::size_t i = 0; i < columns.size(); ++i) std::printf("---|");
  std::printf("---|\n");
  for (const auto& r : rows) {
    std::printf("| %s |", r.c_str());
    for (const auto& c : columns) std::printf(" %d |", counts[r][c]);
    std::string v;
    for (const auto& [name, n] : verdicts[r]) v += name + " " + std::to_string(n) + ", ";
    if (!v.empty()) v.resize(v.size() - 2);
    std::printf(" %s |\n", v.c_str());
  }
  std::printf("\nDiagnosis time: %.3f s per case (mean of %d, simulation excluded).\n",
              seconds / runs, runs);
  return 0;
}
