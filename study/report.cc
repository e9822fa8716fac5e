#include "study/report.h"

#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/number_format.h"

namespace pwsim::study {
namespace {

using nlohmann::ordered_json;

// A number as its shortest round-trip decimal (FormatDouble), so study.json is reproducible.
ordered_json Number(double v) { return ordered_json::parse(FormatDouble(v)); }
ordered_json Optional(const std::optional<double>& v) { return v ? Number(*v) : ordered_json(nullptr); }

ordered_json PairedJson(const PairComparison& pc) {
  ordered_json j;
  j["test"] = "wilcoxon_signed_rank";
  j["a"] = pc.a;
  j["b"] = pc.b;
  if (!pc.paired) {
    j["n_pairs"] = 0;
    j["n_nonzero"] = 0;
    j["v"] = nullptr;
    j["p"] = nullptr;
    j["p_exact"] = nullptr;
    j["method"] = "no participant rated both conditions";
    j["left_out"] = pc.left_out;
    return j;
  }
  const SignedRank& s = *pc.paired;
  j["n_pairs"] = s.n_pairs;
  j["n_nonzero"] = s.n_nonzero;
  j["v"] = Number(s.v);
  j["p"] = Number(s.p);
  j["p_exact"] = Optional(s.p_exact);
  j["method"] = s.method;
  j["n_zero"] = s.n_zero;
  j["ties"] = s.ties;
  j["r_minus"] = Number(s.r_minus);
  j["z"] = Number(s.z);
  j["p_uncorrected"] = Number(pc.paired_p_uncorrected);
  j["left_out"] = pc.left_out;
  return j;
}

ordered_json UnpairedJson(const PairComparison& pc) {
  const RankSum& u = pc.unpaired;
  ordered_json j;
  j["test"] = "mann_whitney";
  j["a"] = pc.a;
  j["b"] = pc.b;
  j["w"] = Number(u.w);
  j["p"] = Number(u.p);
  j["method"] = u.method;
  j["n_a"] = u.n_a;
  j["n_b"] = u.n_b;
  j["ties"] = u.ties;
  j["z"] = Number(u.z);
  j["p_uncorrected"] = Number(pc.unpaired_p_uncorrected);
  j["p_exact"] = Optional(u.p_exact);
  return j;
}

ordered_json EffectJson(const PairComparison& pc) {
  ordered_json j;
  j["matched_rank_biserial"] = pc.paired ? Number(pc.paired->matched_rank_biserial) : ordered_json(nullptr);
  j["rank_biserial"] = Number(pc.unpaired.rank_biserial);
  return j;
}

std::string Fixed(double v, int decimals) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << v;
  return s.str();
}

std::string P(double p) {
  if (p >= 1e-4) return Fixed(p, 4);
  std::ostringstream s;
  s.precision(2);
  s << p;
  return s.str();
}

}  // namespace

