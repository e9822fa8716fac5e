#include "report/skill_sheet.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/atomic_file.h"
#include "engine/csv_fields.h"
#include "engine/input_error.h"
#include "plot/plot.h"
#include "report/study_report.h"
#include "study/analysis.h"
#include "study/ratings.h"

namespace pwsim::report {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const std::vector<std::string> kColumns{"participant", "session", "item", "attempt", "level", "score", "time_s",
                                        "contacts", "contact_speed_max_mps", "near_tips", "tip_over",
                                        "deviation_mean_m", "deviation_max_m", "run", "reason"};

/// A field of score.json of the expected type, or an InputError naming file and field.
const nlohmann::json& Field(const nlohmann::json& j, const std::string& file, const std::string& pointer,
                            nlohmann::json::value_t type, const char* expected) {
  const nlohmann::json::json_pointer p(pointer);
  if (!j.contains(p)) throw InputError(file, 0, pointer.substr(1), expected, "missing");
  const nlohmann::json& v = j[p];
  const bool number = type == nlohmann::json::value_t::number_float;
  if (number ? !v.is_number() : v.type() != type) {
    throw InputError(file, 0, pointer.substr(1), expected, v.dump());
  }
  return v;
}

std::optional<double> NullableNumber(const nlohmann::json& j, const std::string& file, const std::string& pointer) {
  const nlohmann::json::json_pointer p(pointer);
  if (!j.contains(p)) throw InputError(file, 0, pointer.substr(1), "a number or null", "missing");
  if (j[p].is_null()) return std::nullopt;
  if (!j[p].is_number()) throw InputError(file, 0, pointer.substr(1), "a number or null", j[p].dump());
  return j[p].get<double>();
}

std::string Cell(const std::optional<double>& v) {
  if (!v) return "";
  std::ostringstream s;
  s.precision(10);
  s << *v;
  return s.str();
}

std::string Fixed(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v;
  return s.str();
}

std::string NoCommas(std::string text) {
  std::replace(text.begin(), text.end(), ',', ';');
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}


/// Items and sessions in order of first appearance.
std::vector<std::string> InOrder(const std::vector<SkillAttempt>& attempts, std::string SkillAttempt::*field) {
  std::vector<std::string> out;
  for (const SkillAttempt& a : attempts) {
    if (std::find(out.begin(), out.end(), a.*field) == out.end()) out.push_back(a.*field);
  }
  return out;
}

/// What the sheet summarises of one item in one session.
struct ItemSummary {
  int attempts{0};
  double score{kNaN};            ///< mean of the attempts' scores
  double time_s{kNaN};           ///< mean over the attempts that reached the goal
  double contacts{kNaN};         ///< per attempt
  double near_tips{kNaN};        ///< per attempt
  std::string levels;            ///< e.g. "pass, pass with difficulty"
};

ItemSummary Summarise(const std::vector<SkillAttempt>& attempts, const std::string& participant,
                      const std::string& session, const std::string& item) {
  ItemSummary s;
  double score = 0.0, time = 0.0, contacts = 0.0, near_tips = 0.0;
  int timed = 0;
  for (const SkillAttempt& a : attempts) {
    if (a.participant != participant || a.session != session || a.item != item) continue;
    ++s.attempts;
    score += a.score;
    contacts += a.contacts;
    near_tips += a.near_tips;
    if (a.time_s) {
      time += *a.time_s;
      ++timed;
    }
    s.levels += (s.levels.empty() ? "" : ", ") + a.level;
  }
  if (s.attempts == 0) return s;
  s.score = score / s.attempts;
  s.contacts = contacts / s.attempts;
  s.near_tips = near_tips / s.attempts;
  if (timed > 0) s.time_s = time / timed;
  return s;
}

/// The session's total percentage over the items it has: 100 Σ score / (2 items).
double TotalPercent(const std::vector<SkillAttempt>& attempts, const std::string& participant,
                    const std::string& session, const std::vector<std::string>& items) {
  double sum = 0.0;
  int n = 0;
  for (const std::string& item : items) {
    const ItemSummary s = Summarise(attempts, participant, session, item);
    if (s.attempts == 0) continue;
    sum += s.score;
    ++n;
  }
  return n == 0 ? kNaN : 100.0 * sum / (2.0 * n);
}

void WriteItemFigure(const std::vector<SkillAttempt>& attempts, const std::string& item, const fs::path& stem) {
  plot::Figure figure;
  std::string title;
  for (const SkillAttempt& a : attempts) {
    if (a.item == item) {
      title = a.title;
      break;
    }
  }
  figure.title = "pwsim skills: " + item + " (" + title + ")";
  figure.x_label = "attempt, in the order run [number] (the sessions side by side around it)";
  plot::Panel score;
  score.title = "capacity score per attempt (WST: 2 pass, 1 pass with difficulty, 0 fail)";
  score.y_label = "capacity score [0 fail, 1 with difficulty, 2 pass]";
  score.y_min = -0.2;
  score.y_max = 2.2;
  plot::Panel time;
  time.title = "time to the goal per attempt (none: not reached)";
  time.y_label = "time to the goal [s]";
  const std::vector<std::string> participants = InOrder(attempts, &SkillAttempt::participant);
  const std::vector<std::string> sessions = InOrder(attempts, &SkillAttempt::session);
  const double series_count = static_cast<double>(participants.size() * sessions.size());
  double index = 0.0;  // each series a little apart, so equal scores stay visible
  for (const std::string& participant : participants) {
    for (const std::string& session : sessions) {
      const double shift = 0.3 * ((index + 0.5) / series_count - 0.5);
      index += 1.0;
      plot::Series s{participant + " " + session, {}, {}, plot::Style::kLinesPoints, 0};
      plot::Series t = s;
      for (const SkillAttempt& a : attempts) {
        if (a.item != item || a.participant != participant || a.session != session) continue;
        s.x.push_back(a.attempt + shift);
        s.y.push_back(a.score);
        t.x.push_back(a.attempt + shift);
        t.y.push_back(a.time_s ? *a.time_s : kNaN);
      }
      if (s.x.empty()) continue;
      score.series.push_back(s);
      time.series.push_back(t);
    }
  }
  // Times from 0, so that two close times are not drawn as far apart (autoscale spread one
  // attempt's 6.76 s over 6.68-6.84 s).
  double longest = 0.0;
  for (const plot::Series& t : time.series)
    for (double y : t.y)
      if (std::isfinite(y)) longest = std::max(longest, y);
  if (longest > 0.0) {
    time.y_min = 0.0;
    time.y_max = 1.1 * longest;
  }
  // Attempts are counted: integer tics, half an attempt free on each side.
  int attempts_drawn = 1;
  for (const SkillAttempt& a : attempts)
    if (a.item == item) attempts_drawn = std::max(attempts_drawn, static_cast<int>(a.attempt));
  figure.x_min = 0.5;
  figure.x_max = attempts_drawn + 0.5;
  figure.x_integer_tics = true;
  figure.panels = {score, time};
  plot::WriteFigure(stem, figure);
}

}  // namespace

