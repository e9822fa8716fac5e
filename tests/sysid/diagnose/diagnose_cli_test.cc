// End to end: `pwsim generate --effect` writes trial folders with a hidden effect, `pwsim
// diagnose` names it and writes diagnosis.json (pwsim-diagnosis/1) and diagnosis.md; bad input
// fails with a message naming the file and leaves no report behind.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/sysid/cli_support.h"

namespace {

namespace fs = std::filesystem;

/// How each effect's evidence line starts (sysid/diagnose/base_residuals.cc, EvidenceLine).
const std::map<std::string, std::string> kSignature{
    {"wheel_radius", "residual at the terrain breakpoints locked in space"},
    {"tyre_compliance", "residual power above 6 Hz"},
    {"cushion_compliance", "obstacle-top Z residual vs drive-wheel load"},
    {"heave_pitch_coupling", "cross-channel: e_Z vs pitch_GM"},
    {"nonlinear_stiffness", "measured/model pitch gain"},
    {"suspension_friction", "residual vs -sign(suspension rate)"},
    {"inertial_pitch", "pitch residual vs a_x r = "},
    {"marker_offset", "Z residual vs model pitch: slope"}};

using pwsim::test::Read;
using pwsim::test::RunPwsim;
using pwsim::test::TrialDirs;

class DiagnoseCliTest : public testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("pwsim_diagnose_cli_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST_F(DiagnoseCliTest, GenerateHiddenEffectThenDiagnose) {
  const fs::path trials = root_ / "trials", out = root_ / "diag";
  ASSERT_EQ(RunPwsim("generate --out " + trials.string() +
                    " --effect inertial_pitch --strength 1 --speeds 0.6,1.2,2.4 --loads 0,100"
                    " --cushion with --mocap-format alternate --seed 9",
                root_ / "gen.log"),
            0)
      << Read(root_ / "gen.log");
  ASSERT_EQ(RunPwsim("diagnose" + TrialDirs(trials) + " --out " + out.string(), root_ / "diag.log"), 0)
      << Read(root_ / "diag.log");
  const nlohmann::json j = nlohmann::json::parse(Read(out / "diagnosis.json"));
  EXPECT_EQ(j["format"], "pwsim-diagnosis/1");
  EXPECT_EQ(j["cause"], "inertial_pitch");
  ASSERT_EQ(j["ranking"].size(), 8u);
  for (const auto& e : j["ranking"]) {
    for (const char* key : {"effect", "evidence", "delta_bic", "heldout_fit_pct", "parameters"}) {
      EXPECT_TRUE(e.contains(key)) << key;
    }
    EXPECT_TRUE(e["heldout_fit_pct"].contains("z"));
    EXPECT_TRUE(e["heldout_fit_pct"].contains("pitch"));
    // Each line: the residual analysis' statistic of that effect's signature, then the gains
    // and the limits this run used (the defaults: 10 % of the selection error, ΔBIC < -10).
    const std::string evidence = e["evidence"].get<std::string>();
    EXPECT_EQ(evidence.rfind(kSignature.at(e["effect"].get<std::string>()), 0), 0u) << evidence;
    EXPECT_NE(evidence.find("(earns at ≥ 10 % and ΔBIC < -10)"), std::string::npos) << evidence;
  }
  ASSERT_EQ(j["ranking"][0]["effect"], "inertial_pitch");
  // The hidden inertial torque shows in its own statistic: the pitch residual correlates with
  // a_x (about 0.6 on the independent truth's inertial sets, 0.00 on its no-effect set).
  const std::string inertial = j["ranking"][0]["evidence"].get<std::string>();
  const std::string r_key = "pitch residual vs a_x r = ";
  ASSERT_EQ(inertial.rfind(r_key, 0), 0u) << inertial;
  EXPECT_GT(std::stod(inertial.substr(r_key.size())), 0.3) << inertial;
  // The truth (same-model generator): both centres of mass at d_CM = 0.43 m.
  EXPECT_NEAR(j.at("ranking").at(0).at("parameters").at("cm_lever_m").get<double>(), 0.43, 0.08);
  EXPECT_NEAR(j.at("ranking").at(0).at("parameters").at("load_cm_lever_m").get<double>(), 0.43, 0.08);
  for (const char* model : {"base", "extended"}) {
    EXPECT_TRUE(j["heldout_fit_pct"][model]["z"].is_number());
    EXPECT_TRUE(j["heldout_fit_pct"][model]["pitch"].is_number());
  }
  EXPECT_GT(j["heldout_fit_pct"]["extended"]["pitch"].get<double>(),
            j["heldout_fit_pct"]["base"]["pitch"].get<double>() + 1.0);
  ASSERT_EQ(j["heldout_trials"].size(), 2u);  // speed 1.2 m/s × 2 loads
  EXPECT_EQ(j["heldout_trials"][0], "v1.20_m0_cushion_r1");
  const std::string md = Read(out / "diagnosis.md");
  EXPECT_NE(md.find("cause: **inertial_pitch**"), std::string::npos);
  // The additions of measured-trials.md: verdict, causes in order, noise floor.
  EXPECT_TRUE(j["verdict"] == "explained" || j["verdict"] == "partly_explained") << j["verdict"];
  ASSERT_GE(j["causes"].size(), 1u);
  EXPECT_EQ(j["causes"][0]["effect"], "inertial_pitch");
  EXPECT_GT(j["causes"][0]["heldout_gain_pct"].get<double>(), 50.0);
  // Additions of docs/diagnosis.md: confirmed by the report trials, and the verdict's inputs.
  EXPECT_TRUE(j["causes"][0]["confirmed"].get<bool>());
  EXPECT_GT(j["causes"][0]["heldout_gain_lower_pct"].get<double>(), 0.0);
  EXPECT_EQ(j["verdict_inputs"]["limits"]["rho_max"].get<double>(), 0.75);
  EXPECT_GT(j["verdict_inputs"]["noise"]["z"]["sigma"].get<double>(), 0.0);
  EXPECT_FALSE(j["verdict_inputs"]["base"]["noise_like"].get<bool>());
  for (const char* ch : {"z", "pitch"}) {
    EXPECT_GE(j["noise_floor_fit_pct"][ch].get<double>(), j["heldout_fit_pct"]["extended"][ch].get<double>() - 1.0);
    EXPECT_LT(j["noise_floor_fit_pct"][ch].get<double>(), 100.0);
  }
  // One gain wherever it appears (diagnose.h): the interval holds the estimate, and diagnosis.md
  // and the console print the JSON's figure for the cause found and for each ranking entry.
  const std::string console = Read(root_ / "diag.log");
  auto fixed1 = [](double v) {
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(1);
    s << v;
    return s.str();
  };
  for (const auto& c : j["causes"]) {
    const double g = c["heldout_gain_pct"].get<double>();
    EXPECT_LE(c["heldout_gain_lower_pct"].get<double>(), g);
    EXPECT_GE(c["heldout_gain_upper_pct"].get<double>(), g);
    EXPECT_TRUE(c["confirmed"].get<bool>());  // `causes` lists the causes found only
    EXPECT_NE(md.find("held-out gain " + fixed1(g) + " % (90 % interval " +
                      fixed1(c["heldout_gain_lower_pct"].get<double>()) + " to "),
              std::string::npos) << md;
    EXPECT_NE(console.find(c["effect"].get<std::string>() + " " + fixed1(g) + " % [" +
                           fixed1(c["heldout_gain_lower_pct"].get<double>()) + ", "),
              std::string::npos) << console;
  }
  for (const auto& e : j["ranking"]) {
    const double g = e["heldout_gain_pct"].get<double>();
    EXPECT_LE(e["heldout_gain_lower_pct"].get<double>(), g) << e["effect"];
    EXPECT_GE(e["heldout_gain_upper_pct"].get<double>(), g) << e["effect"];
    EXPECT_NE(console.find(fixed1(g) + " % [" + fixed1(e["heldout_gain_lower_pct"].get<double>()) + ", " +
                           fixed1(e["heldout_gain_upper_pct"].get<double>()) + "]"),
              std::string::npos) << console;
  }
  // Every candidate's probability of being present, the hidden one the most probable.
  ASSERT_EQ(j["effect_probability"].size(), 8u);
  std::string most;
  double most_p = -1.0;
  for (const auto& [name, p] : j["effect_probability"].items()) {
    EXPECT_GE(p.get<double>(), 0.0);
    EXPECT_LE(p.get<double>(), 1.0);
    if (p.get<double>() > most_p) most = name, most_p = p.get<double>();
  }
  EXPECT_EQ(most, "inertial_pitch");
  EXPECT_NE(md.find("## How likely each effect is"), std::string::npos);
  // The extended model itself: its effects in the order forward selection added them, their
  // fitted parameters, its GM.
  const auto& ext = j["extended_model"];
  ASSERT_EQ(ext["effects"].size(), j["selected_causes"].size());
  for (std::size_t k = 0; k < ext["effects"].size(); ++k)
    EXPECT_EQ(ext["effects"][k], j["selected_causes"][k]["effect"]);
  EXPECT_TRUE(ext["parameters"]["cm_lever_m"].is_number());
  EXPECT_GT(ext["parameters"]["k_theta"].get<double>(), 0.0);
  EXPECT_EQ(ext["gm"]["alpha"].size(), 3u);
  EXPECT_FALSE(ext["gm"]["identified_under_marker_lever"].get<bool>());
  EXPECT_NE(md.find("| # | effect |"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "plots" / "located-residual.png"));
  EXPECT_TRUE(fs::exists(out / "plots" / "residual-v1.20_m0_cushion_r1.png"));
}

TEST_F(DiagnoseCliTest, BadInputFailsWithoutAReport) {
  const fs::path trials = root_ / "trials", out = root_ / "diag";
  ASSERT_EQ(RunPwsim("generate --out " + trials.string() + " --speeds 0.6,1.2 --loads 0 --cushion with",
                root_ / "gen.log"),
            0);
  // A stale complete report from an earlier run must not survive a failed one either: it would
  // look like the result of this run.
  fs::create_directories(out);
  std::ofstream(out / "diagnosis.json") << "{}";
  const fs::path broken = trials / "v1.20_m0_cushion_r1" / "trial.yaml";
  std::string yaml = Read(broken);
  yaml.replace(yaml.find("load_kg:"), 8, "load_kg: heavy #");
  std::ofstream(broken) << yaml;
  EXPECT_EQ(RunPwsim("diagnose" + TrialDirs(trials) + " --out " + out.string(), root_ / "bad.log"), 1);
  const std::string log = Read(root_ / "bad.log");
  EXPECT_NE(log.find("trial.yaml"), std::string::npos) << log;
  EXPECT_NE(log.find("load_kg"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out / "diagnosis.json")) << "a failed run leaves no old report behind";
  // Unknown effect ids and too few trials are usage errors (exit 2).
  EXPECT_EQ(RunPwsim("diagnose" + TrialDirs(trials) + " --effects caster_shimmy --out " + out.string(),
                root_ / "usage.log"),
            2);
  EXPECT_NE(Read(root_ / "usage.log").find("wheel_radius"), std::string::npos);
  EXPECT_EQ(RunPwsim("diagnose " + (trials / "v0.60_m0_cushion_r1").string(), root_ / "one.log"), 2);
  EXPECT_EQ(RunPwsim("diagnose" + TrialDirs(trials) + " --rho-max -1 --out " + out.string(), root_ / "rho.log"), 2);
  EXPECT_NE(Read(root_ / "rho.log").find("--rho-max"), std::string::npos);
}

TEST_F(DiagnoseCliTest, GenerateRefusesBadOptionsNamingThem) {
  const std::string out = " --out " + (root_ / "g").string();
  // A value that is not a number: the option and the expected form are named (not "stod").
  EXPECT_EQ(RunPwsim("generate" + out + " --effect tyre_compliance --effect-params caster_tyre_period_s=soft",
                     root_ / "p.log"),
            2);
  const std::string p = Read(root_ / "p.log");
  EXPECT_NE(p.find("--effect-params"), std::string::npos) << p;
  EXPECT_NE(p.find("NAME=VALUE"), std::string::npos) << p;
  EXPECT_EQ(p.find("stod"), std::string::npos) << p;
  // Out of range: the option, its range and the value given.
  EXPECT_EQ(RunPwsim("generate" + out + " --speeds 0.6,-1", root_ / "s.log"), 2);
  EXPECT_NE(Read(root_ / "s.log").find("--speeds"), std::string::npos);
  EXPECT_EQ(RunPwsim("generate" + out + " --noise-low-pass-hz 80 --rate-hz 100", root_ / "n.log"), 2);
  EXPECT_NE(Read(root_ / "n.log").find("--noise-low-pass-hz"), std::string::npos);
  EXPECT_EQ(RunPwsim("generate" + out + " --drop-fraction 0.7", root_ / "d.log"), 2);
  EXPECT_FALSE(fs::exists(root_ / "g"));
}

}  // namespace
