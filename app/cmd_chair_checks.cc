// pwsim chair-checks [--chair FILE] [--load KG] [--out DIR]: the full-DoF chair's checks
// against closed forms (steady turn radius, turning on the spot, caster realignment, the pull
// of casters started across, static roll on a cross-slope, load transfer under braking, the
// tip-over grade) as figures and DIR/chair_checks.json. Wiring only: the checks are in
// report/chair_checks.

#include <filesystem>
#include <iostream>
#include <string>

#include "app/commands.h"
#include "app/output_folder.h"
#include "engine/chair.h"
#include "report/chair_checks.h"

namespace pwsim::app {

const CommandSpec& ChairChecksSpec() {
  static const CommandSpec spec{
      "chair-checks",
      "pwsim chair-checks [options]",
      "Check the full-DoF wheelchair model against closed forms; write figures and chair_checks.json.",
      {
          {"chair", "FILE", "-", "assets/chairs/table1_pw6.yaml", "a pwsim-chair/1 file with gm and lm"},
          {"load", "KG", "kg", "100", "occupant mass M_u"},
          OutOption("chair-checks", "chair_checks.json, chair_*.png"),
      },
      ""};
  return spec;
}

int ChairChecksCommand(const ParsedArgs& args) {
  if (!args.positional().empty()) throw UsageError("expected no positional argument");
  std::filesystem::path file = args.Get("chair");
  if (!args.Has("chair") && !std::filesystem::exists(file)) file = std::filesystem::path(PWSIM_SOURCE_DIR) / file;
  const Chair chair = ReadChairFile(file);
  if (!chair.gm || !chair.lm) throw UsageError("--chair: the chair needs identified gm and lm sections");
  const double load = args.GetDouble("load", 0.0, 300.0);
  const std::filesystem::path out = OutDir(args);
  OutputFolder folder(out, "chair-checks");  // what the last command wrote there goes
  const nlohmann::ordered_json r = report::RunChairChecks(chair, file, load, out);
  std::cout << "pwsim chair-checks: " << chair.name << " (" << file.string() << "), " << load << " kg\n"
            << "  steady turns: radius vs v/omega worst " << 100.0 * r["turn"]["worst_relative_difference_radius_vs_v_over_omega"].get<double>()
            << " %, vs set-points " << 100.0 * r["turn"]["worst_relative_difference_radius_vs_setpoints"].get<double>() << " %\n"
            << "  on the spot: axle midpoint drift " << 1000.0 * r["spot"]["axle_midpoint_drift_over_6s_m"].get<double>() << " mm over 6 s\n"
            << "  caster: travel for a factor e " << r["caster"]["travel_for_factor_e_m"].get<double>() << " m (trail "
            << r["caster"]["trail_m"].get<double>() << " m)\n"
            << "  pull with casters across: " << (r["pull"]["pulls_toward_the_casters"].get<bool>() ? "toward the casters" : "NOT toward the casters")
            << ", left " << r["pull"]["heading_after_3s_casters_left_deg"].get<double>() << " deg\n"
            << "  static roll: worst " << r["roll"]["worst_abs_difference_rad"].get<double>() << " rad from the closed form\n"
            << "  braking load transfer: worst " << 100.0 * r["braking"]["worst_relative_difference"].get<double>() << " %\n"
            << "  tip-over grade " << r["tip"]["tip_grade_found"].get<double>() << " (closed form "
            << r["tip"]["tip_grade_closed_form"].get<double>() << ")\n";
  folder.Print(std::cout, "pwsim chair-checks");
  return 0;
}

}  // namespace pwsim::app
