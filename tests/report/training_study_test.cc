// Training metrics through the study's statistics (report/training_study.h): runs.csv of a
// plan, the metrics of each run's report.json per participant and condition, and the same
// signed-rank test as for ratings, checked against a hand-computed Wilcoxon V and exact p.
#include "report/training_study.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "engine/input_error.h"

namespace pwsim::report {
namespace {

namespace fs = std::filesystem;

struct TempDir {
  fs::path path{fs::temp_directory_path() / ("pwsim_training_study_" + std::to_string(::getpid()))};
  TempDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

void WriteReport(const fs::path& file, int commands, const nlohmann::json& completion) {
  fs::create_directories(file.parent_path());
  nlohmann::json j;
  j["training"] = {{"completion_time_s", completion}, {"joystick", {{"commands", commands}}}};
  std::ofstream(file) << j.dump();
}

TEST(TrainingStudy, PlannedRunsCsvHasARunPerTrial) {
  study::PlanOptions options;
  options.participants = 2;
  const std::string csv = PlannedRunsCsv(study::MakePlan(options), "scenes/circuit_course.yaml");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "participant,trial_index,condition,scene,report");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);  // header + 2 participants x 2 conditions
  EXPECT_NE(csv.find("scenes/circuit_course.yaml,runs/P01_1_"), std::string::npos) << csv;
}

// Joystick commands A: 5 6 7 4, B: 4 4 4 8: differences A - B = 1, 2, 3, -4, ranks 1..4, so
// V = 1 + 2 + 3 = 6; of the 16 sign patterns 7 have V >= 6 and 11 have V <= 6: exact two-sided
// p = 2 * 7/16 = 0.875 (R 4.2: wilcox.test(c(5,6,7,4), c(4,4,4,8), paired = TRUE) gives V = 6,
// p-value = 0.875). Completion time is null for P04 in B: P04 is left out of that metric.
TEST(TrainingStudy, MetricsGoThroughTheRatingsStatistics) {
  TempDir dir;
  const int a[] = {5, 6, 7, 4}, b[] = {4, 4, 4, 8};
  std::ofstream runs(dir.path / "runs.csv");
  runs << "participant,trial_index,condition,scene,report\n";
  for (int p = 0; p < 4; ++p) {
    const std::string id = "P0" + std::to_string(p + 1);
    runs << id << ",1,A,x.yaml,runs/" << id << "_A/report.json\n";
    runs << id << ",2,B,x.yaml,runs/" << id << "_B/report.json\n";
    WriteReport(dir.path / "runs" / (id + "_A") / "report.json", a[p], 20.0 + p);
    WriteReport(dir.path / "runs" / (id + "_B") / "report.json", b[p],
                p == 3 ? nlohmann::json(nullptr) : nlohmann::json(21.0 + p));
  }
  runs.close();
  const std::vector<std::string> analysed = WriteTrainingStudy(dir.path / "runs.csv", dir.path / "out");
  ASSERT_EQ(analysed.size(), 2u);  // commands and completion time; the others are absent
  std::ifstream in(dir.path / "out" / "joystick_commands" / "study.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["format"], "pwsim-study/1");
  EXPECT_EQ(s["paired"]["n_pairs"].get<int>(), 4);
  EXPECT_DOUBLE_EQ(s["paired"]["v"].get<double>(), 6.0);
  EXPECT_NEAR(s["paired"]["p"].get<double>(), 0.875, 1e-12);
  std::ifstream m(dir.path / "out" / "metrics.json");
  const nlohmann::json metrics = nlohmann::json::parse(m);
  const auto& left_out = metrics["metrics"]["completion_time_s"]["left_out"];
  ASSERT_EQ(left_out.size(), 1u);
  EXPECT_NE(left_out[0].get<std::string>().find("P04 B"), std::string::npos);
  std::ifstream c(dir.path / "out" / "completion_time_s" / "study.json");
  EXPECT_EQ(nlohmann::json::parse(c)["paired"]["n_pairs"].get<int>(), 3);
  EXPECT_TRUE(metrics["metrics"]["contacts"]["report"].is_null());
}

TEST(TrainingStudy, RunsFileErrorsNameFileLineAndField) {
  TempDir dir;
  std::ofstream(dir.path / "runs.csv") << "participant,condition,report\nP01,,r.json\n";
  try {
    ReadPlannedRuns(dir.path / "runs.csv");
    FAIL() << "accepted an empty condition";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "condition");
  }
  std::ofstream(dir.path / "runs.csv") << "participant,condition\nP01,A\n";
  EXPECT_THROW(ReadPlannedRuns(dir.path / "runs.csv"), InputError);
}

}  // namespace
}  // namespace pwsim::report
