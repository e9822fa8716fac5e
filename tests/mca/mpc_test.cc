// The model-predictive cueing (mca/mpc.h): limits on every shipped chair scene and on fuzzed
// input, determinism, what the preview buys, the fault path, and load-time errors.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "engine/input_error.h"
#include "engine/scene.h"
#include "mca/config.h"
#include "mca/cueing.h"
#include "mca/mpc.h"
#include "mca/offline_optimum.h"

namespace pwsim::mca {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

/// Every command of the stream inside the platform's travel, speed and acceleration.
void ExpectWithinLimits(const PlatformSpec& platform, const std::vector<McaCommand>& commands,
                        const std::string& what) {
  for (Dof dof : kAllDofs) {
    const auto i = static_cast<std::size_t>(Index(dof));
    const DofLimits& lim = platform.limits(dof);
    double pose = 0.0, rate = 0.0, accel = 0.0;
    for (const McaCommand& c : commands) {
      ASSERT_TRUE(std::isfinite(c.pose[i]) && std::isfinite(c.rate[i]) && std::isfinite(c.accel[i])) << what;
      pose = std::max(pose, std::abs(c.pose[i]));
      rate = std::max(rate, std::abs(c.rate[i]));
      accel = std::max(accel, std::abs(c.accel[i]));
    }
    if (!lim.present) {
      EXPECT_EQ(pose, 0.0) << what << " " << DofName(dof);
      continue;
    }
    if (std::isfinite(lim.travel)) {
      EXPECT_LE(pose, lim.travel * (1.0 + 1e-12)) << what << " " << DofName(dof);
    }
    EXPECT_LE(rate, lim.speed * (1.0 + 1e-9)) << what << " " << DofName(dof);
    EXPECT_LE(accel, lim.accel * (1.0 + 1e-6)) << what << " " << DofName(dof);
  }
}

struct Trial {
  std::vector<HeadMotion> head;
  McaConfig config;  ///< the scene's
  double dt;
};

/// The shipped speed-cushion scene, simulated: head motion and MCA configuration.
Trial SpeedCushion() {
  const Scene scene = LoadScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/speed_cushion.yaml");
  Trial trial{{}, LoadMcaConfig(scene), scene.clock.dt()};
  for (const ChairSample& s : SimulateScene(scene)) {
    trial.head.push_back(HeadMotionFromChair(s, scene.occupant.head_offset));
  }
  return trial;
}

// Tests that the MPC, held input and preview alike, keeps the speed cushion's command stream
// inside every pw4dof limit, without a fallback, and that the preview lowers the perceived
// surge and heave error below the washout's (the reason to preview; figures in docs/mca.md).
TEST(MpcTest, SpeedCushionInsideLimitsAndPreviewBeatsWashout) {
  auto [head, config, dt] = SpeedCushion();
  const CueingTrace washout = RunCueing(config, head, dt);
  config.algorithm = McaAlgorithm::kMpc;
  const CueingTrace held = RunCueing(config, head, dt);
  config.mpc.preview = true;
  const CueingTrace preview = RunCueing(config, head, dt);
  EXPECT_FALSE(held.preview);
  EXPECT_TRUE(preview.preview);
  for (const CueingTrace* t : {&held, &preview}) {
    ExpectWithinLimits(config.platform, t->commands, t->preview ? "preview" : "held");
    EXPECT_EQ(t->mpc.fallbacks, 0);
    EXPECT_GT(t->mpc.solves, static_cast<std::int64_t>(head.size() / 10) - 1);
  }
  const ConsistencyReport w = EvaluateConsistency(config, washout, dt);
  const ConsistencyReport p = EvaluateConsistency(config, preview, dt);
  EXPECT_LT(p.otolith[0].rms_error, 0.5 * w.otolith[0].rms_error);
  EXPECT_LT(p.otolith[2].rms_error, w.otolith[2].rms_error);
  EXPECT_LT(p.canals[1].rms_error, 1.2 * w.canals[1].rms_error);
}

// Tests that fuzzed input (random steps up to ±3 g and ±3 rad/s on every axis, impulses,
// NaN and infinity bursts) never moves either platform beyond a limit, and counts faults.
TEST(MpcTest, FuzzedInputNeverBeyondALimit) {
  for (const PlatformSpec& platform : {MakePw4DofPlatform(), MakeCar2DofPlatform()}) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> force(-3.0 * kGravity, 3.0 * kGravity), rate(-3.0, 3.0);
      std::uniform_int_distribution<int> hold(1, 400), kind(0, 9);
      MpcCueing mpc(MpcParams{}, DefaultWashoutParams(), VestibularParams{}, platform, 1e-3);
      std::vector<McaCommand> commands;
      HeadMotion h;
      int nan_ticks = 0;
      while (commands.size() < 8000) {
        const int k = kind(rng);
        for (std::size_t a = 0; a < 3; ++a) {
          h.fs[a] = (a == 2 ? kGravity : 0.0) + (k < 8 ? force(rng) : 0.0);
          h.w[a] = k < 8 ? rate(rng) : 0.0;
        }
        if (k == 9) h.fs[1] = seed == 2 ? std::numeric_limits<double>::infinity() : kNan;
        const int n = hold(rng);
        for (int t = 0; t < n; ++t) {
          commands.push_back(mpc.Step(h));
          if (k == 9) ++nan_ticks;
        }
      }
      ExpectWithinLimits(platform, commands, platform.name + " seed " + std::to_string(seed));
      EXPECT_EQ(mpc.stats().fault_ticks, nan_ticks);
    }
  }
}

