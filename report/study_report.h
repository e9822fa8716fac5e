#pragma once
// The report of `pwsim study` (study.md of the spec): study.json, study.md and the box plot of
// the ratings per condition like seed 000's Fig. 8b (boxplot.png, .svg, .plot.csv, .gp).

#include <filesystem>

#include "study/analysis.h"
#include "study/ratings.h"

namespace pwsim::report {

/// Removes a previous report from `out` (before the inputs are read).
void RemoveStudyReport(const std::filesystem::path& out);

/// Writes the box plot, study.md and study.json (last) under `out`.
void WriteStudyReport(const std::filesystem::path& out, const std::filesystem::path& ratings_file,
                      const study::Ratings& ratings, const study::StudyAnalysis& analysis);

}  // namespace pwsim::report
