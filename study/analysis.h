#pragma once
// The analysis of a user study's ratings (shared/spec/study.md): per condition the descriptive
// statistics and Shapiro–Wilk; per pair of conditions the paired Wilcoxon signed-rank test (on
// the participants who rated both), the unpaired rank-sum (Mann–Whitney) test and effect sizes;
// and notes: what a reader must know to interpret them (ties and zeros, participants left out,
// and, when a published result is given, whether and where it can come from).
//
// Checking a published result: `Reported` holds what a paper states (test kind, statistic,
// p, each with the decimals printed). A signed-rank statistic of n pairs lies in
// [0, n(n+1)/2]; a rank-sum W of sizes m, n in [0, mn]. Every statistic and p-value computed
// here (R's and scipy's conventions, both orders, with and without continuity correction,
// exact conditional) is compared with the reported one at its printed precision, and the notes
// name the matches.

#include <optional>
#include <string>
#include <vector>

#include "study/descriptive.h"
#include "study/rank_sum.h"
#include "study/ratings.h"
#include "study/shapiro_wilk.h"
#include "study/signed_rank.h"

namespace pwsim::study {

struct ConditionSummary {
  std::string name;
  Descriptive stats;
  std::optional<ShapiroWilk> shapiro_wilk;  ///< absent when all ratings are equal
  std::vector<double> values;               ///< file order
};

struct PairComparison {
  std::string a, b;
  std::vector<std::string> paired_participants;
  std::vector<std::string> left_out;  ///< rated only one of a, b
  std::optional<SignedRank> paired;   ///< absent when fewer than 1 complete pair
  RankSum unpaired;
  /// Mann–Whitney without continuity correction (for the notes and the reported-result check).
  double unpaired_p_uncorrected{1.0};
  double paired_p_uncorrected{1.0};
};

/// A result as published, e.g. "matched-paired Wilcoxon, W = 180, p = 0.5045".
struct Reported {
  std::string test;  ///< "paired" or "unpaired" (or empty: unknown)
  std::optional<double> statistic;
  int statistic_decimals{0};
  std::optional<double> p;
  int p_decimals{4};
  std::string text;  ///< as given (for the notes)
};

/// Parses "test=paired,W=180,p=0.5045" (keys: test, W|V|U|statistic, p).
/// @throws std::invalid_argument naming the key.
Reported ParseReported(const std::string& text);

/// Order (period) effect, when the file has an `order` column: per participant with ratings
/// at positions 1 and 2, the first ride's rating against the second's (paired signed-rank), and
/// how many participants had each condition first (counterbalancing check).
struct OrderEffect {
  std::size_t n_participants{0};
  double mean_first{0.0};
  double mean_second{0.0};
  std::optional<SignedRank> test;                          ///< first − second
  std::vector<std::pair<std::string, int>> first_counts;   ///< condition -> participants who had it first
};

struct StudyAnalysis {
  std::optional<OrderEffect> order;
  std::vector<ConditionSummary> conditions;  ///< order of first appearance in the file
  std::vector<PairComparison> pairs;         ///< every pair; pairs[main_pair] is the headline
  std::size_t main_pair{0};
  std::vector<std::string> notes;
};

struct AnalysisOptions {
  std::optional<std::pair<std::string, std::string>> conditions;  ///< the headline pair (a, b)
  std::optional<Reported> reported;
};

/// @throws InputError when a requested condition is not in the file.
StudyAnalysis Analyse(const Ratings& ratings, const AnalysisOptions& options = {});

}  // namespace pwsim::study
