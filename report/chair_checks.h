#pragma once
// The full-DoF chair's checks against closed forms, as figures and numbers
// (`pwsim chair-checks --out DIR`). The same checks, with pass/fail bounds, are the tests of
// tests/engine/full_chair_test.cc; here they are measured and plotted:
//   turn      steady turns at several deflections: the path's radius (arc / heading change)
//             against v/ω and against the profile's set-points v*/ω*
//   spot      turning on the spot: drift of the drive-axle midpoint, yaw rate against ω_max
//   caster    realignment after reversing: δ against the kinematic law
//             tan(δ/2) = tan(δ0/2) e^(-s/t), and the travel for a factor e (≈ the trail t)
//   pull      a rear-drive 4-wheel variant of the chair started with its casters across
//             (left, straight, right): heading against time, sign and mirror symmetry
//   roll      static roll on cross-slopes 0-8 %: φ against K_φ (φ - φ_GM) = M g d sin φ
//   braking   load on the front row while braking: against M (g (x_c - x_r) - a_x h) / L
//   tip       tip-over grade of the 4-wheel variant facing uphill: against (x_c - x_r) / h,
//             with anti-tip wheels against (x_c - x_a) / h
// Writes DIR/chair_<check>.png (+ .svg, .plot.csv, .gp) and DIR/chair_checks.json.

#include <nlohmann/json.hpp>

#include <filesystem>

#include "engine/chair.h"

namespace pwsim::report {

/// Runs every check on `chair` (with gm and lm) carrying `load_kg`; returns the numbers (also
/// written to DIR/chair_checks.json).
nlohmann::ordered_json RunChairChecks(const Chair& chair, const std::filesystem::path& chair_file,
                                      double load_kg, const std::filesystem::path& out_dir);

}  // namespace pwsim::report
