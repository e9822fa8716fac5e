// The live loop against the offline run: the same controls give the same car and the same
// platform commands, tick for tick (both use the per-tick functions).
#include "hardware/car_live.h"

#include <gtest/gtest.h>

#include "mca/rail_yaw.h"

namespace pwsim::hw {
namespace {

void ExpectLiveMatchesOffline(mca::McaAlgorithm algorithm) {
  const vehicle::CarScene scene =
      vehicle::LoadCarScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/car_lane_change.yaml");
  const std::vector<vehicle::CarSample> offline = vehicle::SimulateCarScene(scene);
  mca::McaConfig config = mca::LoadCarMcaConfig(scene);
  config.algorithm = algorithm;
  std::vector<mca::HeadMotion> truth(offline.size());
  for (std::size_t k = 0; k < offline.size(); ++k) {
    const vehicle::CarHeadMotion m = vehicle::HeadMotionOfCar(offline[k], scene.head_offset);
    truth[k].fs = m.fs;
    truth[k].w = m.w;
  }
  const mca::CueingTrace trace = mca::RunRailYawCueing(config, truth, scene.clock.dt());
  const mca::RailYawFalseCues cues = mca::RailYawFalseCue(config.vestibular, trace.commands, scene.clock.dt());

  CarLiveLoop loop(scene, config);
  EXPECT_EQ(loop.last().command, trace.commands[0]);
  for (std::size_t k = 1; k < offline.size(); ++k) {
    const CarLiveTick& t = loop.Step(offline[k].input);  // the controls a wheel would have given
    ASSERT_EQ(t.sample.state, offline[k].state) << "tick " << k;
    ASSERT_EQ(t.command, trace.commands[k]) << "tick " << k;
    ASSERT_EQ(t.false_cue_sway, cues.sway[k]) << "tick " << k;
  }
}

TEST(CarLiveLoop, MatchesTheOfflineRunExactly) { ExpectLiveMatchesOffline(mca::McaAlgorithm::kWashout); }

// Tests the live loop with the MPC (held input, as live): the same commands as `pwsim run --mca mpc`.
TEST(CarLiveLoop, MatchesTheOfflineRunExactlyWithTheMpc) { ExpectLiveMatchesOffline(mca::McaAlgorithm::kMpc); }

}  // namespace
}  // namespace pwsim::hw
