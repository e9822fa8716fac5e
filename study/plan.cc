#include "study/plan.h"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>

#include "engine/input_error.h"

namespace pwsim::study {
namespace {

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

/// Uniform integer in [0, bound) from the raw generator (rejection sampling; portable).
std::uint64_t Below(std::mt19937_64& rng, std::uint64_t bound) {
  const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() -
                              std::numeric_limits<std::uint64_t>::max() % bound;
  std::uint64_t x = 0;
  do x = rng(); while (x >= limit);
  return x % bound;
}

}  // namespace

std::string PlanOptions::Validate() const {
  if (participants < 1 || participants > 100000) return "participants: expected 1..100000";
  if (conditions.size() < 2) return "conditions: expected at least two";
  std::set<std::string> unique;
  for (const std::string& c : conditions) {
    if (c.empty() || c.find_first_of(", \t\"") != std::string::npos)
      return "conditions: expected names without commas, spaces or quotes, got '" + c + "'";
    if (!unique.insert(c).second) return "conditions: '" + c + "' listed twice";
  }
  if (prefix.find_first_of(", \t\"") != std::string::npos) return "prefix: no commas, spaces or quotes";
  return "";
}

std::vector<std::vector<int>> WilliamsSequences(int k) {
  std::vector<int> first;
  first.push_back(0);
  for (int step = 1; static_cast<int>(first.size()) < k; ++step) {
    first.push_back(step);
    if (static_cast<int>(first.size()) < k) first.push_back(k - step);
  }
  std::vector<std::vector<int>> out;
  for (int i = 0; i < k; ++i) {
    std::vector<int> row;
    for (int c : first) row.push_back((c + i) % k);
    out.push_back(row);
  }
  if (k % 2 == 1) {
    for (int i = 0; i < k; ++i) {
      std::vector<int> row = out[static_cast<std::size_t>(i)];
      std::reverse(row.begin(), row.end());
      out.push_back(row);
    }
  }
  return out;
}

StudyPlan MakePlan(const PlanOptions& options) {
  if (const std::string bad = options.Validate(); !bad.empty()) throw std::invalid_argument("study plan: " + bad);
  const int k = static_cast<int>(options.conditions.size());
  const std::vector<std::vector<int>> seq = WilliamsSequences(k);
  StudyPlan plan;
  for (const auto& s : seq) {
    std::vector<std::string> names;
    for (int c : s) names.push_back(options.conditions[static_cast<std::size_t>(c)]);
    plan.sequences.push_back(names);
  }
  plan.participants_per_sequence.assign(seq.size(), 0);
  std::mt19937_64 rng(options.seed);
  const int width = std::max(2, static_cast<int>(std::to_string(options.participants).size()));
  std::vector<int> block;
  for (int p = 0; p < options.participants; ++p) {
    if (block.empty()) {
      for (int i = 0; i < static_cast<int>(seq.size()); ++i) block.push_back(i);
      for (std::size_t i = block.size() - 1; i > 0; --i) std::swap(block[i], block[Below(rng, i + 1)]);
      std::reverse(block.begin(), block.end());  // take from the back below
    }
    const int s = block.back();
    block.pop_back();
    ++plan.participants_per_sequence[static_cast<std::size_t>(s)];
    std::string number = std::to_string(p + 1);
    const std::string id = options.prefix + std::string(static_cast<std::size_t>(width) - std::min(number.size(), static_cast<std::size_t>(width)), '0') + number;
    for (int t = 0; t < k; ++t) {
      PlanTrial trial;
      trial.participant = id;
      trial.trial_index = t + 1;
      trial.condition = plan.sequences[static_cast<std::size_t>(s)][static_cast<std::size_t>(t)];
      trial.sequence = s + 1;
      plan.trials.push_back(trial);
    }
  }
  return plan;
}

std::string PlanCsv(const StudyPlan& plan) {
  std::ostringstream out;
  out << "participant,trial_index,condition,sequence\n";
  for (const PlanTrial& t : plan.trials)
    out << t.participant << ',' << t.trial_index << ',' << t.condition << ',' << t.sequence << '\n';
  return out.str();
}

std::string RatingsTemplateCsv(const StudyPlan& plan) {
  std::ostringstream out;
  out << "# Ratings template: fill in `rating` (1-6 on the decision tree of seed 000, Fig. 8a)\n"
      << "participant,condition,rating,order\n";
  for (const PlanTrial& t : plan.trials) out << t.participant << ',' << t.condition << ",," << t.trial_index << '\n';
  return out.str();
}

std::vector<PlanTrial> ReadPlan(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::ifstream in(file);
  if (!in) throw InputError(name, 0, "file", "a readable plan CSV", "cannot open it");
  std::string line;
  int line_no = 0;
  std::map<std::string, std::size_t> column;
  std::size_t n_columns = 0;
  std::vector<PlanTrial> out;
  std::set<std::pair<std::string, int>> seen;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    std::vector<std::string> fields;
    std::istringstream ls(trimmed);
    std::string f;
    while (std::getline(ls, f, ',')) fields.push_back(Trim(f));
    if (trimmed.back() == ',') fields.push_back("");
    if (column.empty()) {
      for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i] != "participant" && fields[i] != "trial_index" && fields[i] != "condition" && fields[i] != "sequence")
          throw InputError(name, line_no, "header column " + std::to_string(i + 1),
                           "one of participant, trial_index, condition, sequence", "\"" + fields[i] + "\"");
        column[fields[i]] = i;
      }
      for (const char* required : {"participant", "trial_index", "condition"})
        if (!column.count(required))
          throw InputError(name, line_no, "header", std::string("a '") + required + "' column", "\"" + trimmed + "\"");
      n_columns = fields.size();
      continue;
    }
    if (fields.size() != n_columns)
      throw InputError(name, line_no, "line", std::to_string(n_columns) + " fields as in the header",
                       std::to_string(fields.size()) + " fields");
    PlanTrial t;
    t.participant = fields[column["participant"]];
    t.condition = fields[column["condition"]];
    const std::string& index = fields[column["trial_index"]];
    const auto [ptr, ec] = std::from_chars(index.data(), index.data() + index.size(), t.trial_index);
    if (ec != std::errc() || ptr != index.data() + index.size() || t.trial_index < 1)
      throw InputError(name, line_no, "trial_index", "a positive integer", "\"" + index + "\"");
    if (t.participant.empty()) throw InputError(name, line_no, "participant", "a non-empty name", "an empty field");
    if (t.condition.empty()) throw InputError(name, line_no, "condition", "a non-empty name", "an empty field");
    if (!seen.insert({t.participant, t.trial_index}).second)
      throw InputError(name, line_no, "trial_index", "one trial per participant and index",
                       "participant " + t.participant + " trial " + index + " twice");
    out.push_back(t);
  }
  if (out.empty()) throw InputError(name, 0, "trials", "at least one planned trial", "none");
  return out;
}

PlanTrial FindPlannedTrial(const std::vector<PlanTrial>& plan, const std::string& file,
                           const std::string& participant, int trial_index) {
  bool participant_found = false;
  for (const PlanTrial& t : plan) {
    if (t.participant != participant) continue;
    participant_found = true;
    if (t.trial_index == trial_index) return t;
  }
  if (!participant_found) throw InputError(file, 0, "participant", "a participant of the plan", "\"" + participant + "\"");
  throw InputError(file, 0, "trial_index", "a trial index planned for " + participant,
                   std::to_string(trial_index));
}

}  // namespace pwsim::study
