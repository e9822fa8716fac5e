#pragma once
// The study report of shared/spec/study.md: study.json (format pwsim-study/1) and study.md.
// study.json carries the spec's keys for the headline pair, plus (additions allowed by the
// spec) "pairs": every pair of conditions with the same fields, "left_out", "n_zero", "ties",
// "p_uncorrected" and "z". Numbers are written round-trip exact (FormatDouble); a missing value
// (Shapiro-Wilk of constant ratings, an exact p too large to enumerate) is null.

#include <string>

#include "study/analysis.h"

namespace pwsim::study {

std::string StudyJson(const StudyAnalysis& analysis);
/// `boxplot` is the figure's file name relative to study.md ("" for none).
std::string StudyMarkdown(const StudyAnalysis& analysis, const std::string& ratings_file,
                          const std::string& boxplot);

}  // namespace pwsim::study
