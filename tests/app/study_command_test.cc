// End to end through the built binary: `pwsim study RATINGS.csv` writes study.json, study.md
// and boxplot.png per shared/spec/study.md; bad input is refused with the line and field named
// and leaves no report behind; `pwsim study plan` writes a plan and a ratings template.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/app/pwsim_run.h"

namespace {

namespace fs = std::filesystem;

using Result = pwsim::test::PwsimResult;

fs::path Scratch(const std::string& name) { return pwsim::test::FreshTestFolder("study_command", name); }

/// Runs the built pwsim from the test's working folder, its log in `dir`.
Result Pwsim(const std::string& args, const fs::path& dir) { return pwsim::test::RunPwsim(args, dir, false); }



/// Seed 000's reconstructed study (docs/study.md); the pairing is arbitrary.
void WritePaperRatings(const fs::path& file) {
  const int tm[18] = {1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 3};
  const int tr[18] = {2, 1, 2, 1, 2, 2, 3, 1, 2, 2, 1, 2, 2, 3, 1, 2, 2, 1};
  std::ofstream out(file);
  out << "participant,condition,rating,order\n";
  for (int i = 0; i < 18; ++i) {
    const bool tm_first = i % 2 == 0;
    out << "P" << i + 1 << ",T_m," << tm[i] << "," << (tm_first ? 1 : 2) << "\n";
    out << "P" << i + 1 << ",T_r," << tr[i] << "," << (tm_first ? 2 : 1) << "\n";
  }
}

TEST(StudyCommand, WritesReportJsonAndBoxplot) {
  const fs::path dir = Scratch("paper");
  WritePaperRatings(dir / "ratings.csv");
  const Result r = Pwsim("study " + (dir / "ratings.csv").string() + " --out " + (dir / "out").string() +
                             " --reported test=paired,W=180,p=0.5045", dir);
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(dir / "out" / "study.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["format"], "pwsim-study/1");
  EXPECT_EQ(j["unpaired"]["a"], "T_m");
  EXPECT_EQ(j["unpaired"]["w"], 180.0);
  EXPECT_NEAR(j["unpaired"]["p"].get<double>(), 0.5045, 5e-5);
  EXPECT_EQ(j["paired"]["n_pairs"], 18);
  EXPECT_EQ(j["conditions"]["T_m"]["n"], 18);
  EXPECT_EQ(j["conditions"]["T_r"]["median"], 2.0);
  bool bound_note = false;
  for (const auto& note : j["notes"]) bound_note |= note.get<std::string>().find("[0, 171]") != std::string::npos;
  EXPECT_TRUE(bound_note) << j["notes"].dump(2);
  EXPECT_TRUE(fs::exists(dir / "out" / "study.md"));
  ASSERT_TRUE(fs::exists(dir / "out" / "boxplot.png"));
  EXPECT_GT(fs::file_size(dir / "out" / "boxplot.png"), 1000u);
  EXPECT_NE(r.output.find("W = 180"), std::string::npos) << r.output;
}

TEST(StudyCommand, BadInputNamesLineAndFieldAndLeavesNoReport) {
  const fs::path dir = Scratch("bad");
  WritePaperRatings(dir / "ratings.csv");
  ASSERT_EQ(Pwsim("study " + (dir / "ratings.csv").string() + " --out " + (dir / "out").string(), dir).status, 0);
  ASSERT_TRUE(fs::exists(dir / "out" / "study.json"));
  // a participant with the same condition twice, on line 38
  {
    std::ofstream out(dir / "ratings.csv", std::ios::app);
    out << "P3,T_m,2,3\n";
  }
  const Result r = Pwsim("study " + (dir / "ratings.csv").string() + " --out " + (dir / "out").string(), dir);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("ratings.csv:38: field 'condition'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("first on line 6"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "study.json"));  // the old report is gone, no new one
  EXPECT_FALSE(fs::exists(dir / "out" / "study.md"));
  EXPECT_FALSE(fs::exists(dir / "out" / "boxplot.png"));
  // non-numeric rating
  std::ofstream(dir / "nan.csv") << "participant,condition,rating\nA,x,1\nB,x,2\nC,x,3\nA,y,2\nB,y,three\nC,y,1\n";
  const Result n = Pwsim("study " + (dir / "nan.csv").string() + " --out " + (dir / "out2").string(), dir);
  EXPECT_EQ(n.status, 1);
  EXPECT_NE(n.output.find("nan.csv:6: field 'rating': expected a finite number, got \"three\""), std::string::npos) << n.output;
  EXPECT_FALSE(fs::exists(dir / "out2" / "study.json"));
}

TEST(StudyCommand, PlanWritesCounterbalancedOrderAndTemplate) {
  const fs::path dir = Scratch("plan");
  const Result r = Pwsim("study plan --participants 6 --conditions T_r,T_m --seed 3 --out " + dir.string(), dir);
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream plan(dir / "plan.csv");
  std::string line;
  std::getline(plan, line);
  EXPECT_EQ(line, "participant,trial_index,condition,sequence");
  int rows = 0, tr_first = 0;
  while (std::getline(plan, line)) {
    ++rows;
    if (line.find(",1,T_r,") != std::string::npos) ++tr_first;
  }
  EXPECT_EQ(rows, 12);
  EXPECT_EQ(tr_first, 3);
  EXPECT_TRUE(fs::exists(dir / "ratings_template.csv"));
  // the unfilled template is not a ratings file
  const Result t = Pwsim("study " + (dir / "ratings_template.csv").string() + " --out " + (dir / "o").string(), dir);
  EXPECT_EQ(t.status, 1);
  EXPECT_NE(t.output.find(":3: field 'rating'"), std::string::npos) << t.output;
}

// Tests the training runs of a plan through the binary: runs.csv has a circuit run per trial, and
// `study metrics` on it before any run is made analyses nothing and names all 12 runs as left out.
TEST(StudyCommand, PlanWithACircuitListsRunsAndMetricsNamesWhatIsMissing) {
  const fs::path dir = Scratch("plan_circuit");
  const Result r = Pwsim("study plan --participants 6 --conditions A,B --seed 3 --circuit scenes/circuit_course.yaml --out " +
                             dir.string(), dir);
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream runs(dir / "runs.csv");
  std::string line;
  std::getline(runs, line);
  EXPECT_EQ(line, "participant,trial_index,condition,scene,report");
  int rows = 0;
  while (std::getline(runs, line)) rows += line.find(",scenes/circuit_course.yaml,runs/") != std::string::npos;
  EXPECT_EQ(rows, 12);
  const Result m = Pwsim("study metrics " + (dir / "runs.csv").string() + " --out " + (dir / "m").string(), dir);
  ASSERT_EQ(m.status, 0) << m.output;
  std::ifstream in(dir / "m" / "metrics.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["format"], "pwsim-training-study/1");
  for (const auto& [name, entry] : j["metrics"].items()) {
    EXPECT_TRUE(entry["report"].is_null()) << name;
    EXPECT_EQ(entry["left_out"].size(), 12u) << name;
  }
}

}  // namespace
