#pragma once
// The training metrics of a circuit run (engine/training_metrics.h) as the reports carry them:
// "training" in summary.json of `pwsim run` and report.json of `pwsim drive`, and a markdown
// page (training.md) a therapist reads.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/scene.h"
#include "engine/training_metrics.h"

namespace pwsim::report {

/// The metrics' trace of a simulated circuit run (the head at scene.occupant.head_offset).
std::vector<TrainingTick> TrainingTrace(const Scene& scene, const std::vector<FullChairSample>& samples);

/// {"format": "pwsim-training-metrics/1", ...} with units in every key.
nlohmann::ordered_json TrainingJson(const TrainingMetrics& m);

/// The markdown page: what was driven (`title`) and every metric with its definition.
std::string TrainingMarkdown(const TrainingMetrics& m, const std::string& title);

/// Writes DIR/training.md.
void WriteTrainingPage(const TrainingMetrics& m, const std::string& title, const std::filesystem::path& out_dir);

}  // namespace pwsim::report
