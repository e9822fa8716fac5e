#pragma once
// The hidden-effect cases of the axis diagnosis: one truth configuration per effect of the
// spec's table (plus the command delay and no-effect sets). Shared by the test and by the
// matrix program (bench/platform_diagnose_matrix.cc). Sizes are stated here, in one place.

#include <string>
#include <vector>

#include "tests/sysid/platform/truth_axis.h"

namespace pwsim::test {

struct HiddenCase {
  std::string effect;  ///< the spec's id, or "none"
  TruthAxisParams params;
};

inline std::vector<HiddenCase> HiddenAxisCases(std::uint64_t seed) {
  TruthAxisParams base;
  base.delay_samples = 0;  // the recorded effort acts at its sample instant
  base.seed = seed;
  std::vector<HiddenCase> cases;
  cases.push_back({"none", base});
  TruthAxisParams p = base;
  p.fv_pos = 160;  // viscous 160 / 240 N s/m, Coulomb 19 / 22 N
  p.fv_neg = 240;
  p.fc_pos = 19;
  p.fc_neg = 22;
  cases.push_back({"asymmetric_friction", p});
  p = base;
  p.stribeck_extra = 10;  // breakaway 30 N, Stribeck speed 0.03 m/s
  p.stribeck_speed = 0.03;
  cases.push_back({"stribeck_friction", p});
  p = base;
  p.coulomb_slope = 5.0;  // Coulomb 20 N · (1 + 5/m · (x − 0.12 m)): 8 .. 31 N over the stroke
  cases.push_back({"position_dependent_friction", p});
  p = base;
  p.cogging_amplitude = 4.0;  // 4 N, period 20 mm
  p.cogging_period = 0.02;
  cases.push_back({"cogging", p});
  p = base;
  p.stiffness = 6e5;  // motor 25 kg, load 70 kg, 29 Hz, ζ ≈ 0.3
  p.damping = 2000;
  cases.push_back({"transmission_compliance", p});
  p = base;
  p.stiffness = 1e6;  // 0.1 mm dead band, contact 1e6 N/m, 3000 N s/m
  p.damping = 3000;
  p.backlash_gap = 1e-4;
  cases.push_back({"backlash", p});
  p = base;
  p.delay_samples = 1;  // the EMPS loop's one-sample computation delay
  cases.push_back({"command_delay", p});
  return cases;
}

}  // namespace pwsim::test
