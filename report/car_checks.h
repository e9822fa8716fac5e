#pragma once
// The car model's checks against closed forms and physics, as figures and numbers for
// docs/car.md (`pwsim car-checks --out DIR`). The same checks, with pass/fail bounds, are the
// tests of tests/engine/vehicle/; here they are measured and plotted:
//   understeer   steady-state cornering at 20 m/s, δ - L/R against a_y, with the linear
//                single-track model's line K a_y, K = (m/L)(b/C_f - a/C_r)
//   launch       0-100 km/h with the closed-loop driver shifting at 6000 rpm: speed, engine
//                speed, gear; the time, and the power bound m v²/(2 P_max)
//   energy       work-energy over a launch: engine work against ΔKE + clutch, driveline, tyre,
//                drag and rolling/brake losses
//   stall        clutch dropped in 5th at idle (stalls) and released slowly in 1st (does not)
//   ratios       locked clutch in each gear: engine speed against ω_wheel · i_gear · i_final
// Writes DIR/car_<check>.png (+ .svg, .csv, .gp) and DIR/car_checks.json.

#include <nlohmann/json.hpp>

#include <filesystem>

#include "engine/vehicle/vehicle_params.h"

namespace pwsim::report {

/// Runs every check on `car`; returns the numbers (also written to DIR/car_checks.json).
nlohmann::ordered_json RunCarChecks(const vehicle::Vehicle& car, const std::filesystem::path& vehicle_file,
                                    const std::filesystem::path& out_dir);

}  // namespace pwsim::report
