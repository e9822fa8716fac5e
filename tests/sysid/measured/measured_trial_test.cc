#include "sysid/measured/measured_trial.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/chair_simulator.h"
#include "engine/input_error.h"
#include "tests/sysid/measured/test_files.h"

namespace pwsim {
namespace {

using testing::ScratchDir;
using testing::WriteText;

const char* kChair =
    "format: pwsim-chair/1\nname: pw6\nmass_kg: 53\ninertia_kgm2: 9.9\ncm_height_m: 0.43\n"
    "wheels:\n"
    "  - {name: front_caster, x_m: 0.38, radius_m: 0.10}\n"
    "  - {name: drive,        x_m: 0.00, radius_m: 0.17}\n"
    "  - {name: rear_caster,  x_m: -0.38, radius_m: 0.10}\n";
const char* kTerrain =
    "format: pwsim-terrain/1\n"
    "profile_m: [[0.0, 0.0], [1.80, 0.0], [2.10, 0.065], [3.60, 0.065], [3.90, 0.0], [12.0, 0.0]]\n";
const char* kTrial =
    "format: pwsim-trial/1\n"
    "chair: ../shared/chair.yaml\n"
    "terrain: ../shared/terrain.yaml\n"
    "load_kg: 100\n"
    "profile:\n"
    "  speed_mps: 1.2\n"
    "  accel_mps2: 0.5\n"
    "mocap:\n"
    "  file: mocap.csv\n"
    "  format: csv\n";

std::filesystem::path MakeTrial(const std::string& trial_yaml = kTrial) {
  const auto root = ScratchDir();
  WriteText(root / "shared" / "chair.yaml", kChair);
  WriteText(root / "shared" / "terrain.yaml", kTerrain);
  WriteText(root / "t1" / "mocap.csv", "t_s,x_m,z_m,pitch_rad\n0,0,0.3,0\n0.01,0.012,0.3,0\n");
  WriteText(root / "t1" / "trial.yaml", trial_yaml);
  return root / "t1";
}

TEST(ReadMeasuredTrialTest, ReadsFolderWithSharedChairAndTerrain) {
  const MeasuredTrial trial = ReadMeasuredTrial(MakeTrial());
  EXPECT_EQ(trial.name, "t1");
  EXPECT_EQ(trial.chair.wheel_count(), 3);
  EXPECT_FALSE(trial.chair.gm.has_value());
  EXPECT_DOUBLE_EQ(trial.terrain.MaxHeight(), 0.065);
  EXPECT_DOUBLE_EQ(trial.load_kg, 100.0);
  EXPECT_DOUBLE_EQ(*trial.profile.speed, 1.2);
  EXPECT_EQ(trial.mocap_format, "csv");
  EXPECT_EQ(trial.track.size(), 2u);
  EXPECT_DOUBLE_EQ(trial.NominalSpeed(), 1.2);
  // The trial.yaml path itself works too.
  EXPECT_EQ(ReadMeasuredTrial(MakeTrial() / "trial.yaml").name, "t1");
}

TEST(MalformedTrialTest, MissingTrialFile) {
  const auto folder = ScratchDir() / "empty_trial";
  std::filesystem::create_directories(folder);
  try {
    ReadMeasuredTrial(folder);
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), (folder / "trial.yaml").string());
    EXPECT_NE(std::string(error.what()).find("no such file"), std::string::npos);
  }
}

TEST(MalformedTrialTest, WrongFormatTag) {
  std::string text = kTrial;
  text.replace(text.find("pwsim-trial/1"), 13, "pwsim-trial/2");
  const auto folder = MakeTrial(text);
  try {
    ReadMeasuredTrial(folder);
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.line(), 1);
    EXPECT_EQ(error.field(), "format");
    EXPECT_EQ(error.expected(), "\"pwsim-trial/1\"");
  }
}

TEST(MalformedTrialTest, BadLoadNumber) {
  std::string text = kTrial;
  text.replace(text.find("load_kg: 100"), 12, "load_kg: 1OO");
  try {
    ReadMeasuredTrial(MakeTrial(text));
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.line(), 4);
    EXPECT_EQ(error.field(), "load_kg");
  }
}

