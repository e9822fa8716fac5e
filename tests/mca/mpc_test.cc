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
#include "tests/mca/actuator_checks.h"
#include "tests/run_command.h"

namespace pwsim::mca {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

/// Every actuator inside its stroke, speed and acceleration (tests/mca/actuator_checks.h).
void ExpectWithinLimits(const PlatformSpec& platform, const std::vector<McaCommand>& commands, double dt,
                        const std::string& what) {
  test::ExpectActuatorsWithinLimits(platform, commands, dt, what);
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
    ExpectWithinLimits(config.platform, t->commands, dt, t->preview ? "preview" : "held");
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
// NaN and infinity bursts) never takes an actuator of any shipped platform (pw4dof's five,
// car2dof's two, stewart6dof's six) beyond its stroke, speed or acceleration, and counts faults.
TEST(MpcTest, FuzzedInputNeverBeyondALimit) {
  const std::filesystem::path dir = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/platforms";
  for (const char* file : {"pw4dof.yaml", "car2dof.yaml", "stewart6dof.yaml"}) {
    const PlatformSpec platform = ReadPlatformFile(dir / file);
    for (unsigned seed = 1; seed <= 3; ++seed) {
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> force(-3.0 * kGravity, 3.0 * kGravity), rate(-3.0, 3.0);
      std::uniform_int_distribution<int> hold(1, 400), kind(0, 9);
      MpcCueing mpc(MpcParams{}, DefaultWashoutParams(), VestibularParams{}, platform, 1e-3);
      std::vector<McaCommand> commands;
      HeadMotion h;
      int nan_ticks = 0;
      const std::size_t ticks = platform.mechanism.actuator_count() > 5 ? 4000 : 8000;  // Stewart: 6 legs, dearer
      while (commands.size() < ticks) {
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
      ExpectWithinLimits(platform, commands, 1e-3, platform.name + " seed " + std::to_string(seed));
      EXPECT_EQ(mpc.stats().fault_ticks, nan_ticks);
    }
  }
}

// Tests the tilt-rate guarantee of mca/mpc.h on fuzzed input: random steps of specific force
// (±3 g) and of roll and pitch rate (±3 rad/s, far beyond what any platform follows), impulses,
// slow ramps and NaN bursts, on pw4dof and on a pw4dof whose pitch drive sustains only
// 100 deg/s² (its brake acceleration below the 300 deg/s² peak), at 1 kHz and at 100 Hz (one
// tick per control period), with the active set and ALGLIB's DENSE-IPM. Recomputed here from
// the definition: the vehicle's own rate ω (roll w_x, nose-up pitch −w_y; during a fault the
// last finite input for fault.hold_s, then rest), ω_f changing by at most the brake
// acceleration per tick, and the platform's rate r = (p_k − p_k−1)/dt; r never leaves
// [min(0, ω_f) − τ, max(0, ω_f) + τ] beyond floating point, the command's tilt_rate_* say the
// same, every limit holds, and no solve fails (no fallback to the washout).
TEST(MpcTest, FuzzedInputNeverTiltsFasterThanTheThreshold) {
  PlatformSpec weak_pitch = MakePw4DofPlatform();
  weak_pitch.dofs[Index(Dof::kPitch)].steady_accel = 100.0 * kDegToRad;
  const double threshold = VestibularParams{}.thresholds.tilt_rate;
  const double hold_time = DefaultWashoutParams().fault.hold_time;
  for (const PlatformSpec& platform : {MakePw4DofPlatform(), weak_pitch}) {
    for (const double dt : {1e-3, 1e-2}) {
      for (const QpAlgorithm solver : {QpAlgorithm::kActiveSet, QpAlgorithm::kDenseIpm}) {
        if (solver == QpAlgorithm::kDenseIpm && dt == 1e-3 && platform.limits(Dof::kPitch) != weak_pitch.limits(Dof::kPitch))
          continue;  // ALGLIB is slow: one platform at 1 kHz is enough
        for (unsigned seed = 1; seed <= 2; ++seed) {
          const std::string what = platform.name + (platform.limits(Dof::kPitch).steady_accel < 1.0 ? " weak" : "") +
                                   " dt " + std::to_string(dt) + " " + std::string(QpAlgorithmName(solver)) + " seed " +
                                   std::to_string(seed);
          std::mt19937 rng(seed);
          std::uniform_real_distribution<double> force(-3.0 * kGravity, 3.0 * kGravity), rate(-3.0, 3.0), unit(0.0, 1.0);
          std::uniform_int_distribution<int> hold(1, static_cast<int>(0.4 / dt)), kind(0, 9);
          MpcParams params;
          params.solver = solver;
          MpcCueing mpc(params, DefaultWashoutParams(), VestibularParams{}, platform, dt);
          std::vector<McaCommand> commands;
          std::array<double, 2> follow{}, previous{}, held{};
          double fault_time = 0.0;
          const int ticks = static_cast<int>((solver == QpAlgorithm::kDenseIpm ? 3.0 : 8.0) / dt);
          while (static_cast<int>(commands.size()) < ticks) {
            const int k = kind(rng);
            HeadMotion h;
            for (std::size_t a = 0; a < 3; ++a) {
              h.fs[a] = (a == 2 ? kGravity : 0.0) + (k < 7 ? force(rng) : 0.0);
              h.w[a] = k < 7 ? rate(rng) : 0.0;
            }
            if (k == 9) h.w[1] = seed == 2 ? std::numeric_limits<double>::infinity() : kNan;
            const bool ramp = k == 7 || k == 8;  // a slow pitch (roll) rate ramp the platform can follow
            const double slope = (unit(rng) - 0.5) * 2.0;  // [rad/s²]
            const int n = k == 6 ? 1 : hold(rng);          // k == 6: a one-tick impulse
            for (int step = 0; step < n && static_cast<int>(commands.size()) < ticks; ++step) {
              if (ramp) h.w[k == 7 ? 1 : 0] = slope * step * dt;
              const McaCommand& c = mpc.Step(h);
              commands.push_back(c);
              // the vehicle rate the MPC must use: finite input, else held for hold_s, then rest
              std::array<double, 2> vehicle{h.w[0], -h.w[1]};
              if (std::isfinite(h.w[1])) {
                fault_time = 0.0;
                held = vehicle;
              } else {
                fault_time += dt;
                vehicle = fault_time <= hold_time ? held : std::array<double, 2>{};
              }
              for (std::size_t axis = 0; axis < 2; ++axis) {  // roll, pitch
                const Dof dof = axis == 0 ? Dof::kRoll : Dof::kPitch;
                const double brake = platform.limits(dof).brake_accel();
                follow[axis] = std::clamp(vehicle[axis], follow[axis] - brake * dt, follow[axis] + brake * dt);
                const double pose = c.pose[Index(dof)];
                const double r = (pose - previous[axis]) / dt;
                previous[axis] = pose;
                const double beyond = r - std::clamp(r, std::min(0.0, follow[axis]), std::max(0.0, follow[axis]));
                ASSERT_LE(std::abs(beyond), threshold * (1.0 + 1e-9) + 1e-9)
                    << what << " " << DofName(dof) << " tick " << commands.size();
                ASSERT_NEAR(axis == 0 ? c.tilt_rate_roll : c.tilt_rate_pitch, beyond, 1e-9) << what << " tick " << commands.size();
              }
            }
          }
          ExpectWithinLimits(platform, commands, dt, what);
          // recursive feasibility in practice: no solve failed, even on this input
          EXPECT_EQ(mpc.stats().fallbacks, 0) << what;
        }
      }
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
// within the tilt band (the vehicle does not pitch: at most the 3 deg/s threshold), and the
// vehicle at rest gives exactly zero commands.
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
  EXPECT_LE(max_rate, 3.0 * kDegToRad * (1.0 + 1e-9));
  EXPECT_GT(max_rate, 2.9 * kDegToRad);  // the band binds: tilt as fast as is imperceptible
  EXPECT_NEAR(c.tilt_pitch, pitch, 1e-12);  // the vehicle does not pitch: all of it is tilt
}

McaConfig LoadText(const std::string& mca_yaml) {
  const pwsim::testing::TempDir dir("mpc_test_scene");  // its own, removed after the load
  const std::filesystem::path file = dir / "pwsim_mpc_test_scene.yaml";
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
  ExpectWithinLimits(config.platform, best.commands, dt, "offline");
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
