// pwsim chair-checks' numbers and files: the report runs the checks of
// tests/engine/full_chair_test.cc on the Table I chair and writes them; here its JSON is read
// back against the closed forms' bounds and every figure is checked to exist.

#include "report/chair_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace pwsim::report {
namespace {

namespace fs = std::filesystem;

TEST(ChairChecks, NumbersMatchTheClosedFormsAndFiguresAreWritten) {
  const fs::path out = fs::path(PWSIM_BINARY_DIR) / "report_chair_checks";
  fs::remove_all(out);
  const Chair chair = ReadChairFile(fs::path(PWSIM_SOURCE_DIR) / "assets/chairs/table1_pw6.yaml");
  const nlohmann::ordered_json r = RunChairChecks(chair, "table1_pw6.yaml", 100.0, out);
  EXPECT_LT(r["turn"]["worst_relative_difference_radius_vs_v_over_omega"].get<double>(), 0.005);
  EXPECT_LT(r["spot"]["axle_midpoint_drift_over_6s_m"].get<double>(), 1e-3);
  EXPECT_LT(std::abs(r["caster"]["relative_difference_to_trail"].get<double>()), 0.25);
  EXPECT_TRUE(r["pull"]["pulls_toward_the_casters"].get<bool>());
  EXPECT_LT(std::abs(r["pull"]["mirror_asymmetry_deg"].get<double>()), 1e-6);
  EXPECT_LT(r["roll"]["worst_abs_difference_rad"].get<double>(), 1e-6);
  EXPECT_LT(r["braking"]["worst_relative_difference"].get<double>(), 1e-9);
  // the tip-over grade by bisection on the chair's flag against (x_c - x_r)/h, written here:
  // the 4-wheel variant has α = (0.3, 0.7) at x = (0.30, -0.15), so x_c = -0.015, x_r = -0.15
  EXPECT_NEAR(r["tip"]["tip_grade_found"].get<double>(), (-0.015 + 0.15) / chair.cm_height, 1e-9);
  EXPECT_NEAR(r["tip"]["tip_grade_with_anti_tip_found"].get<double>(), (-0.015 + 0.45) / chair.cm_height, 1e-9);
  EXPECT_TRUE(fs::exists(out / "chair_checks.json"));
  for (const char* stem : {"chair_turn", "chair_caster", "chair_pull", "chair_roll", "chair_braking", "chair_tip"}) {
    EXPECT_TRUE(fs::exists(out / (std::string(stem) + ".png"))) << stem;
  }
}

}  // namespace
}  // namespace pwsim::report