SkillAttempt ReadSkillAttempt(const fs::path& run_dir, const std::string& participant, const std::string& session) {
  const fs::path file = run_dir / "score.json";
  const std::string name = file.string();
  if (!fs::is_directory(run_dir)) {
    throw InputError(run_dir.string(), 0, "RUN_DIR", "a run folder of `pwsim run` or `pwsim drive` on a skill item",
                     "no such folder");
  }
  std::ifstream in(file);
  if (!in) {
    throw InputError(name, 0, "RUN_DIR", "the score of a skill item (score.json, written by `pwsim run` or `pwsim drive` on scenes/skills/*.yaml)",
                     "no score.json in " + run_dir.string() + " (a run of a scene without a skill: section?)");
  }
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) throw InputError(name, 0, "", "a JSON object", "text that is not JSON");
  using V = nlohmann::json::value_t;
  const std::string format = Field(j, name, "/format", V::string, "\"pwsim-skill-score/1\"").get<std::string>();
  if (format != "pwsim-skill-score/1") throw InputError(name, 0, "format", "\"pwsim-skill-score/1\"", "\"" + format + "\"");
  SkillAttempt a;
  a.participant = participant;
  a.session = session;
  a.item = Field(j, name, "/item", V::string, "a string").get<std::string>();
  a.title = Field(j, name, "/title", V::string, "a string").get<std::string>();
  a.source = Field(j, name, "/source", V::string, "a string").get<std::string>();
  a.level = Field(j, name, "/level", V::string, "a string").get<std::string>();
  const double score = Field(j, name, "/score", V::number_float, "0, 1 or 2").get<double>();
  if (score != 0.0 && score != 1.0 && score != 2.0) throw InputError(name, 0, "score", "0, 1 or 2", j["score"].dump());
  a.score = static_cast<int>(score);
  const char* levels[] = {"fail", "pass with difficulty", "pass"};
  if (a.level != levels[a.score]) {
    throw InputError(name, 0, "level", std::string("\"") + levels[a.score] + "\" (its score is " + std::to_string(a.score) + ")",
                     "\"" + a.level + "\"");
  }
  a.reason = Field(j, name, "/reason", V::string, "a string").get<std::string>();
  a.time_s = NullableNumber(j, name, "/time_s");
  a.contacts = static_cast<int>(Field(j, name, "/contacts/count", V::number_float, "a count").get<double>());
  a.contact_speed_max_mps = Field(j, name, "/contacts/max_speed_mps", V::number_float, "a speed [m/s]").get<double>();
  a.near_tips = static_cast<int>(Field(j, name, "/near_tips/count", V::number_float, "a count").get<double>());
  a.tip_over = !j.contains("tip_over_t_s") ? throw InputError(name, 0, "tip_over_t_s", "a time [s] or null", "missing")
                                           : !j["tip_over_t_s"].is_null();
  if (j.contains("deviation_m") && j["deviation_m"].is_object()) {
    a.deviation_mean_m = NullableNumber(j, name, "/deviation_m/mean");
    a.deviation_max_m = NullableNumber(j, name, "/deviation_m/max");
  } else if (!j.contains("deviation_m")) {
    throw InputError(name, 0, "deviation_m", "{mean, rms, max} [m] or null", "missing");
  }
  a.run = run_dir.string();
  return a;
}

