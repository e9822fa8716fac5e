// study/ratings.h: the ratings reader accepts the spec's format and refuses bad input with
// the line and field named.

#include <gtest/gtest.h>

#include <string>

#include "engine/input_error.h"
#include "study/ratings.h"

namespace pwsim::study {
namespace {

std::string Good() {
  return "participant,condition,rating,order\n"
         "P01,T_m,2,1\nP01,T_r,1,2\n"
         "P02,T_r,2,1\nP02,T_m,2,2\n"
         "# a comment\n\n"
         "P03,T_m,3,1\nP03,T_r,2,2\n";
}

/// The InputError of parsing `text`, or a test failure.
InputError ErrorOf(const std::string& text) {
  try {
    ParseRatings(text, "r.csv");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return InputError("", 0, "", "", "");
}

TEST(Ratings, ReadsTheSpecFormat) {
  const Ratings r = ParseRatings(Good(), "r.csv");
  EXPECT_EQ(r.rows.size(), 6u);
  EXPECT_EQ(r.conditions, (std::vector<std::string>{"T_m", "T_r"}));
  EXPECT_EQ(r.participants, (std::vector<std::string>{"P01", "P02", "P03"}));
  EXPECT_EQ(r.Values("T_m"), (std::vector<double>{2, 2, 3}));
  ASSERT_TRUE(r.rows[1].order.has_value());
  EXPECT_EQ(*r.rows[1].order, 2);
  EXPECT_EQ(r.rows[4].line, 8);  // after a comment and a blank line
}

TEST(Ratings, ColumnsInAnyOrderAndOrderOptional) {
  const Ratings r = ParseRatings("rating,condition,participant\n1,A,p\n2,A,q\n3,A,s\n1.5,B,p\n2,B,q\n4,B,s\n", "x");
  EXPECT_FALSE(r.has_order);
  EXPECT_EQ(r.Values("B"), (std::vector<double>{1.5, 2, 4}));
}

TEST(Ratings, UnknownColumn) {
  const InputError e = ErrorOf("participant,condition,rating,score\nP1,A,1,2\n");
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.field(), "header column 4");
  EXPECT_NE(std::string(e.what()).find("\"score\""), std::string::npos) << e.what();
}

TEST(Ratings, MissingColumn) {
  const InputError e = ErrorOf("participant,condition\nP1,A\n");
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.field(), "header");
  EXPECT_NE(std::string(e.what()).find("'rating'"), std::string::npos) << e.what();
}

TEST(Ratings, NonNumericRatingNamesLineAndField) {
  std::string text = Good();
  text.replace(text.find("P02,T_m,2,2"), 11, "P02,T_m,two,2");
  const InputError e = ErrorOf(text);
  EXPECT_EQ(e.line(), 5);
  EXPECT_EQ(e.field(), "rating");
  EXPECT_NE(std::string(e.what()).find("\"two\""), std::string::npos) << e.what();
  EXPECT_EQ(ErrorOf("participant,condition,rating\nP1,A,\n").field(), "rating");
  EXPECT_EQ(ErrorOf("participant,condition,rating\nP1,A,nan\n").field(), "rating");
  EXPECT_EQ(ErrorOf("participant,condition,rating\nP1,A,inf\n").field(), "rating");
}

TEST(Ratings, SameConditionTwice) {
  std::string text = Good() + "P02,T_r,3,3\n";
  const InputError e = ErrorOf(text);
  EXPECT_EQ(e.line(), 10);
  EXPECT_EQ(e.field(), "condition");
  EXPECT_NE(std::string(e.what()).find("first on line 4"), std::string::npos) << e.what();
}

TEST(Ratings, FewerThanThreeRatingsPerCondition) {
  const InputError e = ErrorOf("participant,condition,rating\nP1,A,1\nP2,A,2\nP3,A,3\nP1,B,1\nP2,B,2\n");
  EXPECT_EQ(e.field(), "rating");
  EXPECT_EQ(e.line(), 5);  // the first rating of B
  EXPECT_NE(std::string(e.what()).find("2 for condition \"B\""), std::string::npos) << e.what();
}

TEST(Ratings, OneConditionOnly) {
  EXPECT_EQ(ErrorOf("participant,condition,rating\nP1,A,1\nP2,A,2\nP3,A,3\n").field(), "condition");
}

TEST(Ratings, WrongFieldCountBadOrderEmptyNames) {
  EXPECT_EQ(ErrorOf("participant,condition,rating\nP1,A\n").line(), 2);
  EXPECT_EQ(ErrorOf("participant,condition,rating,order\nP1,A,1,0\n").field(), "order");
  EXPECT_EQ(ErrorOf("participant,condition,rating,order\nP1,A,1,x\n").field(), "order");
  EXPECT_EQ(ErrorOf("participant,condition,rating\n,A,1\n").field(), "participant");
  EXPECT_EQ(ErrorOf("participant,condition,rating\nP1,,1\n").field(), "condition");
  EXPECT_EQ(ErrorOf("participant,condition,rating\n\"P1\",A,1\n").field(), "line");
  EXPECT_EQ(ErrorOf("").field(), "header");
}

TEST(Ratings, MissingFile) {
  EXPECT_THROW(ReadRatings("/nonexistent/ratings.csv"), InputError);
}

// Tests that a rating beyond any scale (1e308: finite, but its square overflows) is refused at
// its line and field, and that a directory named as the ratings file says so.
TEST(Ratings, HugeRatingAndDirectoryAreRefused) {
  std::string text = Good();
  text.replace(text.find("P02,T_m,2,2"), 11, "P02,T_m,1e308,2");
  const InputError e = ErrorOf(text);
  EXPECT_EQ(e.line(), 5);
  EXPECT_EQ(e.field(), "rating");
  EXPECT_EQ(e.got(), "\"1e308\"");
  EXPECT_NE(e.expected().find("within +-1e6"), std::string::npos) << e.what();
  EXPECT_EQ(ErrorOf("participant,condition,rating\nP1,A,-2e6\n").field(), "rating");
  try {
    ReadRatings(PWSIM_BINARY_DIR);
    ADD_FAILURE() << "a directory was read as ratings";
  } catch (const InputError& error) {
    EXPECT_EQ(error.got(), "a path that is a directory");
  }
}

}  // namespace
}  // namespace pwsim::study
