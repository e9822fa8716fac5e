// study/plan.h: Williams sequences balance position and carry-over; the plan is counterbalanced,
// reproducible from its seed, and different for another seed; plan.csv reads back.

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>

#include "engine/input_error.h"
#include "study/plan.h"
#include "study/ratings.h"
#include "tests/study/study_test_util.h"

namespace pwsim::study {
namespace {

TEST(Plan, WilliamsSequencesAreBalanced) {
  for (int k = 2; k <= 7; ++k) {
    const auto seq = WilliamsSequences(k);
    ASSERT_EQ(seq.size(), static_cast<std::size_t>(k % 2 ? 2 * k : k)) << k;
    // every condition in every position equally often
    std::map<std::pair<int, int>, int> position;
    std::map<std::pair<int, int>, int> follows;
    for (const auto& s : seq) {
      ASSERT_EQ(std::set<int>(s.begin(), s.end()).size(), static_cast<std::size_t>(k));
      for (int i = 0; i < k; ++i) ++position[{i, s[static_cast<std::size_t>(i)]}];
      for (int i = 1; i < k; ++i) ++follows[{s[static_cast<std::size_t>(i - 1)], s[static_cast<std::size_t>(i)]}];
    }
    const int per = static_cast<int>(seq.size()) / k;
    for (const auto& [key, count] : position) EXPECT_EQ(count, per) << "k=" << k;
    EXPECT_EQ(follows.size(), static_cast<std::size_t>(k * (k - 1))) << "k=" << k;
    for (const auto& [key, count] : follows) EXPECT_EQ(count, k % 2 ? 2 : 1) << "k=" << k;
  }
}

TEST(Plan, CounterbalancedAndSeeded) {
  PlanOptions o;
  o.participants = 18;
  o.conditions = {"T_r", "T_m"};
  o.seed = 7;
  const StudyPlan a = MakePlan(o);
  ASSERT_EQ(a.trials.size(), 36u);
  EXPECT_EQ(a.participants_per_sequence, (std::vector<int>{9, 9}));
  int first_tr = 0;
  for (const PlanTrial& t : a.trials)
    if (t.trial_index == 1 && t.condition == "T_r") ++first_tr;
  EXPECT_EQ(first_tr, 9);
  EXPECT_EQ(PlanCsv(MakePlan(o)), PlanCsv(a));  // reproducible
  o.seed = 8;
  EXPECT_NE(PlanCsv(MakePlan(o)), PlanCsv(a));  // randomised
  o.participants = 5;
  o.conditions = {"A", "B", "C"};
  const StudyPlan odd = MakePlan(o);
  EXPECT_EQ(odd.trials.size(), 15u);
  EXPECT_EQ(odd.trials.front().participant, "P01");
  o.conditions = {"A", "A"};
  EXPECT_THROW(MakePlan(o), std::invalid_argument);
}

TEST(Plan, CsvReadsBackAndTemplateNeedsRatings) {
  PlanOptions o;
  o.participants = 4;
  const StudyPlan plan = MakePlan(o);
  const auto dir = test_util::TempDir("plan");
  std::ofstream(dir / "plan.csv") << PlanCsv(plan);
  const std::vector<PlanTrial> back = ReadPlan(dir / "plan.csv");
  ASSERT_EQ(back.size(), plan.trials.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].participant, plan.trials[i].participant);
    EXPECT_EQ(back[i].condition, plan.trials[i].condition);
    EXPECT_EQ(back[i].trial_index, plan.trials[i].trial_index);
  }
  EXPECT_EQ(FindPlannedTrial(back, "plan.csv", "P02", 2).condition, plan.trials[3].condition);
  EXPECT_THROW(FindPlannedTrial(back, "plan.csv", "P09", 1), InputError);
  EXPECT_THROW(FindPlannedTrial(back, "plan.csv", "P02", 3), InputError);
  // the unfilled template is refused (empty rating), naming the line
  try {
    ParseRatings(RatingsTemplateCsv(plan), "ratings_template.csv");
    ADD_FAILURE() << "template accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "rating");
    EXPECT_EQ(e.line(), 3);
  }
  std::ofstream(dir / "bad.csv") << "participant,trial_index,condition\nP1,zero,A\n";
  EXPECT_THROW(ReadPlan(dir / "bad.csv"), InputError);
}

}  // namespace
}  // namespace pwsim::study
