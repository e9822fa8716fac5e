#include "study/ratings.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "engine/csv_fields.h"
#include "engine/input_error.h"

namespace pwsim::study {
namespace {

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}


std::string Quoted(const std::string& s) { return "\"" + s + "\""; }

/// The largest rating magnitude accepted (see ratings.h).
constexpr double kMaxRatingMagnitude = 1e6;

bool ParseNumber(const std::string& s, double* value) {
  if (s.empty()) return false;
  const char* begin = s.data();
  if (*begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, s.data() + s.size(), *value);
  return ec == std::errc() && ptr == s.data() + s.size() && std::isfinite(*value);
}

}  // namespace

std::vector<double> Ratings::Values(const std::string& condition) const {
  std::vector<double> out;
  for (const Rating& r : rows)
    if (r.condition == condition) out.push_back(r.value);
  return out;
}

const Rating* Ratings::Find(const std::string& participant, const std::string& condition) const {
  for (const Rating& r : rows)
    if (r.participant == participant && r.condition == condition) return &r;
  return nullptr;
}

Ratings ParseRatings(const std::string& text, const std::string& name) {
  static const std::vector<std::string> kKnown{"participant", "condition", "rating", "order"};
  Ratings out;
  out.file = name;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::map<std::string, std::size_t> column;  // name -> index
  std::size_t n_columns = 0;
  int header_line = 0;
  std::map<std::pair<std::string, std::string>, int> seen;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 byte order mark
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    if (trimmed.find('"') != std::string::npos)
      throw InputError(name, line_no, "line", "comma-separated fields without quotes", Quoted(trimmed));
    const std::vector<std::string> fields = SplitCsvFields(trimmed);
    if (header_line == 0) {
      header_line = line_no;
      for (std::size_t i = 0; i < fields.size(); ++i) {
        const std::string& f = fields[i];
        if (std::find(kKnown.begin(), kKnown.end(), f) == kKnown.end())
          throw InputError(name, line_no, "header column " + std::to_string(i + 1),
                           "one of participant, condition, rating, order", Quoted(f));
        if (column.count(f))
          throw InputError(name, line_no, "header column " + std::to_string(i + 1),
                           "each column once", Quoted(f) + " twice");
        column[f] = i;
      }
      for (const char* required : {"participant", "condition", "rating"})
        if (!column.count(required))
          throw InputError(name, line_no, "header", std::string("a '") + required + "' column",
                           Quoted(trimmed));
      n_columns = fields.size();
      out.has_order = column.count("order") > 0;
      continue;
    }
    if (fields.size() != n_columns)
      throw InputError(name, line_no, "line",
                       std::to_string(n_columns) + " comma-separated fields as in the header",
                       std::to_string(fields.size()) + " fields");
    Rating r;
    r.line = line_no;
    r.participant = fields[column["participant"]];
    r.condition = fields[column["condition"]];
    if (r.participant.empty()) throw InputError(name, line_no, "participant", "a non-empty name", "an empty field");
    if (r.condition.empty()) throw InputError(name, line_no, "condition", "a non-empty name", "an empty field");
    const std::string& rating = fields[column["rating"]];
    if (!ParseNumber(rating, &r.value))
      throw InputError(name, line_no, "rating", "a finite number",
                       rating.empty() ? std::string("an empty field") : Quoted(rating));
    if (std::abs(r.value) > kMaxRatingMagnitude)
      throw InputError(name, line_no, "rating", "a number within +-1e6 (a value on a rating scale)", Quoted(rating));
    if (out.has_order) {
      const std::string& order = fields[column["order"]];
      int value = 0;
      const auto [ptr, ec] = std::from_chars(order.data(), order.data() + order.size(), value);
      if (order.empty() || ec != std::errc() || ptr != order.data() + order.size() || value < 1)
        throw InputError(name, line_no, "order", "a positive integer (the trial's position)",
                         order.empty() ? std::string("an empty field") : Quoted(order));
      r.order = value;
    }
    const auto key = std::make_pair(r.participant, r.condition);
    if (const auto it = seen.find(key); it != seen.end())
      throw InputError(name, line_no, "condition",
                       "one rating per participant and condition",
                       "participant " + Quoted(r.participant) + " rated " + Quoted(r.condition) +
                           " again (first on line " + std::to_string(it->second) + ")");
    seen[key] = line_no;
    if (std::find(out.conditions.begin(), out.conditions.end(), r.condition) == out.conditions.end())
      out.conditions.push_back(r.condition);
    if (std::find(out.participants.begin(), out.participants.end(), r.participant) == out.participants.end())
      out.participants.push_back(r.participant);
    out.rows.push_back(std::move(r));
  }
  if (header_line == 0)
    throw InputError(name, 0, "header", "a header line participant,condition,rating[,order]", "an empty file");
  if (out.conditions.size() < 2)
    throw InputError(name, 0, "condition", "ratings of at least two conditions",
                     std::to_string(out.conditions.size()) + " condition(s)");
  for (const std::string& c : out.conditions) {
    const std::size_t n = out.Values(c).size();
    int first_line = 0;
    for (const Rating& r : out.rows)
      if (r.condition == c && first_line == 0) first_line = r.line;
    if (n < 3)
      throw InputError(name, first_line, "rating", "at least 3 ratings per condition",
                       std::to_string(n) + " for condition " + Quoted(c));
  }
  return out;
}

Ratings ReadRatings(const std::filesystem::path& file) {
  RequireReadableFile(file, "a ratings CSV");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "file", "a readable ratings CSV", "cannot open it");
  std::ostringstream text;
  text << in.rdbuf();
  return ParseRatings(text.str(), file.string());
}

}  // namespace pwsim::study
