#include "report/training_study.h"

#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/atomic_file.h"
#include "engine/csv_fields.h"
#include "engine/input_error.h"
#include "report/study_report.h"
#include "study/analysis.h"
#include "study/ratings.h"

namespace pwsim::report {

const std::vector<StudyMetric> kStudyMetrics{
    {"completion_time_s", "/completion_time_s"},
    {"route_deviation_mean_m", "/route_deviation_m/mean"},
    {"contacts", "/contacts/count"},
    {"contact_speed_max_mps", "/contacts/approach_speed_max_mps"},
    {"clearance_min_m", "/clearance/min_m"},
    {"joystick_commands", "/joystick/commands"},
    {"joystick_reversals", "/joystick/reversals"},
    {"head_jerk_rms_mps3", "/head_jerk_mps3/rms"},
    {"near_tips", "/near_tips"},
    {"lift_offs", "/lift_offs/episodes"},
};

std::string PlannedRunsCsv(const study::StudyPlan& plan, const std::string& scene) {
  std::ostringstream csv;
  csv << "participant,trial_index,condition,scene,report\n";
  for (const study::PlanTrial& t : plan.trials) {
    csv << t.participant << ',' << t.trial_index << ',' << t.condition << ',' << scene << ",runs/" << t.participant
        << '_' << t.trial_index << '_' << t.condition << "/report.json\n";
  }
  return csv.str();
}

namespace {


}  // namespace

std::vector<PlannedRun> ReadPlannedRuns(const std::filesystem::path& file) {
  RequireReadableFile(file, "a runs.csv (pwsim study plan --circuit)");
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), 0, "", "a readable runs.csv", "cannot open");
  std::string line;
  int number = 0;
  const std::vector<std::string> header = ReadCsvHeader(in, number, line);
  std::map<std::string, std::size_t> column;
  for (std::size_t i = 0; i < header.size(); ++i) column[header[i]] = i;
  for (const char* need : {"participant", "condition", "report"}) {
    if (!column.count(need))
      throw InputError(file.string(), number, need, "a header with participant, condition and report", line);
  }
  std::vector<PlannedRun> runs;
  while (std::getline(in, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    const std::vector<std::string> f = SplitCsvFields(line);
    if (f.size() != header.size())
      throw InputError(file.string(), number, "", std::to_string(header.size()) + " fields", std::to_string(f.size()));
    PlannedRun run;
    run.participant = f[column["participant"]];
    run.condition = f[column["condition"]];
    const std::string report = f[column["report"]];
    for (auto [name, value] : {std::pair<const char*, const std::string*>{"participant", &run.participant},
                               std::pair<const char*, const std::string*>{"condition", &run.condition},
                               std::pair<const char*, const std::string*>{"report", &report}}) {
      if (value->empty()) throw InputError(file.string(), number, name, "a non-empty name", "empty");
    }
    run.report = std::filesystem::path(report).is_absolute() ? std::filesystem::path(report)
                                                             : file.parent_path() / report;
    run.line = number;
    runs.push_back(run);
  }
  return runs;
}

std::string MetricRatingsCsv(const std::vector<PlannedRun>& runs, const StudyMetric& metric,
                             std::vector<std::string>* skipped) {
  std::ostringstream csv;
  csv << "participant,condition,rating\n";
  csv.precision(17);
  for (const PlannedRun& run : runs) {
    std::ifstream in(run.report);
    const std::string who = run.participant + " " + run.condition + ": ";
    if (!in) {
      skipped->push_back(who + run.report.string() + " missing");
      continue;
    }
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.contains("training")) {
      skipped->push_back(who + run.report.string() + " has no training section");
      continue;
    }
    const nlohmann::json::json_pointer pointer(metric.pointer);
    const nlohmann::json& training = j["training"];
    if (!training.contains(pointer) || !training[pointer].is_number()) {
      skipped->push_back(who + metric.name + " is not a number (e.g. the route was not completed)");
      continue;
    }
    csv << run.participant << ',' << run.condition << ',' << training[pointer].get<double>() << '\n';
  }
  return csv.str();
}

std::vector<std::string> WriteTrainingStudy(const std::filesystem::path& runs_file, const std::filesystem::path& out) {
  const std::vector<PlannedRun> runs = ReadPlannedRuns(runs_file);
  nlohmann::ordered_json summary;
  summary["format"] = "pwsim-training-study/1";
  summary["runs"] = runs_file.string();
  summary["metrics"] = nlohmann::ordered_json::object();
  std::vector<std::string> analysed;
  for (const StudyMetric& metric : kStudyMetrics) {
    std::vector<std::string> skipped;
    const std::string csv = MetricRatingsCsv(runs, metric, &skipped);
    nlohmann::ordered_json entry;
    entry["left_out"] = skipped;
    try {
      const study::Ratings ratings = study::ParseRatings(csv, runs_file.string() + " (" + metric.name + ")");
      const study::StudyAnalysis analysis = study::Analyse(ratings);
      const std::filesystem::path dir = out / metric.name;
      RemoveStudyReport(dir);
      WriteStudyReport(dir, runs_file.string() + " (" + metric.name + ")", ratings, analysis);
      entry["report"] = (std::filesystem::path(metric.name) / "study.json").string();
      analysed.push_back(metric.name);
    } catch (const InputError& e) {  // e.g. fewer than 3 values for a condition
      entry["report"] = nullptr;
      entry["not_analysed"] = e.what();
    }
    summary["metrics"][metric.name] = entry;
  }
  WriteFileAtomically(out / "metrics.json", summary.dump(2) + "\n");
  return analysed;
}

}  // namespace pwsim::report
