#include "study/analysis.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "engine/input_error.h"
#include "engine/number_format.h"

namespace pwsim::study {
namespace {

std::string Num(double v, int decimals) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << v;
  return s.str();
}

std::string Fmt(double v) {
  // short, human: up to 4 significant decimals for p-values, whole numbers stay whole
  if (v == std::round(v) && std::abs(v) < 1e9) return Num(v, 0);
  if (std::abs(v) >= 0.001) return Num(v, 4);
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + names[i];
  return out;
}

int DecimalsOf(const std::string& number) {
  const auto dot = number.find('.');
  if (dot == std::string::npos) return 0;
  return static_cast<int>(number.size() - dot - 1);
}

bool Matches(double computed, double reported, int decimals) {
  return std::abs(computed - reported) <= 0.5 * std::pow(10.0, -decimals) + 1e-12;
}

PairComparison Compare(const Ratings& ratings, const std::string& a, const std::string& b) {
  PairComparison pc;
  pc.a = a;
  pc.b = b;
  std::vector<double> xa, xb;
  for (const std::string& p : ratings.participants) {
    const Rating* ra = ratings.Find(p, a);
    const Rating* rb = ratings.Find(p, b);
    if (ra && rb) {
      pc.paired_participants.push_back(p);
      xa.push_back(ra->value);
      xb.push_back(rb->value);
    } else if (ra || rb) {
      pc.left_out.push_back(p);
    }
  }
  if (!xa.empty()) {
    pc.paired = SignedRankTest(xa, xb);
    SignedRankOptions uncorrected;
    uncorrected.correct = false;
    pc.paired_p_uncorrected = SignedRankTest(xa, xb, uncorrected).p_normal;
  }
  const std::vector<double> va = ratings.Values(a);
  const std::vector<double> vb = ratings.Values(b);
  pc.unpaired = RankSumTest(va, vb);
  RankSumOptions uncorrected;
  uncorrected.correct = false;
  pc.unpaired_p_uncorrected = RankSumTest(va, vb, uncorrected).p_normal;
  return pc;
}

struct Candidate {
  std::string test;       ///< "paired" / "unpaired"
  std::string statistic;  ///< description
  double value;
};
struct PCandidate {
  std::string test;
  std::string what;
  double value;
};

void CheckReported(const StudyAnalysis& an, const Reported& rep, std::vector<std::string>* notes) {
  const PairComparison& pc = an.pairs[an.main_pair];
  const std::string stat_text = rep.statistic ? Num(*rep.statistic, rep.statistic_decimals) : "";
  // 1. Range of the statistic under the reported test.
  if (rep.statistic && pc.paired && (rep.test == "paired" || rep.test.empty())) {
    const double n = static_cast<double>(pc.paired->n_pairs);
    const double max_v = n * (n + 1.0) / 2.0;
    if (*rep.statistic > max_v || *rep.statistic < 0.0)
      notes->push_back("The reported statistic " + stat_text +
                       " cannot come from a matched-pairs (signed-rank) test of " +
                       Fmt(n) + " pairs: V, R- and min(R+, R-) all lie in [0, " + Fmt(max_v) +
                       "] (n(n+1)/2 with n = " + Fmt(n) + ").");
  }
  if (rep.statistic && (rep.test == "unpaired" || rep.test.empty())) {
    const double mn = static_cast<double>(pc.unpaired.n_a * pc.unpaired.n_b);
    if (*rep.statistic > mn || *rep.statistic < 0.0)
      notes->push_back("The reported statistic " + stat_text +
                       " cannot come from a rank-sum test of " + std::to_string(pc.unpaired.n_a) +
                       " and " + std::to_string(pc.unpaired.n_b) + " ratings: W lies in [0, " +
                       Fmt(mn) + "].");
  }
  // 2. Which computed result reproduces it.
  std::vector<Candidate> stats;
  std::vector<PCandidate> ps;
  const std::string ab = pc.a + " vs " + pc.b;
  if (pc.paired) {
    const SignedRank& s = *pc.paired;
    stats.push_back({"paired", "V of " + pc.a + " - " + pc.b + " (R's wilcox.test(paired = TRUE))", s.v});
    stats.push_back({"paired", "V of " + pc.b + " - " + pc.a, s.r_minus});
    stats.push_back({"paired", "min(R+, R-) (scipy.stats.wilcoxon)", std::min(s.v, s.r_minus)});
    ps.push_back({"paired", s.method + " (R 4.2 default)", s.p});
    ps.push_back({"paired", "normal approximation without continuity correction (scipy default)",
                  pc.paired_p_uncorrected});
    if (s.p_exact) ps.push_back({"paired", "exact conditional p", *s.p_exact});
  }
  const RankSum& u = pc.unpaired;
  const double mn = static_cast<double>(u.n_a * u.n_b);
  stats.push_back({"unpaired", "W of " + pc.a + " vs " + pc.b + " (R's wilcox.test(" + pc.a + ", " + pc.b + "))", u.w});
  stats.push_back({"unpaired", "W of " + pc.b + " vs " + pc.a, mn - u.w});
  ps.push_back({"unpaired", u.method + " (R 4.2 default, scipy mannwhitneyu default)", u.p});
  ps.push_back({"unpaired", "normal approximation without continuity correction", pc.unpaired_p_uncorrected});
  if (u.p_exact) ps.push_back({"unpaired", "exact conditional p", *u.p_exact});

  std::vector<std::string> full;
  std::vector<std::string> partial;
  for (const char* test : {"paired", "unpaired"}) {
    std::vector<const Candidate*> sm;
    std::vector<const PCandidate*> pm;
    for (const Candidate& c : stats)
      if (c.test == test && rep.statistic && Matches(c.value, *rep.statistic, rep.statistic_decimals)) sm.push_back(&c);
    for (const PCandidate& c : ps)
      if (c.test == test && rep.p && Matches(c.value, *rep.p, rep.p_decimals)) pm.push_back(&c);
    const std::string kind = std::string(test) == "paired" ? "the paired signed-rank test"
                                                           : "the unpaired rank-sum (Mann-Whitney) test";
    const bool need_s = rep.statistic.has_value();
    const bool need_p = rep.p.has_value();
    if ((!need_s || !sm.empty()) && (!need_p || !pm.empty()) && (need_s || need_p)) {
      std::string what = kind + " of " + ab + ":";
      for (const Candidate* c : sm) what += " " + c->statistic + " = " + Fmt(c->value) + ";";
      for (const PCandidate* c : pm) what += " p = " + Num(c->value, rep.p_decimals + 2) + " (" + c->what + ");";
      what.pop_back();
      full.push_back(what);
    } else if (!sm.empty() || !pm.empty()) {
      std::string what = kind + " matches only the " + (sm.empty() ? "p-value" : "statistic") + ":";
      for (const Candidate* c : sm) what += " " + c->statistic + " = " + Fmt(c->value) + ";";
      for (const PCandidate* c : pm) what += " p = " + Num(c->value, rep.p_decimals + 2) + " (" + c->what + ");";
      what.pop_back();
      partial.push_back(what);
    }
  }
  const std::string label = "The reported result (" + rep.text + ")";
  if (!full.empty()) {
    std::string note = label + " is reproduced by " + full.front();
    for (std::size_t i = 1; i < full.size(); ++i) note += "; and by " + full[i];
    note += ".";
    const bool reported_paired = rep.test == "paired";
    bool only_unpaired = true;
    for (const std::string& f : full)
      if (f.find("paired signed-rank") != std::string::npos && f.find("unpaired") == std::string::npos) only_unpaired = false;
    if (reported_paired && only_unpaired)
      note += " It was reported as a matched-pairs test, but only the unpaired test gives it.";
    notes->push_back(note);
  } else {
    notes->push_back(label + " is not reproduced by any test computed here on these ratings" +
                     (partial.empty() ? std::string(".") : " (partial matches: " + JoinNames(partial) + ")."));
  }
}

}  // namespace