std::vector<SkillAttempt> ReadSkillSessions(const std::string& participant, const std::vector<SkillSession>& sessions) {
  std::vector<SkillAttempt> attempts;
  for (const SkillSession& session : sessions) {
    std::map<std::string, int> count;
    for (const fs::path& run : session.runs) {
      SkillAttempt a = ReadSkillAttempt(run, participant, session.name);
      a.attempt = ++count[a.item];
      attempts.push_back(a);
    }
  }
  return attempts;
}

std::string SkillSheetCsv(const std::vector<SkillAttempt>& attempts) {
  std::ostringstream csv;
  for (std::size_t i = 0; i < kColumns.size(); ++i) csv << (i ? "," : "") << kColumns[i];
  csv << "\n";
  for (const SkillAttempt& a : attempts) {
    csv << NoCommas(a.participant) << ',' << NoCommas(a.session) << ',' << a.item << ',' << a.attempt << ',' << a.level
        << ',' << a.score << ',' << Cell(a.time_s) << ',' << a.contacts << ',' << Cell(a.contact_speed_max_mps) << ','
        << a.near_tips << ',' << (a.tip_over ? 1 : 0) << ',' << Cell(a.deviation_mean_m) << ','
        << Cell(a.deviation_max_m) << ',' << NoCommas(a.run) << ',' << NoCommas(a.reason) << '\n';
  }
  return csv.str();
}