std::string StudyJson(const StudyAnalysis& an) {
  ordered_json j;
  j["format"] = "pwsim-study/1";
  ordered_json conditions = ordered_json::object();
  for (const ConditionSummary& c : an.conditions) {
    ordered_json s;
    s["n"] = c.stats.n;
    s["mean"] = Number(c.stats.mean);
    s["median"] = Number(c.stats.median);
    s["q1"] = Number(c.stats.q1);
    s["q3"] = Number(c.stats.q3);
    s["min"] = Number(c.stats.min);
    s["max"] = Number(c.stats.max);
    if (c.shapiro_wilk) {
      s["shapiro_wilk"] = {{"w", Number(c.shapiro_wilk->w)}, {"p", Number(c.shapiro_wilk->p)}};
    } else {
      s["shapiro_wilk"] = nullptr;
    }
    s["sd"] = Number(c.stats.sd);
    conditions[c.name] = s;
  }
  j["conditions"] = conditions;
  const PairComparison& main = an.pairs[an.main_pair];
  j["paired"] = PairedJson(main);
  j["unpaired"] = UnpairedJson(main);
  j["effect_size"] = EffectJson(main);
  j["notes"] = an.notes;
  if (an.order && an.order->test) {
    ordered_json o;
    o["n_participants"] = an.order->n_participants;
    o["mean_first"] = Number(an.order->mean_first);
    o["mean_second"] = Number(an.order->mean_second);
    o["v"] = Number(an.order->test->v);
    o["p"] = Number(an.order->test->p);
    o["method"] = an.order->test->method;
    ordered_json counts = ordered_json::object();
    for (const auto& [c, k] : an.order->first_counts) counts[c] = k;
    o["first"] = counts;
    j["order_effect"] = o;
  }
  ordered_json pairs = ordered_json::array();
  for (const PairComparison& pc : an.pairs)
    pairs.push_back({{"paired", PairedJson(pc)}, {"unpaired", UnpairedJson(pc)}, {"effect_size", EffectJson(pc)}});
  j["pairs"] = pairs;
  return j.dump(2) + "\n";
}

std::string StudyMarkdown(const StudyAnalysis& an, const std::string& ratings_file,
                          const std::string& boxplot) {
  std::ostringstream md;
  md << "# User study: ratings and statistics\n\n"
     << "Ratings: `" << ratings_file << "`. Conventions as R 4.2's `wilcox.test` and `shapiro.test`"
     << " (see shared/spec/study.md); quartiles are R's `quantile(type = 7)`.\n\n";
  md << "| condition | n | mean | sd | median | q1 | q3 | min | max | Shapiro-Wilk W | p |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ConditionSummary& c : an.conditions) {
    md << "| " << c.name << " | " << c.stats.n << " | " << Fixed(c.stats.mean, 3) << " | "
       << Fixed(c.stats.sd, 3) << " | " << Fixed(c.stats.median, 2) << " | " << Fixed(c.stats.q1, 2)
       << " | " << Fixed(c.stats.q3, 2) << " | " << Fixed(c.stats.min, 2) << " | "
       << Fixed(c.stats.max, 2) << " | "
       << (c.shapiro_wilk ? Fixed(c.shapiro_wilk->w, 4) + " | " + P(c.shapiro_wilk->p) : std::string("- | -"))
       << " |\n";
  }
  md << "\n## Comparisons\n\n"
     << "| a vs b | test | n | statistic | p (R 4.2 default) | method | p exact (conditional) | effect size |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const PairComparison& pc : an.pairs) {
    if (pc.paired) {
      const SignedRank& s = *pc.paired;
      md << "| " << pc.a << " vs " << pc.b << " | paired signed-rank | " << s.n_pairs << " pairs ("
         << s.n_nonzero << " non-zero) | V = " << FormatDouble(s.v) << " | " << P(s.p) << " | "
         << s.method << " | " << (s.p_exact ? P(*s.p_exact) : "-") << " | matched rank-biserial "
         << Fixed(s.matched_rank_biserial, 3) << " |\n";
    }
    const RankSum& u = pc.unpaired;
    md << "| " << pc.a << " vs " << pc.b << " | unpaired rank-sum (Mann-Whitney) | " << u.n_a << " + "
       << u.n_b << " | W = " << FormatDouble(u.w) << " | " << P(u.p) << " | " << u.method << " | "
       << (u.p_exact ? P(*u.p_exact) : "-") << " | rank-biserial " << Fixed(u.rank_biserial, 3) << " |\n";
  }
  if (!an.notes.empty()) {
    md << "\n## Notes\n\n";
    for (const std::string& n : an.notes) md << "- " << n << "\n";
  }
  if (!boxplot.empty())
    md << "\n## Ratings\n\n![ratings per condition: median, quartiles, extremes, every rating](" << boxplot << ")\n";
  return md.str();
}

}  // namespace pwsim::study