Reported ParseReported(const std::string& text) {
  Reported r;
  r.text = text;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument("option --reported: expected KEY=VALUE items, got '" + item + "'");
    std::string key = item.substr(0, eq);
    std::string value = item.substr(eq + 1);
    key.erase(0, key.find_first_not_of(' '));
    key.erase(key.find_last_not_of(' ') + 1);
    value.erase(0, value.find_first_not_of(' '));
    value.erase(value.find_last_not_of(' ') + 1);
    if (key == "test") {
      if (value != "paired" && value != "unpaired")
        throw std::invalid_argument("option --reported: key 'test': expected paired or unpaired, got '" + value + "'");
      r.test = value;
      continue;
    }
    const std::optional<double> number = ParseFiniteNumber(value);
    if (!number)
      throw std::invalid_argument("option --reported: key '" + key + "': expected a number, got '" + value + "'");
    const double v = *number;
    if (key == "W" || key == "V" || key == "U" || key == "statistic") {
      r.statistic = v;
      r.statistic_decimals = DecimalsOf(value);
    } else if (key == "p") {
      r.p = v;
      r.p_decimals = DecimalsOf(value);
    } else {
      throw std::invalid_argument("option --reported: unknown key '" + key + "' (expected test, W, V, U, statistic or p)");
    }
  }
  if (!r.statistic && !r.p) throw std::invalid_argument("option --reported: give a statistic (W=...) or p=...");
  return r;
}

