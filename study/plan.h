#pragma once
// The protocol of a within-subject perception study: every participant experiences every
// condition once, in an order that is counterbalanced over participants and randomised.
//
// Counterbalancing: a Williams design (balanced Latin square). For k conditions numbered
// 0..k−1 the first sequence is 0, 1, k−1, 2, k−2, 3, …; sequence i adds i (mod k) to each
// entry. For even k these k sequences balance position and first-order carry-over (every
// condition follows every other exactly once); for odd k the k mirrored sequences are added
// (2k in all). For k = 2: (A, B) and (B, A).
// Randomisation: participants are taken in blocks of as many participants as sequences; each
// block receives every sequence once, in an order drawn by std::mt19937_64 seeded with `seed`
// (std::shuffle is not specified portably, so a Fisher-Yates shuffle on the raw generator
// output is used: the same seed gives the same plan on every platform).
// With N not a multiple of the number of sequences the last block is incomplete; the plan
// says how many participants follow each sequence.
//
// Files:
//   plan.csv       participant,trial_index,condition,sequence   (one row per trial)
//   ratings.csv    participant,condition,rating,order            (the template; rating empty)
// `pwsim session --plan plan.csv --participant P --trial-index K` replays trial K of P.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pwsim::study {

struct PlanOptions {
  int participants{18};
  std::vector<std::string> conditions{"T_r", "T_m"};
  std::uint64_t seed{1};
  std::string prefix{"P"};  ///< participant ids: prefix + zero-padded number (P01, …)
  std::string Validate() const;  ///< "" when valid, else which field is wrong and why
};

struct PlanTrial {
  std::string participant;
  int trial_index{0};  ///< 1-based position in the participant's sequence
  std::string condition;
  int sequence{0};     ///< 1-based index of the Williams sequence
};

struct StudyPlan {
  std::vector<PlanTrial> trials;                  ///< by participant, then trial_index
  std::vector<std::vector<std::string>> sequences;  ///< the Williams sequences
  std::vector<int> participants_per_sequence;
};

/// The Williams sequences for k conditions (indices 0..k−1).
std::vector<std::vector<int>> WilliamsSequences(int k);

/// @throws std::invalid_argument (options.Validate()).
StudyPlan MakePlan(const PlanOptions& options);

std::string PlanCsv(const StudyPlan& plan);
std::string RatingsTemplateCsv(const StudyPlan& plan);

/// Reads a plan.csv (header participant,trial_index,condition[,sequence]). @throws InputError.
std::vector<PlanTrial> ReadPlan(const std::filesystem::path& file);
/// The trial of `participant` at `trial_index`. @throws InputError naming the plan file.
PlanTrial FindPlannedTrial(const std::vector<PlanTrial>& plan, const std::string& file,
                           const std::string& participant, int trial_index);

}  // namespace pwsim::study
