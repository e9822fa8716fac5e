#pragma once
// The skill score sheet (`pwsim skills`, docs/skills.md): the scores of a participant's drives
// through skill items (report/skill_score.h: each run folder's score.json), attempt by attempt,
// item by item, per session, and the comparison of two sessions (before and after training).
//
//   sheet.csv   one row per attempt:
//               participant,session,item,attempt,level,score,time_s,contacts,
//               contact_speed_max_mps,near_tips,tip_over,deviation_mean_m,deviation_max_m,run,reason
//               (score 2 pass, 1 pass with difficulty, 0 fail; empty time_s / deviation when
//               none; commas in the reason written as semicolons)
//   sheet.md    per session: every item's attempts with their level and reason, the item score
//               (the mean of its attempts' scores) and the session's total percentage
//                 total % = 100 · Σ_items item score / (2 · items)
//               (the WST's total percentage: the scores summed over the items, out of the most
//               they can be); with two sessions the comparison table
//   comparison.csv  (two sessions) per item and in total: score, time to the goal (mean over
//               the attempts that reached it), contacts and near-tips per attempt, before, after
//               and after - before
//   items/<item>.png  one figure per item: capacity score and time to the goal per attempt,
//               one series per session
//
// Attempts are numbered in the order their run folders are given, per session and item.
// The sheet is also `pwsim study skills`' input: per participant and session (the condition)
// the total percentage and every item's score go through the ratings' statistics
// (shared/spec/study.md) into OUT/total_percent/ and OUT/<item>/.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pwsim::report {

/// One attempt: a run folder's score.json.
struct SkillAttempt {
  std::string participant, session, item, title, source;
  int attempt{1};
  std::string level;           ///< "pass", "pass with difficulty", "fail"
  int score{0};                ///< 2, 1, 0
  std::optional<double> time_s;
  int contacts{0};
  double contact_speed_max_mps{0.0};
  int near_tips{0};
  bool tip_over{false};
  std::optional<double> deviation_mean_m, deviation_max_m;
  std::string run;             ///< the run folder
  std::string reason;
};

/// Reads RUN_DIR/score.json. @throws InputError naming the file and field: no score.json (a run
/// of a scene that is not a skill item, or no run at all), not JSON, a wrong format, a missing
/// or mistyped field.
SkillAttempt ReadSkillAttempt(const std::filesystem::path& run_dir, const std::string& participant,
                              const std::string& session);

/// A session: its name and its run folders in attempt order.
struct SkillSession {
  std::string name;
  std::vector<std::filesystem::path> runs;
};

/// Every run of every session read and numbered (attempt k of an item in a session).
std::vector<SkillAttempt> ReadSkillSessions(const std::string& participant, const std::vector<SkillSession>& sessions);

/// sheet.csv's text.
std::string SkillSheetCsv(const std::vector<SkillAttempt>& attempts);

/// Writes sheet.csv, sheet.md, items/<item>.png and, with exactly two sessions (the first
/// "before", the second "after"), comparison.csv. Returns the files written.
std::vector<std::filesystem::path> WriteSkillSheet(const std::vector<SkillAttempt>& attempts,
                                                   const std::filesystem::path& out);

/// Is `file` a skill score sheet (a header with session, item and score columns)? False for a
/// file that cannot be read (the caller's reader then says why).
bool IsSkillSheet(const std::filesystem::path& file);

/// Reads sheet.csv files (several participants' sheets together). @throws InputError naming
/// file, line and field (a missing column, a wrong field count, a score not 0, 1 or 2).
std::vector<SkillAttempt> ReadSkillSheets(const std::vector<std::filesystem::path>& files);

/// The ratings CSV (participant,condition,rating) of one measure: the total percentage
/// (`item` empty) or one item's score, per participant and session.
std::string SkillRatingsCsv(const std::vector<SkillAttempt>& attempts, const std::string& item);

/// `pwsim study skills`: analyses the total percentage and every item with at least 3
/// participants in each of two sessions into OUT/<measure>/ (study.json, study.md, boxplot.png)
/// and writes OUT/skills.json (what was analysed, what not and why). `conditions` picks the
/// pair (empty: the first two sessions in the sheets). Returns the measures analysed.
std::vector<std::string> WriteSkillStudy(const std::vector<std::filesystem::path>& sheets,
                                         const std::vector<std::string>& conditions, const std::filesystem::path& out);

}  // namespace pwsim::report
