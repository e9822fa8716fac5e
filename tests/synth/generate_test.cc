#include "synth/generate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sysid/identify/identify.h"
#include "sysid/measured/measured_trial.h"
#include "tests/sysid/measured/test_files.h"

namespace pwsim {
namespace {

GenerateConfig Tiny() {
  GenerateConfig config;
  config.speeds = {0.6, 2.4};
  config.loads = {100.0};
  config.repeats = 1;
  config.seed = 42;
  return config;
}

TEST(GenerateTrialSetTest, ProtocolGridAndNames) {
  GenerateConfig config;  // the default protocol: 4 speeds × 3 loads × with/without × 1
  const TrialSet set = GenerateTrialSet(config);
  EXPECT_EQ(set.trials.size(), 24u);
  EXPECT_EQ(set.truth_model_id, "base");
  EXPECT_EQ(set.trials.front().measured.name, "v0.60_m0_cushion_r1");
  EXPECT_EQ(set.trials[1].measured.name, "v0.60_m0_flat_r1");
  for (const SyntheticTrial& trial : set.trials) {
    EXPECT_FALSE(trial.measured.chair.gm.has_value()) << "the lab does not know gm";
    EXPECT_EQ(trial.measured.terrain.MaxHeight() > 0.0, trial.cushion);
    // Cruise speed is reached before the front wheel meets the cushion (paper protocol).
    const MocapTrack& track = trial.measured.track;
    for (std::size_t k = 1; k < track.size(); ++k) {
      if (track.x[k] + 0.38 > 1.8 && track.x[k] - 0.38 < 3.9) {
        const double v = (track.x[k] - track.x[k - 1]) / (track.t[k] - track.t[k - 1]);
        EXPECT_NEAR(v, trial.speed, 0.05 * trial.speed + 0.1);  // noise over one frame
        break;
      }
    }
  }
}

TEST(GenerateTrialSetTest, DeterministicForASeed) {
  const TrialSet a = GenerateTrialSet(Tiny());
  const TrialSet b = GenerateTrialSet(Tiny());
  GenerateConfig other = Tiny();
  other.seed = 43;
  const TrialSet c = GenerateTrialSet(other);
  ASSERT_EQ(a.trials.size(), b.trials.size());
  EXPECT_EQ(a.trials[0].measured.track.z, b.trials[0].measured.track.z);
  EXPECT_NE(a.trials[0].measured.track.z, c.trials[0].measured.track.z);
}

TEST(GenerateTrialSetTest, RandomRateAndDroppedFrames) {
  GenerateConfig config = Tiny();
  config.rate_hz = 100.0;
  config.rate_max_hz = 250.0;
  config.drop_fraction = 0.05;
  const TrialSet set = GenerateTrialSet(config);
  for (const SyntheticTrial& trial : set.trials) {
    EXPECT_GE(trial.rate_hz, 100.0);
    EXPECT_LE(trial.rate_hz, 250.0);
    EXPECT_GT(trial.measured.track.untracked_frames, 0);
    EXPECT_EQ(trial.measured.track.size() + trial.measured.track.untracked_frames,
              trial.frames.size());
  }
}

TEST(GenerateTrialSetTest, TruthModelHookDecidesTheMotion) {
  GenerateConfig config = Tiny();
  config.noise_position = 0.0;
  config.noise_pitch = 0.0;
  config.truth_model = std::make_shared<FunctionTruthModel>(
      "constant", [](const TruthModelInput& input) {
        return TruthModelOutput{std::vector<double>(input.t.size(), 0.01),
                                std::vector<double>(input.t.size(), -0.02)};
      });
  const TrialSet set = GenerateTrialSet(config);
  EXPECT_EQ(set.truth_model_id, "constant");
  for (double z : set.trials[0].measured.track.z) EXPECT_DOUBLE_EQ(z, 0.01);
  for (double p : set.trials[0].measured.track.pitch) EXPECT_DOUBLE_EQ(p, -0.02);
}

TEST(GenerateTrialSetTest, NominalSpeedFromTheTrackWhenNoProfileIsGiven) {
  const TrialSet set = GenerateTrialSet(Tiny());
  for (const SyntheticTrial& trial : set.trials) {
    MeasuredTrial measured = trial.measured;
    measured.profile.speed.reset();
    EXPECT_NEAR(measured.NominalSpeed(), trial.speed, 0.05 * trial.speed) << measured.name;
  }
}

TEST(GenerateTrialSetTest, RejectsAnInconsistentConfig) {
  GenerateConfig config = Tiny();
  config.truth.lm.reset();
  EXPECT_THROW(GenerateTrialSet(config), std::invalid_argument);
  config = Tiny();
  config.speeds.clear();
  EXPECT_THROW(GenerateTrialSet(config), std::invalid_argument);
}

TEST(WriteTrialSetTest, FoldersReadBackInBothFormats) {
  GenerateConfig config = Tiny();
  config.mocap_format = MocapFormat::kBoth;
  config.drop_fraction = 0.02;
  const TrialSet set = GenerateTrialSet(config);
  const auto dir = testing::ScratchDir();
  WriteTrialSet(set, dir);
  for (const SyntheticTrial& trial : set.trials) {
    const auto folder = dir / trial.measured.name;
    ASSERT_TRUE(std::filesystem::exists(folder / "mocap.csv"));
    // Trial folders hold only what a lab measures; the truth lies beside the set.
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      EXPECT_EQ(entry.path().filename().string().find("truth"), std::string::npos) << entry.path();
    const MeasuredTrial read = ReadMeasuredTrial(folder);
    EXPECT_EQ(read.mocap_format, "qtm-6d-tsv");
    EXPECT_EQ(read.name, trial.measured.name);
    EXPECT_EQ(read.track.untracked_frames, trial.measured.track.untracked_frames);
    ASSERT_EQ(read.track.size(), trial.measured.track.size());
    const MocapTrack csv = ReadMocapCsv(folder / "mocap.csv");
    ASSERT_EQ(csv.size(), read.track.size());
    for (std::size_t k = 0; k < csv.size(); k += 37) {
      EXPECT_NEAR(read.track.z[k], trial.measured.track.z[k], 1e-6);
      EXPECT_NEAR(csv.z[k], trial.measured.track.z[k], 6e-6);
      EXPECT_NEAR(read.track.pitch[k], csv.pitch[k], 1e-6);
    }
  }
  const Chair truth = ReadChairFile(TruthFileBeside(dir, "truth-chair.yaml"));
  EXPECT_DOUBLE_EQ(truth.lm->k_z, set.truth.lm->k_z);
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_TRUE(entry.is_directory()) << entry.path();
}

TEST(DemoTrialsTest, ShippedSetIsIdentifiedAndReproducesHeldOutTrials) {
  const std::filesystem::path root = std::filesystem::path(PWSIM_SOURCE_DIR) / "assets/trials-demo";
  std::vector<MeasuredTrial> trials;
  for (const auto& entry : std::filesystem::directory_iterator(root)) {
    trials.push_back(ReadMeasuredTrial(entry.path()));
  }
  std::sort(trials.begin(), trials.end(),
            [](const MeasuredTrial& a, const MeasuredTrial& b) { return a.name < b.name; });
  ASSERT_GE(trials.size(), 6u);
  const IdentifyResult result = IdentifyChair(trials, AssignRoles(trials));
  const Chair truth = ReadChairFile(TruthFileBeside(root, "truth-chair.yaml"));
  EXPECT_NEAR(result.chair.lm->k_z / truth.lm->k_z, 1.0, 0.02);
  EXPECT_NEAR(result.chair.lm->k_theta / truth.lm->k_theta, 1.0, 0.02);
  EXPECT_NEAR(result.chair.lm->c_z / truth.lm->c_z, 1.0, 0.05);
  EXPECT_NEAR(result.chair.lm->c_theta / truth.lm->c_theta, 1.0, 0.05);
  EXPECT_GT(result.validation_fit_z, 95.0);
  EXPECT_GT(result.validation_fit_pitch, 95.0);
}

}  // namespace
}  // namespace pwsim
