// The MPC's vehicle prediction without preview (mca/vehicle_prediction.h): where the driver's
// input does not change over the horizon, the vehicle model run ahead with it held is the trial
// itself — the trial's simulated head motion averaged over the same blocks is the truth here
// (SimulateScene, SimulateCarScene: the engine's own runs, not the predictor).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "engine/scene.h"
#include "engine/vehicle/car_scene.h"
#include "mca/head_motion.h"
#include "mca/vehicle_prediction.h"

namespace pwsim::mca {
namespace {

/// The MPC's blocks at 1 kHz: one control period of 10 ticks, then ten of 100.
std::vector<int> Blocks() {
  std::vector<int> blocks{10};
  for (int k = 0; k < 10; ++k) blocks.push_back(100);
  return blocks;
}

/// The mean channels (fs_x, fs_y, fs_z − g, w) of `head` over the blocks from `tick`.
Eigen::MatrixXd TrialMeans(const std::vector<HeadMotion>& head, std::int64_t tick, const std::vector<int>& blocks) {
  Eigen::MatrixXd means = Eigen::MatrixXd::Zero(6, static_cast<Eigen::Index>(blocks.size()));
  std::int64_t t = tick;
  for (std::size_t kb = 0; kb < blocks.size(); ++kb) {
    for (int k = 0; k < blocks[kb]; ++k, ++t) {
      const HeadMotion& h = head[static_cast<std::size_t>(t)];
      means.col(static_cast<Eigen::Index>(kb)) +=
          Eigen::Matrix<double, 6, 1>(h.fs[0], h.fs[1], h.fs[2] - kGravity, h.w[0], h.w[1], h.w[2]);
    }
    means.col(static_cast<Eigen::Index>(kb)) /= blocks[kb];
  }
  return means;
}

// Tests the chair: while the power module cruises (its speed command held is the trial's own)
// the chair model run ahead over the cushion is the trial's future, to rounding; while it still
// accelerates the held command (the cruise speed) is the trial's too; and a new run of the trial
// (a tick back in time) starts the lockstep simulator again.
TEST(VehiclePredictionTest, ChairRunAheadIsTheTrialWhileTheCommandHolds) {
  const Scene scene = LoadScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/speed_cushion.yaml");
  std::vector<HeadMotion> head;
  for (const ChairSample& s : SimulateScene(scene)) head.push_back(HeadMotionFromChair(s, scene.occupant.head_offset));
  ChairRolloutPredictor predictor(scene);
  const std::vector<int> blocks = Blocks();
  Eigen::MatrixXd predicted(6, static_cast<Eigen::Index>(blocks.size()));
  const double cruise_end = scene.drive.DecelStartTime();
  int checked = 0;
  for (const double t : {0.8, 2.0, 2.5, 3.0, 0.6}) {  // accelerating, then cruising over the cushion; then back
    const auto tick = static_cast<std::int64_t>(std::llround(t / scene.clock.dt()));
    ASSERT_LT(t + 1.1, cruise_end);
    predictor.Predict(tick, blocks, predicted);
    const Eigen::MatrixXd truth = TrialMeans(head, tick, blocks);
    EXPECT_LT((predicted - truth).cwiseAbs().maxCoeff(), 1e-9 * (1.0 + truth.cwiseAbs().maxCoeff())) << t;
    ++checked;
  }
  EXPECT_EQ(checked, 5);
  EXPECT_EQ(HeldDriveAt(scene.drive, 0.1).speed, 0.0);  // still: no command yet
  EXPECT_EQ(HeldDriveAt(scene.drive, 2.0).speed, scene.drive.speed);
  EXPECT_EQ(HeldDriveAt(scene.drive, cruise_end + 0.1).speed, 0.0);  // braking: the stop held
}

// Tests the car: between 3.5 and 5.5 s of car_launch every control (throttle 0.5, first gear,
// clutch in, no brake, no steer: its return to centre changes nothing) holds, so the car model run ahead from 4.0 s is the trial's own
// future; stepped at 5 ms against the trial's 1 ms, its block means agree within 0.5 % of the
// surge specific force's and 0.01 m/s², rad/s elsewhere. At 6 s (a gear change under way) the
// held controls are not the driver's next ones, and the prediction departs from the trial.
TEST(VehiclePredictionTest, CarRunAheadIsTheTrialWhileTheControlsHold) {
  const vehicle::CarScene scene = vehicle::LoadCarScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/car_launch.yaml");
  const std::vector<vehicle::CarSample> samples = vehicle::SimulateCarScene(scene);
  std::vector<HeadMotion> head;
  for (const vehicle::CarSample& s : samples) {
    const vehicle::CarHeadMotion m = vehicle::HeadMotionOfCar(s, scene.head_offset);
    HeadMotion h;
    h.fs = m.fs;
    h.w = m.w;
    head.push_back(h);
  }
  const double dt = scene.clock.dt();
  CarRolloutPredictor predictor(scene.car, samples, scene.head_offset, dt);
  const std::vector<int> blocks = Blocks();
  Eigen::MatrixXd predicted(6, static_cast<Eigen::Index>(blocks.size()));
  const auto steady = static_cast<std::int64_t>(std::llround(4.0 / dt));
  predictor.Predict(steady, blocks, predicted);
  Eigen::MatrixXd truth = TrialMeans(head, steady, blocks);
  EXPECT_GT(truth.row(0).cwiseAbs().minCoeff(), 0.5);  // [m/s²] accelerating all along
  EXPECT_LT((predicted.row(0) - truth.row(0)).cwiseAbs().maxCoeff(), 0.005 * truth.row(0).cwiseAbs().maxCoeff());
  EXPECT_LT((predicted.bottomRows(5) - truth.bottomRows(5)).cwiseAbs().maxCoeff(), 0.01);
  const auto shifting = static_cast<std::int64_t>(std::llround(5.5 / dt));
  predictor.Predict(shifting, blocks, predicted);
  truth = TrialMeans(head, shifting, blocks);
  EXPECT_GT((predicted.row(0) - truth.row(0)).cwiseAbs().maxCoeff(), 0.3);  // [m/s²]: the driver changed gear
}

}  // namespace
}  // namespace pwsim::mca