TEST(MalformedTrialTest, UnknownMocapFormatAndMissingBody) {
  std::string text = kTrial;
  text.replace(text.find("format: csv"), 11, "format: c3d");
  EXPECT_THROW(ReadMeasuredTrial(MakeTrial(text)), InputError);
  std::string tsv = kTrial;
  tsv.replace(tsv.find("format: csv"), 11, "format: qtm-6d-tsv");  // no body given
  try {
    ReadMeasuredTrial(MakeTrial(tsv));
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), "mocap.body");
  }
}

TEST(MalformedTrialTest, MissingChairFile) {
  std::string text = kTrial;
  text.replace(text.find("../shared/chair.yaml"), 20, "nowhere/chair.yaml");
  try {
    ReadMeasuredTrial(MakeTrial(text));
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_NE(error.file().find("nowhere/chair.yaml"), std::string::npos);
  }
}

// ---- the model driven by measured x(t) ----

/// The chair simulator at 1 kHz on a constant-speed drive (the reference).
struct Reference {
  std::vector<double> t, x, z, pitch;
};
Reference RunSimulator(double speed, double load_kg) {
  const Chair chair = MakeTableOneChair();
  const Terrain terrain = MakeSpeedCushion();
  ChairSimulator sim(chair, terrain, load_kg, 1e-3);
  Reference ref;
  for (long tick = 0; tick <= 5000; ++tick) {
    const double t = static_cast<double>(tick) * 1e-3;
    const Longitudinal drive{0.5 + speed * t, speed, 0.0};
    const ChairSample& s = tick == 0 ? sim.Start(drive) : sim.Advance(drive);
    ref.t.push_back(t);
    ref.x.push_back(drive.x);
    ref.z.push_back(s.lm.z);
    ref.pitch.push_back(s.lm.pitch);
  }
  return ref;
}

TEST(SimulateMeasuredTrialTest, MatchesTheChairSimulatorOnItsGrid) {
  const Reference ref = RunSimulator(1.2, 100.0);
  const ModelOutput out = SimulateMeasuredTrial(MakeTableOneChair(), MakeSpeedCushion(), 100.0,
                                                ref.t, ref.x);
  double worst_z = 0.0;
  double worst_pitch = 0.0;
  for (std::size_t k = 0; k < ref.t.size(); ++k) {
    worst_z = std::max(worst_z, std::abs(out.z[k] - ref.z[k]));
    worst_pitch = std::max(worst_pitch, std::abs(out.pitch[k] - ref.pitch[k]));
  }
  EXPECT_LT(worst_z, 1e-9);
  EXPECT_LT(worst_pitch, 1e-9);
}

TEST(SimulateMeasuredTrialTest, MocapRateAndDroppedFramesBarelyMatter) {
  const Reference ref = RunSimulator(1.2, 50.0);
  // 150 Hz frames with every 7th dropped and a 0.1 s hole.
  std::vector<double> t, x;
  for (int k = 0; k * (1.0 / 150.0) <= 5.0; ++k) {
    const double time = k / 150.0;
    if (k % 7 == 3 || (time > 2.0 && time < 2.1)) continue;
    t.push_back(time);
    x.push_back(0.5 + 1.2 * time);
  }
  const ModelOutput out =
      SimulateMeasuredTrial(MakeTableOneChair(), MakeSpeedCushion(), 50.0, t, x);
  ASSERT_EQ(out.z.size(), t.size());
  for (std::size_t s = 0; s < t.size(); ++s) {
    const auto k = static_cast<std::size_t>(std::lround(t[s] * 1000.0));
    if (std::abs(t[s] * 1000.0 - static_cast<double>(k)) > 1e-6) continue;  // off-grid time
    EXPECT_NEAR(out.z[s], ref.z[k], 2e-4) << t[s];
    EXPECT_NEAR(out.pitch[s], ref.pitch[k], 2e-3) << t[s];
  }
}

TEST(InitialOffsetTest, MeanOverTheFirstWindow) {
  const std::vector<double> t{0.0, 0.1, 0.2, 0.3, 0.4};
  const std::vector<double> measured{1.0, 1.2, 1.1, 5.0, 5.0};
  const std::vector<double> model{0.0, 0.0, 0.0, 0.0, 0.0};
  EXPECT_NEAR(InitialOffset(t, measured, model, 0.25), 1.1, 1e-12);
  EXPECT_NEAR(InitialOffset(t, measured, model, 0.0), 1.0, 1e-12);
}

}  // namespace
}  // namespace pwsim
