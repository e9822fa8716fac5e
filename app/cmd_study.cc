// pwsim study RATINGS.csv --out DIR: the statistics of a perception study (study/analysis.h)
// as DIR/study.json, DIR/study.md and DIR/boxplot.png (shared/spec/study.md).
// pwsim study plan --participants N --conditions A,B --seed S --out DIR: a counterbalanced,
// randomised order per participant (DIR/plan.csv, study/plan.h) and DIR/ratings_template.csv;
// with --circuit SCENE also DIR/runs.csv (a circuit run per trial).
// pwsim study metrics RUNS.csv --out DIR: the training metrics of those runs per participant and
// condition through the same statistics as ratings (report/training_study.h).
// pwsim study skills SHEET.csv... --out DIR: skill score sheets (`pwsim skills`), the total
// percentage and each item's score per participant and session through the same statistics
// (report/skill_sheet.h).

#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "app/commands.h"
#include "app/output_folder.h"
#include "app/progress.h"
#include "engine/atomic_file.h"
#include "report/skill_sheet.h"
#include "report/study_report.h"
#include "report/training_study.h"
#include "study/analysis.h"
#include "study/plan.h"
#include "study/ratings.h"
#include "study/report.h"

namespace pwsim::app {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> SplitNames(const std::string& option, const std::string& text) {
  const std::vector<std::string> names = SplitOptionList(option, text, "name");
  if (names.size() < 2) throw UsageError("option --" + option + ": expected at least two names, e.g. T_r,T_m");
  return names;
}

int PlanCommand(const ParsedArgs& args) {
  if (args.positional().size() != 1) throw UsageError("study plan: unexpected arguments");
  study::PlanOptions options;
  const long long n = args.GetInt("participants");
  if (n < 1 || n > 100000) throw UsageError("option --participants: expected 1..100000");
  options.participants = static_cast<int>(n);
  options.conditions = SplitNames("conditions", args.Has("conditions") ? args.Get("conditions") : "T_r,T_m");
  const long long seed = args.GetInt("seed");
  if (seed < 0) throw UsageError("option --seed: expected a non-negative integer");
  options.seed = static_cast<std::uint64_t>(seed);
  if (const std::string bad = options.Validate(); !bad.empty()) throw UsageError("study plan: " + bad);
  const fs::path out = OutDir(args, "plan");
  OutputFolder folder(out, "study plan");  // what the last command wrote there goes
  const study::StudyPlan plan = study::MakePlan(options);
  WriteFileAtomically(out / "plan.csv", study::PlanCsv(plan));
  WriteFileAtomically(out / "ratings_template.csv", study::RatingsTemplateCsv(plan));
  std::cout << "pwsim study plan: " << options.participants << " participants, "
            << plan.sequences.size() << " counterbalanced sequences (";
  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    std::cout << (s ? "; " : "");
    for (std::size_t c = 0; c < plan.sequences[s].size(); ++c) std::cout << (c ? " " : "") << plan.sequences[s][c];
    std::cout << ": " << plan.participants_per_sequence[s];
  }
  std::cout << ")\n";
  if (args.Has("circuit")) {  // training runs: one circuit run per participant and condition
    WriteFileAtomically(out / "runs.csv", report::PlannedRunsCsv(plan, args.Get("circuit")));
    std::cout << "  runs.csv: a run of " << args.Get("circuit")
              << " per trial (pwsim drive ... --out DIR/runs/P_K_CONDITION, then pwsim study metrics "
              << (out / "runs.csv").string() << ")\n";
  }
  folder.Print(std::cout, "pwsim study plan");
  return 0;
}

}  // namespace

const CommandSpec& StudySpec() {
  static const CommandSpec spec{
      "study",
      "pwsim study RATINGS.csv|SHEET.csv... [--out DIR] [options] | pwsim study plan --participants N [options] | pwsim study metrics RUNS.csv [--out DIR] | pwsim study skills SHEET.csv... [--out DIR]",
      "User-study statistics (seed 000, sec. V): Shapiro-Wilk, Wilcoxon, boxplot; or a study plan (with --circuit: a circuit run per trial); or the training metrics of planned circuit runs through the same statistics.",
      {
          OutOption("study", "study.json, study.md, boxplot.png (plan: default out/study-plan; metrics: out/study-metrics)"),
          {"conditions", "A,B", "-", "", "analysis: the headline pair (default: the first two in the file); plan: the conditions (default T_r,T_m)"},
          {"reported", "TEXT", "-", "", "a published result to check, e.g. test=paired,W=180,p=0.5045"},
          {"participants", "N", "-", "18", "plan: number of participants"},
          {"seed", "S", "-", "1", "plan: seed of the randomised sequence assignment"},
          {"circuit", "SCENE", "-", "", "plan: also DIR/runs.csv, a run of this circuit scene per participant and condition (for pwsim study metrics)"},
          QuietOption(),
      },
      "RATINGS.csv  participant,condition,rating[,order] (shared/spec/study.md); or `plan`; or `metrics RUNS.csv` (participant,condition,report[,...]: report/training_study.h); or `skills SHEET.csv...` (sheet.csv of pwsim skills, one per participant: report/skill_sheet.h)"};
  return spec;
}