std::vector<fs::path> WriteSkillSheet(const std::vector<SkillAttempt>& attempts, const fs::path& out) {
  std::vector<fs::path> written;
  fs::create_directories(out / "items");
  WriteFileAtomically(out / "sheet.csv", SkillSheetCsv(attempts));
  written.push_back(out / "sheet.csv");
  const std::vector<std::string> participants = InOrder(attempts, &SkillAttempt::participant);
  const std::vector<std::string> sessions = InOrder(attempts, &SkillAttempt::session);
  const std::vector<std::string> items = InOrder(attempts, &SkillAttempt::item);
  std::map<std::string, const SkillAttempt*> first_of_item;
  for (const SkillAttempt& a : attempts) first_of_item.emplace(a.item, &a);

  std::ostringstream md;
  md << "# Skill score sheet\n\n"
     << "Written by `pwsim skills` (report/skill_sheet.h) from the score.json of every run; the items, their\n"
     << "settings and scoring rule are in docs/skills.md. Levels as the Wheelchair Skills Test grades capacity:\n"
     << "2 pass, 1 pass with difficulty, 0 fail. Item score: the mean over its attempts; total: 100 x the sum of\n"
     << "the item scores / (2 x items).\n\n";
  for (const std::string& participant : participants) {
    for (const std::string& session : sessions) {
      bool any = false;
      for (const SkillAttempt& a : attempts) any = any || (a.participant == participant && a.session == session);
      if (!any) continue;
      md << "## " << participant << ", session " << session << "\n\n"
         << "| item | source | attempt | level | time to goal [s] | contacts (max speed [m/s]) | near-tips | deviation mean / max [m] | reason |\n"
         << "|---|---|---|---|---|---|---|---|---|\n";
      for (const SkillAttempt& a : attempts) {
        if (a.participant != participant || a.session != session) continue;
        md << "| " << a.item << " | " << a.source << " | " << a.attempt << " | " << a.level << " | "
           << (a.time_s ? Fixed(*a.time_s, 2) : std::string("not reached")) << " | " << a.contacts << " ("
           << Fixed(a.contact_speed_max_mps, 2) << ") | " << a.near_tips << " | "
           << (a.deviation_mean_m ? Fixed(*a.deviation_mean_m, 3) + " / " + Fixed(a.deviation_max_m.value_or(kNaN), 3)
                                  : std::string("no route"))
           << " | " << a.reason << " |\n";
      }
      md << "\n| item | attempts | item score [0-2] |\n|---|---|---|\n";
      for (const std::string& item : items) {
        const ItemSummary s = Summarise(attempts, participant, session, item);
        if (s.attempts == 0) continue;
        md << "| " << item << " | " << s.attempts << " | " << Fixed(s.score, 2) << " |\n";
      }
      md << "\nTotal: **" << Fixed(TotalPercent(attempts, participant, session, items), 1) << " %**\n\n";
    }
  }
  if (sessions.size() == 2) {
    const std::string& before = sessions[0];
    const std::string& after = sessions[1];
    std::ostringstream csv;
    csv << "participant,item,measure,before,after,change\n";
    md << "## Before (" << before << ") and after (" << after << ")\n\n"
       << "Per item: the mean over the attempts of each session; time to the goal over the attempts that reached it.\n\n"
       << "| participant | item | score before | after | change | time before [s] | after | change | contacts per attempt before | after | near-tips per attempt before | after |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const std::string& participant : participants) {
      for (const std::string& item : items) {
        const ItemSummary b = Summarise(attempts, participant, before, item);
        const ItemSummary a = Summarise(attempts, participant, after, item);
        if (b.attempts == 0 && a.attempts == 0) continue;
        md << "| " << participant << " | " << item << " | " << Fixed(b.score, 2) << " | " << Fixed(a.score, 2) << " | "
           << Fixed(a.score - b.score, 2) << " | " << Fixed(b.time_s, 2) << " | " << Fixed(a.time_s, 2) << " | "
           << Fixed(a.time_s - b.time_s, 2) << " | " << Fixed(b.contacts, 2) << " | " << Fixed(a.contacts, 2) << " | "
           << Fixed(b.near_tips, 2) << " | " << Fixed(a.near_tips, 2) << " |\n";
        for (auto [measure, vb, va] : {std::tuple{"score", b.score, a.score}, std::tuple{"time_s", b.time_s, a.time_s},
                                       std::tuple{"contacts_per_attempt", b.contacts, a.contacts},
                                       std::tuple{"near_tips_per_attempt", b.near_tips, a.near_tips}}) {
          csv << NoCommas(participant) << ',' << item << ',' << measure << ','
              << (std::isfinite(vb) ? Cell(vb) : "") << ',' << (std::isfinite(va) ? Cell(va) : "") << ','
              << (std::isfinite(va - vb) ? Cell(va - vb) : "") << '\n';
        }
      }
      const double tb = TotalPercent(attempts, participant, before, items);
      const double ta = TotalPercent(attempts, participant, after, items);
      md << "| " << participant << " | **total %** | " << Fixed(tb, 1) << " | " << Fixed(ta, 1) << " | "
         << Fixed(ta - tb, 1) << " | | | | | | | |\n";
      csv << NoCommas(participant) << ",total,percent," << (std::isfinite(tb) ? Cell(tb) : "") << ','
          << (std::isfinite(ta) ? Cell(ta) : "") << ',' << (std::isfinite(ta - tb) ? Cell(ta - tb) : "") << '\n';
    }
    md << "\n";
    WriteFileAtomically(out / "comparison.csv", csv.str());
    written.push_back(out / "comparison.csv");
  }
  md << "## Figures\n\n";
  for (const std::string& item : items) {
    WriteItemFigure(attempts, item, out / "items" / item);
    written.push_back(out / "items" / (item + ".png"));
    md << "![" << item << "](items/" << item << ".png)\n\n";
  }
  WriteFileAtomically(out / "sheet.md", md.str());
  written.push_back(out / "sheet.md");
  return written;
}

bool IsSkillSheet(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    const std::vector<std::string> header = SplitCsvFields(line);
    auto has = [&](const char* name) { return std::find(header.begin(), header.end(), name) != header.end(); };
    return has("session") && has("item") && has("score");
  }
  return false;
}

