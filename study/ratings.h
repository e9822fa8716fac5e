#pragma once
// The ratings file of a user study (shared/spec/study.md): CSV, one row per rating,
//   participant,condition,rating[,order]
// in any column order; `participant` and `condition` are free strings, `rating` a number,
// `order` (optional) the 1-based position of that trial in the participant's sequence. Blank
// lines and lines starting with '#' are skipped. Fields are separated by commas and trimmed;
// quoting is not supported (a '"' is an error).
//
// Refused with an InputError naming the file, line and field: a missing or unknown column, a
// row with the wrong number of fields, an empty participant or condition, a rating that is not
// a finite number within ±1e6 (every rating scale fits; beyond, the sums of squares of the
// statistics overflow long before any real scale is reached: 1e308 is a typo, not a rating), an order that is not a positive integer, a participant rated twice for the
// same condition, fewer than two conditions, or fewer than 3 ratings for a condition.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pwsim::study {

struct Rating {
  std::string participant;
  std::string condition;
  double value{0.0};
  std::optional<int> order;
  int line{0};  ///< 1-based line in the file
};

struct Ratings {
  std::string file;                     ///< as given (for messages)
  std::vector<Rating> rows;             ///< file order
  std::vector<std::string> conditions;  ///< in order of first appearance
  std::vector<std::string> participants;  ///< in order of first appearance
  bool has_order{false};

  /// The ratings of one condition, file order.
  std::vector<double> Values(const std::string& condition) const;
  const Rating* Find(const std::string& participant, const std::string& condition) const;
};

/// @throws InputError (see above).
Ratings ReadRatings(const std::filesystem::path& file);
/// The same checks on text (`name` is used in messages).
Ratings ParseRatings(const std::string& text, const std::string& name);

}  // namespace pwsim::study