namespace {

/// pwsim study metrics RUNS.csv --out DIR: the training metrics of planned circuit runs, per
/// participant and condition, through the ratings' statistics (report/training_study.h).
int MetricsCommand(const ParsedArgs& args) {
  if (args.positional().size() != 2) throw UsageError("study metrics: expected one RUNS.csv");
  const fs::path out = OutDir(args, "metrics");
  OutputFolder folder(out, "study metrics");  // what the last command wrote there goes
  Progress progress("pwsim study metrics", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  progress.Stage("analyse the training metrics");
  const std::vector<std::string> analysed = report::WriteTrainingStudy(args.positional()[1], out);
  progress.Finish();
  std::cout << "pwsim study metrics: " << analysed.size() << " of " << report::kStudyMetrics.size()
            << " training metrics analysed\n";
  folder.Print(std::cout, "pwsim study metrics");
  return 0;
}

/// pwsim study skills SHEET.csv... --out DIR (or pwsim study SHEET.csv...: a score sheet is
/// recognised by its header): skill score sheets per participant and session (the condition)
/// through the ratings' statistics (report/skill_sheet.h). The sheets are the positional
/// arguments from `first` on.
int SkillsStudyCommand(const ParsedArgs& args, std::size_t first) {
  if (args.positional().size() <= first) throw UsageError("study skills: expected SHEET.csv... (sheet.csv of pwsim skills)");
  std::vector<std::string> conditions;
  if (args.Has("conditions")) {
    conditions = SplitNames("conditions", args.Get("conditions"));
    if (conditions.size() != 2) throw UsageError("option --conditions: expected two sessions A,B (e.g. before,after)");
  }
  const std::vector<fs::path> sheets(args.positional().begin() + static_cast<std::ptrdiff_t>(first),
                                     args.positional().end());
  (void)report::ReadSkillSheets(sheets);  // a bad sheet is refused before the output folder is touched
  const fs::path out = OutDir(args, "skills");
  OutputFolder folder(out, "study skills");  // what the last command wrote there goes
  const std::vector<std::string> analysed = report::WriteSkillStudy(sheets, conditions, out);
  std::cout << "pwsim study skills: " << analysed.size() << " measures analysed (the total percentage and the items"
            << " with at least 3 participants in both sessions); " << (out / "skills.json").string() << "\n";
  folder.Print(std::cout, "pwsim study skills");
  return 0;
}

}  // namespace

int StudyCommand(const ParsedArgs& args) {
  if (!args.positional().empty() && args.positional()[0] == "plan") return PlanCommand(args);
  if (!args.positional().empty() && args.positional()[0] == "metrics") return MetricsCommand(args);
  if (!args.positional().empty() && args.positional()[0] == "skills") return SkillsStudyCommand(args, 1);
  if (!args.positional().empty() && report::IsSkillSheet(args.positional()[0])) return SkillsStudyCommand(args, 0);
  if (!args.positional().empty() && !fs::exists(args.positional()[0])) {  // a misspelt sub-command?
    const std::string hint = DidYouMean(args.positional()[0], {"plan", "metrics", "skills"});
    if (!hint.empty()) throw UsageError("no ratings file '" + args.positional()[0] + "'" + hint);
  }
  if (args.positional().size() != 1) throw UsageError("expected one RATINGS.csv (or `plan`)");
  const fs::path ratings_file = args.positional()[0];
  const fs::path out = OutDir(args);
  // Old outputs go first, so a failed run never leaves a previous report looking current.
  OutputFolder folder(out, "study");
  report::RemoveStudyReport(out);

  study::AnalysisOptions options;
  if (args.Has("conditions")) {
    const std::vector<std::string> names = SplitNames("conditions", args.Get("conditions"));
    if (names.size() != 2) throw UsageError("option --conditions: expected two names A,B");
    options.conditions = std::make_pair(names[0], names[1]);
  }
  if (args.Has("reported")) options.reported = study::ParseReported(args.Get("reported"));
  Progress progress("pwsim study", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  progress.Stage("read the ratings");
  const study::Ratings ratings = study::ReadRatings(ratings_file);
  progress.Stage("analyse the ratings");
  const study::StudyAnalysis analysis = study::Analyse(ratings, options);
  progress.Stage("write the report");
  report::WriteStudyReport(out, ratings_file, ratings, analysis);
  progress.Finish();

  const study::PairComparison& main = analysis.pairs[analysis.main_pair];
  std::cout << "pwsim study: " << ratings.rows.size() << " ratings, " << ratings.participants.size()
            << " participants, conditions";
  for (const std::string& c : ratings.conditions) std::cout << " " << c;
  std::cout << "\n";
  if (main.paired)
    std::cout << "  paired " << main.a << " vs " << main.b << ": V = " << main.paired->v << ", p = "
              << main.paired->p << " (" << main.paired->method << ")\n";
  std::cout << "  unpaired " << main.a << " vs " << main.b << ": W = " << main.unpaired.w << ", p = "
            << main.unpaired.p << " (" << main.unpaired.method << ")\n";
  for (const std::string& note : analysis.notes) std::cout << "  note: " << note << "\n";
  folder.Print(std::cout, "pwsim study");
  return 0;
}

}  // namespace pwsim::app
