#pragma once
// The residual analysis of the base model over all trials (the evidence the verdict and the
// ranking read): pooled fitness, whiteness, correlation with the GM input and across channels,
// spectra, scale and lag of measured on predicted, the residual located on the terrain
// (against the wheel's distance from each slope change, slow vs fast trials), and per drive
// phase. The statistics themselves are in residual_analysis.h.

#include <vector>

#include "engine/chair.h"
#include "sysid/diagnose/diagnose.h"

namespace pwsim::diagnose {

/// @pre trials and records in the same order, every trial simulated with the base model.
ResidualReport Analyse(const std::vector<TrialAnalysis>& trials, const Chair& chair,
                       const std::vector<effects::TrialRecord>& records);

}  // namespace pwsim::diagnose