std::vector<SkillAttempt> ReadSkillSheets(const std::vector<fs::path>& files) {
  std::vector<SkillAttempt> attempts;
  for (const fs::path& file : files) {
    std::ifstream in(file);
    if (!in) throw InputError(file.string(), 0, "SHEET.csv", "a readable sheet.csv (pwsim skills)", "cannot open");
    std::string line;
    int number = 0;
    const std::vector<std::string> header = ReadCsvHeader(in, number, line);
    std::map<std::string, std::size_t> column;
    for (std::size_t i = 0; i < header.size(); ++i) column[header[i]] = i;
    for (const char* need : {"participant", "session", "item", "attempt", "score"}) {
      if (!column.count(need)) {
        throw InputError(file.string(), number, need,
                         "a sheet.csv header with participant, session, item, attempt and score", line);
      }
    }
    while (std::getline(in, line)) {
      ++number;
      if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
      const std::vector<std::string> f = SplitCsvFields(line);
      if (f.size() != header.size()) {
        throw InputError(file.string(), number, "", std::to_string(header.size()) + " fields", std::to_string(f.size()));
      }
      SkillAttempt a;
      a.participant = f[column["participant"]];
      a.session = f[column["session"]];
      a.item = f[column["item"]];
      for (const char* key : {"participant", "session", "item"}) {
        if (f[column[key]].empty()) throw InputError(file.string(), number, key, "a non-empty name", "empty");
      }
      const std::string score = f[column["score"]];
      if (score != "0" && score != "1" && score != "2") {
        throw InputError(file.string(), number, "score", "0, 1 or 2 (fail, pass with difficulty, pass)", "\"" + score + "\"");
      }
      a.score = score[0] - '0';
      try {
        a.attempt = std::stoi(f[column["attempt"]]);
      } catch (const std::exception&) {
        throw InputError(file.string(), number, "attempt", "an attempt number", "\"" + f[column["attempt"]] + "\"");
      }
      if (column.count("level")) a.level = f[column["level"]];
      attempts.push_back(a);
    }
  }
  return attempts;
}

std::string SkillRatingsCsv(const std::vector<SkillAttempt>& attempts, const std::string& item) {
  std::ostringstream csv;
  csv << "participant,condition,rating\n";
  csv.precision(17);
  const std::vector<std::string> items = InOrder(attempts, &SkillAttempt::item);
  for (const std::string& participant : InOrder(attempts, &SkillAttempt::participant)) {
    for (const std::string& session : InOrder(attempts, &SkillAttempt::session)) {
      const double value = item.empty() ? TotalPercent(attempts, participant, session, items)
                                        : Summarise(attempts, participant, session, item).score;
      if (std::isfinite(value)) csv << participant << ',' << session << ',' << value << '\n';
    }
  }
  return csv.str();
}

std::vector<std::string> WriteSkillStudy(const std::vector<fs::path>& sheets, const std::vector<std::string>& conditions,
                                         const fs::path& out) {
  const std::vector<SkillAttempt> attempts = ReadSkillSheets(sheets);
  std::string label;
  for (const fs::path& s : sheets) label += (label.empty() ? "" : " ") + s.string();
  nlohmann::ordered_json summary;
  summary["format"] = "pwsim-skill-study/1";
  summary["sheets"] = label;
  summary["measures"] = nlohmann::ordered_json::object();
  std::vector<std::string> measures{""};
  for (const std::string& item : InOrder(attempts, &SkillAttempt::item)) measures.push_back(item);
  std::vector<std::string> analysed;
  for (const std::string& item : measures) {
    const std::string name = item.empty() ? "total_percent" : item;
    nlohmann::ordered_json entry;
    entry["measure"] = item.empty() ? "total percentage: 100 x sum of item scores / (2 x items)"
                                    : "item score: mean of the attempts' scores (0-2)";
    try {
      const study::Ratings ratings = study::ParseRatings(SkillRatingsCsv(attempts, item), label + " (" + name + ")");
      study::AnalysisOptions options;
      if (conditions.size() == 2) options.conditions = std::make_pair(conditions[0], conditions[1]);
      const study::StudyAnalysis analysis = study::Analyse(ratings, options);
      const fs::path dir = out / name;
      RemoveStudyReport(dir);
      WriteStudyReport(dir, label + " (" + name + ")", ratings, analysis);
      entry["report"] = (fs::path(name) / "study.json").string();
      analysed.push_back(name);
    } catch (const InputError& e) {  // e.g. fewer than 3 participants in a session
      entry["report"] = nullptr;
      entry["not_analysed"] = e.what();
    }
    summary["measures"][name] = entry;
  }
  fs::create_directories(out);
  WriteFileAtomically(out / "skills.json", summary.dump(2) + "\n");
  return analysed;
}

}  // namespace pwsim::report
