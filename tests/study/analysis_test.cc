// study/analysis.h and study/report.h: the headline pair, participants left out of the paired
// test, the notes (ties, zeros, discrete scales) and the check of a published result, on the
// seed paper's case; study.json carries the spec's keys.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sstream>

#include "engine/input_error.h"
#include "study/analysis.h"
#include "study/report.h"

namespace pwsim::study {
namespace {

/// Ratings text of the seed's reconstructed study: T_m = {1:3, 2:14, 3:1}, T_r = {1:6, 2:10,
/// 3:2} (docs/study.md); the pairing of the two ratings of a participant is arbitrary here.
std::string PaperRatings() {
  const int tm[18] = {1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 3};
  const int tr[18] = {2, 1, 2, 1, 2, 2, 3, 1, 2, 2, 1, 2, 2, 3, 1, 2, 2, 1};
  std::ostringstream s;
  s << "participant,condition,rating\n";
  for (int i = 0; i < 18; ++i) {
    s << "P" << (i < 9 ? "0" : "") << i + 1 << ",T_m," << tm[i] << "\n";
    s << "P" << (i < 9 ? "0" : "") << i + 1 << ",T_r," << tr[i] << "\n";
  }
  return s.str();
}

bool HasNote(const StudyAnalysis& an, const std::string& part) {
  for (const std::string& n : an.notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

std::string AllNotes(const StudyAnalysis& an) {
  std::string all;
  for (const std::string& n : an.notes) all += n + "\n";
  return all;
}

TEST(Analysis, PaperCaseReportedResultIsTheUnpairedTest) {
  const Ratings ratings = ParseRatings(PaperRatings(), "paper.csv");
  AnalysisOptions options;
  options.reported = ParseReported("test=paired,W=180,p=0.5045");
  const StudyAnalysis an = Analyse(ratings, options);
  ASSERT_EQ(an.conditions.size(), 2u);
  EXPECT_NEAR(an.conditions[0].stats.mean, 34.0 / 18.0, 1e-12);
  EXPECT_NEAR(an.conditions[1].stats.mean, 32.0 / 18.0, 1e-12);
  EXPECT_EQ(an.conditions[0].stats.median, 2.0);
  const PairComparison& pc = an.pairs[an.main_pair];
  EXPECT_EQ(pc.a, "T_m");
  EXPECT_EQ(pc.unpaired.w, 180.0);
  EXPECT_TRUE(HasNote(an, "cannot come from a matched-pairs (signed-rank) test of 18 pairs")) << AllNotes(an);
  EXPECT_TRUE(HasNote(an, "[0, 171]")) << AllNotes(an);
  EXPECT_TRUE(HasNote(an, "is reproduced by the unpaired rank-sum (Mann-Whitney) test of T_m vs T_r")) << AllNotes(an);
  EXPECT_TRUE(HasNote(an, "only the unpaired test gives it")) << AllNotes(an);
  EXPECT_TRUE(HasNote(an, "take 3 distinct values")) << AllNotes(an);
}

TEST(Analysis, AReportedResultThatNothingGives) {
  const Ratings ratings = ParseRatings(PaperRatings(), "paper.csv");
  AnalysisOptions options;
  options.reported = ParseReported("test=unpaired,W=150,p=0.01");
  const StudyAnalysis an = Analyse(ratings, options);
  EXPECT_TRUE(HasNote(an, "is not reproduced by any test")) << AllNotes(an);
  EXPECT_FALSE(HasNote(an, "cannot come from"));
}

TEST(Analysis, ReversedHeadlinePairAndLeftOutParticipant) {
  std::string text = PaperRatings() + "P19,T_r,2\n";
  const Ratings ratings = ParseRatings(text, "x.csv");
  AnalysisOptions options;
  options.conditions = std::make_pair(std::string("T_r"), std::string("T_m"));
  const StudyAnalysis an = Analyse(ratings, options);
  const PairComparison& pc = an.pairs[an.main_pair];
  EXPECT_EQ(pc.a, "T_r");
  EXPECT_EQ(pc.unpaired.n_a, 19u);
  EXPECT_EQ(pc.left_out, (std::vector<std::string>{"P19"}));
  ASSERT_TRUE(pc.paired.has_value());
  EXPECT_EQ(pc.paired->n_pairs, 18u);
  EXPECT_TRUE(HasNote(an, "P19 rated only one")) << AllNotes(an);
  options.conditions = std::make_pair(std::string("T_r"), std::string("T_x"));
  EXPECT_THROW(Analyse(ratings, options), InputError);
}

TEST(Analysis, EveryPairOfThreeConditions) {
  std::ostringstream s;
  s << "participant,condition,rating\n";
  for (int i = 0; i < 6; ++i)
    s << "P" << i << ",A," << 1 + i % 3 << "\nP" << i << ",B," << 2 + i % 2 << "\nP" << i << ",C," << 1 + i << "\n";
  const StudyAnalysis an = Analyse(ParseRatings(s.str(), "three.csv"));
  ASSERT_EQ(an.pairs.size(), 3u);
  EXPECT_EQ(an.pairs[0].a + an.pairs[0].b, "AB");
  EXPECT_EQ(an.pairs[1].a + an.pairs[1].b, "AC");
  EXPECT_EQ(an.pairs[2].a + an.pairs[2].b, "BC");
}

TEST(Analysis, OrderEffectFromTheOrderColumn) {
  // every participant rates 1 on the first ride and 3 on the second: a pure order effect
  std::ostringstream s;
  s << "\xEF\xBB\xBFparticipant,condition,rating,order\r\n";  // Excel's BOM and CRLF
  for (int i = 0; i < 10; ++i) {
    const bool a_first = i % 2 == 0;
    s << "P" << i << ",A," << (a_first ? 1 : 3) << "," << (a_first ? 1 : 2) << "\r\n";
    s << "P" << i << ",B," << (a_first ? 3 : 1) << "," << (a_first ? 2 : 1) << "\r\n";
  }
  const StudyAnalysis an = Analyse(ParseRatings(s.str(), "order.csv"));
  ASSERT_TRUE(an.order.has_value());
  EXPECT_EQ(an.order->n_participants, 10u);
  EXPECT_EQ(an.order->mean_first, 1.0);
  EXPECT_EQ(an.order->mean_second, 3.0);
  ASSERT_TRUE(an.order->test.has_value());
  EXPECT_LT(an.order->test->p, 0.01);
  EXPECT_TRUE(HasNote(an, "A first: 5, B first: 5")) << AllNotes(an);
  EXPECT_TRUE(HasNote(an, "an order effect")) << AllNotes(an);
  const nlohmann::json j = nlohmann::json::parse(StudyJson(an));
  EXPECT_EQ(j["order_effect"]["first"]["A"], 5);
  // without an order column there is no order analysis
  EXPECT_FALSE(Analyse(ParseRatings(PaperRatings(), "p.csv")).order.has_value());
}

TEST(Report, JsonHasTheSpecKeys) {
  AnalysisOptions options;
  options.reported = ParseReported("test=paired,W=180,p=0.5045");
  const StudyAnalysis an = Analyse(ParseRatings(PaperRatings(), "paper.csv"), options);
  const nlohmann::json j = nlohmann::json::parse(StudyJson(an));
  EXPECT_EQ(j["format"], "pwsim-study/1");
  for (const char* c : {"T_m", "T_r"})
    for (const char* key : {"n", "mean", "median", "q1", "q3", "min", "max"})
      EXPECT_TRUE(j["conditions"][c].contains(key)) << c << " " << key;
  EXPECT_TRUE(j["conditions"]["T_m"]["shapiro_wilk"].contains("w"));
  for (const char* key : {"test", "a", "b", "n_pairs", "n_nonzero", "v", "p", "p_exact", "method"})
    EXPECT_TRUE(j["paired"].contains(key)) << key;
  for (const char* key : {"test", "a", "b", "w", "p", "method"}) EXPECT_TRUE(j["unpaired"].contains(key)) << key;
  EXPECT_EQ(j["paired"]["test"], "wilcoxon_signed_rank");
  EXPECT_EQ(j["unpaired"]["test"], "mann_whitney");
  EXPECT_EQ(j["unpaired"]["w"], 180.0);
  EXPECT_TRUE(j["effect_size"].contains("matched_rank_biserial"));
  EXPECT_NEAR(j["effect_size"]["rank_biserial"].get<double>(), 2.0 * 180.0 / 324.0 - 1.0, 1e-12);
  EXPECT_GE(j["notes"].size(), 3u);
  const std::string md = StudyMarkdown(an, "paper.csv", "boxplot.png");
  EXPECT_NE(md.find("W = 180"), std::string::npos);
  EXPECT_NE(md.find("![ratings"), std::string::npos);
}

TEST(Reported, ParsesAndRefuses) {
  const Reported r = ParseReported("test=paired, W=180, p=0.5045");
  EXPECT_EQ(r.test, "paired");
  EXPECT_EQ(*r.statistic, 180.0);
  EXPECT_EQ(r.statistic_decimals, 0);
  EXPECT_EQ(r.p_decimals, 4);
  EXPECT_THROW(ParseReported("test=twice,W=1"), std::invalid_argument);
  EXPECT_THROW(ParseReported("W=abc"), std::invalid_argument);
  EXPECT_THROW(ParseReported("Q=1"), std::invalid_argument);
  EXPECT_THROW(ParseReported("test=paired"), std::invalid_argument);
}

}  // namespace
}  // namespace pwsim::study