StudyAnalysis Analyse(const Ratings& ratings, const AnalysisOptions& options) {
  StudyAnalysis an;
  for (const std::string& c : ratings.conditions) {
    ConditionSummary s;
    s.name = c;
    s.values = ratings.Values(c);
    s.stats = Describe(s.values);
    if (s.stats.max - s.stats.min >= 1e-10) s.shapiro_wilk = ShapiroWilkTest(s.values);
    an.conditions.push_back(std::move(s));
  }
  std::string a = ratings.conditions[0];
  std::string b = ratings.conditions[1];
  if (options.conditions) {
    for (const std::string* name : {&options.conditions->first, &options.conditions->second})
      if (std::find(ratings.conditions.begin(), ratings.conditions.end(), *name) == ratings.conditions.end())
        throw InputError(ratings.file, 0, "condition",
                         "the conditions named by --conditions (file has " + JoinNames(ratings.conditions) + ")",
                         "\"" + *name + "\"");
    if (options.conditions->first == options.conditions->second)
      throw std::invalid_argument("option --conditions: expected two different conditions");
    a = options.conditions->first;
    b = options.conditions->second;
  }
  an.pairs.push_back(Compare(ratings, a, b));
  for (std::size_t i = 0; i < ratings.conditions.size(); ++i)
    for (std::size_t j = i + 1; j < ratings.conditions.size(); ++j) {
      const std::set<std::string> pair{ratings.conditions[i], ratings.conditions[j]};
      if (pair == std::set<std::string>{a, b}) continue;
      an.pairs.push_back(Compare(ratings, ratings.conditions[i], ratings.conditions[j]));
    }

  // Notes.
  for (const ConditionSummary& s : an.conditions) {
    std::set<double> distinct(s.values.begin(), s.values.end());
    if (!s.shapiro_wilk) {
      an.notes.push_back("Every rating of " + s.name + " is " + Fmt(s.values.front()) +
                         ": Shapiro-Wilk is undefined (shapiro_wilk is null).");
    } else if (distinct.size() <= 7) {
      an.notes.push_back("The ratings of " + s.name + " take " + std::to_string(distinct.size()) +
                         " distinct values: Shapiro-Wilk (W = " + Num(s.shapiro_wilk->w, 4) +
                         ", p = " + Fmt(s.shapiro_wilk->p) +
                         ") tests a discrete scale, which is never normal; the rank tests do not assume normality.");
    }
  }
  for (const PairComparison& pc : an.pairs) {
    const std::string ab = pc.a + " vs " + pc.b;
    if (!pc.left_out.empty())
      an.notes.push_back(ab + ": participant(s) " + JoinNames(pc.left_out) + " rated only one of the two " +
                         "conditions and are left out of the paired test.");
    if (pc.paired) {
      const SignedRank& s = *pc.paired;
      if (s.n_zero > 0 || s.ties) {
        std::string why;
        if (s.n_zero > 0) why += std::to_string(s.n_zero) + " zero difference(s) (dropped, Wilcoxon's method as R 4.2)";
        if (s.ties) why += std::string(why.empty() ? "" : " and ") + "tied differences";
        an.notes.push_back(ab + ", paired: " + why + " make R's exact test impossible: p = " + Fmt(s.p) +
                           " is the normal approximation with continuity correction; the exact conditional p " +
                           (s.p_exact ? "is " + Fmt(*s.p_exact) : std::string("was not computed (too large)")) +
                           ". R >= 4.6 computes exact conditional p-values by default and keeps zeros, so it reports a different p.");
      }
    } else {
      an.notes.push_back(ab + ": no participant rated both: no paired test.");
    }
    if (pc.unpaired.ties)
      an.notes.push_back(ab + ", unpaired: tied ratings make R's exact test impossible: p = " + Fmt(pc.unpaired.p) +
                         " is the normal approximation with tie-corrected variance and continuity correction; the exact conditional p " +
                         (pc.unpaired.p_exact ? "is " + Fmt(*pc.unpaired.p_exact) : std::string("was not computed (too large)")) + ".");
  }
  if (ratings.has_order) {
    OrderEffect oe;
    std::vector<double> first, second;
    for (const std::string& p : ratings.participants) {
      const Rating* r1 = nullptr;
      const Rating* r2 = nullptr;
      for (const Rating& r : ratings.rows) {
        if (r.participant != p || !r.order) continue;
        if (*r.order == 1) r1 = &r;
        if (*r.order == 2) r2 = &r;
      }
      if (r1 == nullptr) continue;
      auto it = std::find_if(oe.first_counts.begin(), oe.first_counts.end(),
                             [&](const auto& c) { return c.first == r1->condition; });
      if (it == oe.first_counts.end()) {
        oe.first_counts.emplace_back(r1->condition, 1);
      } else {
        ++it->second;
      }
      if (r2 == nullptr) continue;
      first.push_back(r1->value);
      second.push_back(r2->value);
    }
    oe.n_participants = first.size();
    if (!first.empty()) {
      for (std::size_t i = 0; i < first.size(); ++i) {
        oe.mean_first += first[i];
        oe.mean_second += second[i];
      }
      oe.mean_first /= static_cast<double>(first.size());
      oe.mean_second /= static_cast<double>(first.size());
      oe.test = SignedRankTest(first, second);
      std::string counts;
      for (const auto& [c, k] : oe.first_counts) counts += (counts.empty() ? "" : ", ") + c + " first: " + std::to_string(k);
      an.notes.push_back("Order: " + std::to_string(oe.n_participants) + " participants rated a first and a second ride (" +
                         counts + "); mean rating of the first ride " + Num(oe.mean_first, 3) + ", of the second " +
                         Num(oe.mean_second, 3) + ", paired signed-rank p = " + Fmt(oe.test->p) +
                         (oe.test->p < 0.05 ? ": an order effect; check that the conditions were counterbalanced." : "."));
    }
    an.order = oe;
  }
  if (options.reported) CheckReported(an, *options.reported, &an.notes);
  return an;
}

}  // namespace pwsim::study