// Tests that the same input gives the same command bits (two controllers, and after Reset).
TEST(MpcTest, Deterministic) {
  MpcCueing a(MpcParams{}, DefaultWashoutParams(), VestibularParams{}, MakePw4DofPlatform(), 1e-3);
  MpcCueing b(MpcParams{}, DefaultWashoutParams(), VestibularParams{}, MakePw4DofPlatform(), 1e-3);
  std::vector<McaCommand> first;
  HeadMotion h;
  for (int k = 0; k < 3000; ++k) {
    h.fs[0] = std::sin(k * 3e-3);
    h.w[1] = 0.2 * std::cos(k * 7e-3);
    first.push_back(a.Step(h));
    EXPECT_EQ(first.back(), b.Step(h)) << k;
  }
  a.Reset();
  for (int k = 0; k < 3000; ++k) {
    h.fs[0] = std::sin(k * 3e-3);
    h.w[1] = 0.2 * std::cos(k * 7e-3);
    ASSERT_EQ(a.Step(h), first[static_cast<std::size_t>(k)]) << k;
  }
}

// Tests tilt coordination out of the optimisation: a sustained surge specific force of 1 m/s²
// on pw4dof (no surge axis) is rendered by pitching nose-up towards asin(1/g) at a pitch rate
// within the tilt band (threshold 3 deg/s plus the small slack the soft constraint allows), and
// the vehicle at rest gives exactly zero commands.
TEST(MpcTest, TiltCoordinationComesOutOfTheOptimisation) {
  MpcCueing mpc(MpcParams{}, DefaultWashoutParams(), VestibularParams{}, MakePw4DofPlatform(), 1e-3);
  HeadMotion rest;
  for (int k = 0; k < 500; ++k) {
    const McaCommand& c = mpc.Step(rest);
    for (double p : c.pose) ASSERT_EQ(p, 0.0);
  }
  HeadMotion push;
  push.fs[0] = 1.0;
  double max_rate = 0.0;
  McaCommand c;
  for (int k = 0; k < 8000; ++k) {
    c = mpc.Step(push);
    max_rate = std::max(max_rate, std::abs(c.rate[Index(Dof::kPitch)]));
  }
  const double pitch = c.pose[Index(Dof::kPitch)];
  EXPECT_GT(pitch, 0.5 * std::asin(1.0 / kGravity));
  EXPECT_LT(pitch, 1.5 * std::asin(1.0 / kGravity));
  EXPECT_LT(max_rate, 4.0 * kDegToRad);
  EXPECT_NEAR(c.tilt_pitch, pitch, 1e-12);  // the vehicle does not pitch: all of it is tilt
}

