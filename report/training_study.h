#pragma once
// Training metrics in a user study: circuit runs planned per participant and condition
// (`pwsim study plan --circuit SCENE`: DIR/runs.csv) and their metrics compared between
// conditions with the same statistics as ratings (`pwsim study metrics RUNS.csv`).
//
// runs.csv (one row per planned run; the columns in any order, extra columns ignored):
//   participant,trial_index,condition,scene,report
// `report` is the run's report.json (`pwsim drive`) or summary.json (`pwsim run`), relative to
// the folder of runs.csv; its "training" section (report/training_report.h) gives the metrics.
// For each metric of kStudyMetrics a ratings table (participant, condition, value) is built and
// analysed by study::Analyse exactly as ratings are (shared/spec/study.md), into
// OUT/<metric>/study.json, study.md and boxplot.png; OUT/metrics.json lists them. A run whose
// report is missing, or a metric that is null there (completion time of an unfinished run),
// leaves that participant's value out for that metric (the paired test then names them).

#include <filesystem>
#include <string>
#include <vector>

#include "study/plan.h"

namespace pwsim::report {

struct StudyMetric {
  const char* name;     ///< folder and key, e.g. "completion_time_s"
  const char* pointer;  ///< JSON pointer into the "training" section
};
extern const std::vector<StudyMetric> kStudyMetrics;

/// runs.csv of a plan: every planned trial as a run of `scene`, its report at
/// runs/<participant>_<trial_index>_<condition>/report.json.
std::string PlannedRunsCsv(const study::StudyPlan& plan, const std::string& scene);

struct PlannedRun {
  std::string participant, condition;
  std::filesystem::path report;  ///< resolved against the folder of runs.csv
  int line{0};
};

/// @throws InputError naming file, line and field (missing column, wrong field count, empty name).
std::vector<PlannedRun> ReadPlannedRuns(const std::filesystem::path& file);

/// The ratings CSV text (participant,condition,rating) of one metric over the runs; `skipped`
/// gets "participant condition: why" for each run left out.
std::string MetricRatingsCsv(const std::vector<PlannedRun>& runs, const StudyMetric& metric,
                             std::vector<std::string>* skipped);

/// Analyses every metric with at least 3 values per condition into OUT/<metric>/ and writes
/// OUT/metrics.json; returns the metrics analysed.
std::vector<std::string> WriteTrainingStudy(const std::filesystem::path& runs_file, const std::filesystem::path& out);

}  // namespace pwsim::report
