// pwsim car-checks [--vehicle FILE] [--out DIR]: the car model's checks against closed forms
// (understeer gradient, 0-100 km/h, energy balance, stall, locked-clutch ratios) as figures and
// DIR/car_checks.json. Wiring only: the checks are in report/car_checks.

#include <filesystem>
#include <iostream>

#include "app/commands.h"
#include "app/output_folder.h"
#include "engine/vehicle/vehicle_params.h"
#include "report/car_checks.h"

namespace pwsim::app {

const CommandSpec& CarChecksSpec() {
  static const CommandSpec spec{
      "car-checks",
      "pwsim car-checks [options]",
      "Check the car model against closed forms; write figures and car_checks.json.",
      {
          {"vehicle", "FILE", "-", "assets/cars/midsize.yaml", "a pwsim-vehicle/1 file"},
          OutOption("car-checks", "car_checks.json, car_*.png"),
      },
      ""};
  return spec;
}

int CarChecksCommand(const ParsedArgs& args) {
  if (!args.positional().empty()) throw UsageError("expected no positional argument");
  std::filesystem::path file = args.Get("vehicle");
  if (!args.Has("vehicle") && !std::filesystem::exists(file)) file = std::filesystem::path(PWSIM_SOURCE_DIR) / file;
  const vehicle::Vehicle car = vehicle::ReadVehicleFile(file);
  const std::filesystem::path out = OutDir(args);
  OutputFolder folder(out, "car-checks");  // what the last command wrote there goes
  const nlohmann::ordered_json r = report::RunCarChecks(car, file, out);
  std::cout << "pwsim car-checks: " << car.name << " (" << file.string() << ")\n"
            << "  understeer gradient " << r["understeer"]["understeer_gradient_measured_radpmps2"].get<double>()
            << " rad/(m/s^2), closed form " << r["understeer"]["understeer_gradient_closed_form_radpmps2"].get<double>()
            << "\n  0-100 km/h " << r["launch"]["zero_to_100_kmh_s"].get<double>() << " s (power bound "
            << r["launch"]["power_bound_s"].get<double>() << " s)\n  energy residual "
            << 100.0 * r["energy"]["residual_fraction"].get<double>() << " % of the engine work\n"
            << "  stall in 5th: " << (r["stall"]["dropped_in_fifth_stalls"].get<bool>() ? "yes" : "no")
            << ", slow release in 1st: " << (r["stall"]["slow_release_in_first_stalls"].get<bool>() ? "stalls" : "no stall")
            << "\n";
  folder.Print(std::cout, "pwsim car-checks");
  return 0;
}

}  // namespace pwsim::app
