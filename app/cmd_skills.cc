// pwsim skills RUN_DIR... [--session NAME] [--participant NAME] --out DIR
// pwsim skills --before DIR,DIR,... --after DIR,DIR,... [--participant NAME] --out DIR
// The skill score sheet (report/skill_sheet.h): the score.json of every run of a skill item
// (`pwsim run scenes/skills/X.yaml` or `pwsim drive` on one), attempt by attempt, as
// DIR/sheet.csv, DIR/sheet.md, DIR/items/<item>.png and, with --before and --after, the
// comparison of the two sessions (DIR/comparison.csv and its table in sheet.md). Wiring only.

#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/commands.h"
#include "app/output_folder.h"
#include "app/progress.h"
#include "report/skill_sheet.h"

namespace pwsim::app {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> SplitRuns(const std::string& option, const std::string& text) {
  std::vector<fs::path> runs;
  for (const std::string& item : SplitOptionList(option, text, "run folder")) runs.emplace_back(item);
  if (runs.empty()) throw UsageError("option --" + option + ": expected run folders DIR,DIR,...");
  return runs;
}

}  // namespace

const CommandSpec& SkillsSpec() {
  static const CommandSpec spec{
      "skills",
      "pwsim skills RUN_DIR... [--session NAME] [options] | pwsim skills --before DIR,... --after DIR,... [options]",
      "The skill score sheet of a participant's runs of skill items (scenes/skills/*.yaml): every attempt's level (pass, pass with difficulty, fail), time, contacts, near-tips and reason; per item a figure; with --before and --after the comparison of the two sessions.",
      {
          OutOption("skills", "sheet.csv, sheet.md, items/<item>.png; with --before/--after also comparison.csv"),
          {"participant", "NAME", "-", "P01", "the participant the runs are of (a column of sheet.csv, for pwsim study skills)"},
          {"session", "NAME", "-", "session", "the session of the RUN_DIRs (e.g. a date or a condition)"},
          {"before", "DIR,...", "-", "", "the runs of the session before training, in attempt order (with --after)"},
          {"after", "DIR,...", "-", "", "the runs of the session after training, in attempt order (with --before)"},
          QuietOption(),  // accepted as by every command; the sheet takes seconds and prints no progress
      },
      "RUN_DIR  output folders of `pwsim run` or `pwsim drive` on a skill item (each with score.json), in attempt order; "
      "the attempts of an item are numbered in the order given. sheet.md gives per session each item's score (the mean "
      "of its attempts: 2 pass, 1 pass with difficulty, 0 fail) and the total percentage 100 x sum / (2 x items); "
      "with --before/--after, comparison.csv gives per item and in total the score, time to the goal, contacts and "
      "near-tips per attempt before, after and after - before. Several participants: one sheet each, then "
      "`pwsim study skills SHEET.csv...` (docs/skills.md)"};
  return spec;
}

int SkillsCommand(const ParsedArgs& args) {
  const bool before = args.Has("before"), after = args.Has("after");
  if (before != after) throw UsageError("options --before and --after: give both (the two sessions to compare)");
  std::vector<report::SkillSession> sessions;
  if (before) {
    if (!args.positional().empty()) {
      throw UsageError("give the runs either as RUN_DIR... (one session) or with --before and --after, not both");
    }
    if (args.Has("session")) throw UsageError("option --session: the sessions are named before and after with --before/--after");
    sessions.push_back({"before", SplitRuns("before", args.Get("before"))});
    sessions.push_back({"after", SplitRuns("after", args.Get("after"))});
  } else {
    if (args.positional().empty()) throw UsageError("expected RUN_DIR... (runs of skill items) or --before and --after");
    const std::string name = args.Get("session");
    if (name.empty() || name.find(',') != std::string::npos) {
      throw UsageError("option --session: expected a name without commas, got '" + name + "'");
    }
    report::SkillSession session{name, {}};
    for (const std::string& run : args.positional()) session.runs.emplace_back(run);
    sessions.push_back(session);
  }
  const std::string participant = args.Get("participant");
  if (participant.empty() || participant.find(',') != std::string::npos) {
    throw UsageError("option --participant: expected a name without commas, got '" + participant + "'");
  }
  // every score is read (and a bad one refused) before the output folder is touched
  const std::vector<report::SkillAttempt> attempts = report::ReadSkillSessions(participant, sessions);
  const fs::path out = OutDir(args);
  OutputFolder folder(out, "skills");  // replaces what the last command wrote there
  report::WriteSkillSheet(attempts, out);
  int counts[3] = {0, 0, 0};
  for (const report::SkillAttempt& a : attempts) ++counts[a.score];
  std::cout << "pwsim skills: " << attempts.size() << " attempts of " << participant << " in " << sessions.size()
            << (sessions.size() == 1 ? " session" : " sessions") << ": " << counts[2] << " pass, " << counts[1]
            << " pass with difficulty, " << counts[0] << " fail\n";
  folder.Print(std::cout, "pwsim skills");
  return 0;
}

}  // namespace pwsim::app