McaConfig LoadText(const std::string& mca_yaml) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "pwsim_mpc_test_scene.yaml";
  {
    std::ofstream out(file);
    out << "platform: " << PWSIM_SOURCE_DIR << "/scenes/platforms/pw4dof.yaml\nmca:\n" << mca_yaml;
  }
  const YamlDocument document = LoadYamlFile(file);
  SceneSection platform{document.root["platform"], file, 1};
  SceneSection mca{document.root["mca"], file, 2};
  return LoadMcaConfig(&platform, &mca, McaConfig{});
}

std::string LoadError(const std::string& mca_yaml) {
  try {
    LoadText(mca_yaml);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Tests that `algorithm: mpc` and the mpc: keys load, and that negative or non-finite weights,
// a horizon the solver cannot meet in real time, a horizon under 1 s and an unknown solver
// fail at load time naming the file, the field and what was expected.
TEST(MpcTest, LoadTimeErrors) {
  const McaConfig ok = LoadText("  algorithm: mpc\n  mpc: {horizon_s: 1.5, preview: true, weights: {otolith_x: 2}}\n");
  EXPECT_EQ(ok.algorithm, McaAlgorithm::kMpc);
  EXPECT_TRUE(ok.mpc.preview);
  EXPECT_EQ(ok.mpc.weight_otolith[0], 2.0);
  EXPECT_EQ(ok.mpc.BlockCount(), 1 + 15);
  const std::string negative = LoadError("  algorithm: mpc\n  mpc: {weights: {canal_y: -1}}\n");
  EXPECT_NE(negative.find("pwsim_mpc_test_scene.yaml"), std::string::npos) << negative;
  EXPECT_NE(negative.find("canal_y"), std::string::npos) << negative;
  const std::string nan = LoadError("  mpc: {weights: {neutral: .nan}}\n");
  EXPECT_NE(nan.find("neutral"), std::string::npos) << nan;
  EXPECT_NE(nan.find("expected a number in [0"), std::string::npos) << nan;
  const std::string long_horizon = LoadError("  mpc: {horizon_s: 5, block_s: 0.1}\n");
  EXPECT_NE(long_horizon.find("real time"), std::string::npos) << long_horizon;
  EXPECT_NE(long_horizon.find("horizon_s"), std::string::npos) << long_horizon;
  EXPECT_NE(LoadError("  mpc: {horizon_s: 0.5}\n").find("horizon_s"), std::string::npos);
  EXPECT_NE(LoadError("  mpc: {solver: osqp}\n").find("active_set"), std::string::npos);
  EXPECT_NE(LoadError("  algorithm: model_predictive\n").find("algorithm"), std::string::npos);
}

}  // namespace
}  // namespace pwsim::mca

namespace pwsim::mca {
namespace {

// Tests the offline ceiling on the speed cushion: inside every limit, and its perceived surge
// and pitch-rate errors no worse than the online MPC's with the same preview (the online MPC
// sees 1 s ahead, the ceiling the whole trial).
TEST(OfflineOptimumTest, SpeedCushionCeilingInsideLimitsAndNoWorseThanOnline) {
  auto [head, config, dt] = SpeedCushion();
  const CueingTrace best = RunOfflineOptimum(config, head, dt);
  ExpectWithinLimits(config.platform, best.commands, "offline");
  EXPECT_EQ(best.mpc.solves, 1);
  EXPECT_EQ(best.mpc.fallbacks, 0);
  config.algorithm = McaAlgorithm::kMpc;
  config.mpc.preview = true;
  const CueingTrace online = RunCueing(config, head, dt);
  const ConsistencyReport b = EvaluateConsistency(config, best, dt);
  const ConsistencyReport o = EvaluateConsistency(config, online, dt);
  EXPECT_LT(b.otolith[0].rms_error, 1.1 * o.otolith[0].rms_error);
  EXPECT_LT(b.canals[1].rms_error, 1.1 * o.canals[1].rms_error);
}

}  // namespace
}  // namespace pwsim::mca
