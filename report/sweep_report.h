#pragma once
// The figures of `pwsim sweep collect`: DIR/plots/<variable>.{png,svg,plot.csv,gp}, one figure
// per numeric swept variable, a panel per numeric gathered field, a curve per combination of the
// other variables (at most a dozen), points in the order of the variable.

#include <filesystem>
#include <vector>

#include "sweep/collect.h"
#include "sweep/plan.h"

namespace pwsim::report {

/// Returns the PNG files written (none, with a note on stdout, when gnuplot is missing).
std::vector<std::filesystem::path> WriteSweepPlots(const sweep::Manifest& manifest,
                                                   const sweep::Collection& collection);

}  // namespace pwsim::report
