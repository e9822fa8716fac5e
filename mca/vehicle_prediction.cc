#include "mca/vehicle_prediction.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"
#include "mca/head_motion.h"

namespace pwsim::mca {

HeldDrive HeldDriveAt(const DriveProfile& profile, double t) {
  switch (PhaseAt(profile, t)) {
    case DrivePhase::kStill: return {0.0, profile.decel};
    case DrivePhase::kAccelerate:
    case DrivePhase::kCruise: return {profile.speed, profile.accel};
    case DrivePhase::kDecelerate:
    case DrivePhase::kStopped: return {0.0, profile.decel};
  }
  return {0.0, profile.decel};
}

Longitudinal HeldLongitudinal(const Longitudinal& from, const HeldDrive& held, double tau) {
  const double gap = held.speed - from.v;
  const double reach = std::abs(gap) / held.rate;  // [s] until the command is reached
  const double sign = gap > 0.0 ? 1.0 : -1.0;
  Longitudinal out;
  if (tau < reach) {
    out.v = from.v + sign * held.rate * tau;
    out.x = from.x + from.v * tau + 0.5 * sign * held.rate * tau * tau;
    out.a = sign * held.rate;
  } else {
    out.v = held.speed;
    out.x = from.x + from.v * reach + 0.5 * sign * held.rate * reach * reach + held.speed * (tau - reach);
    out.a = 0.0;
  }
  return out;
}

ChairRolloutPredictor::ChairRolloutPredictor(const Scene& scene)
    : scene_(scene), lockstep_(scene.chair, scene.terrain, scene.load_kg, scene.clock.dt(), scene.pitch_torque) {
  PWSIM_DEMAND(!scene.is_circuit());
}

void ChairRolloutPredictor::Predict(std::int64_t tick, const std::vector<int>& block_ticks, Eigen::MatrixXd& means) {
  // the trial's own simulator, to the present tick (SimulateScene's inputs); a new run of the
  // trial (a tick back in time) starts it again
  if (lockstep_tick_ < 0 || tick < lockstep_tick_) {
    lockstep_.Start(EvaluateDrive(scene_.drive, 0.0));
    lockstep_tick_ = 0;
  }
  while (lockstep_tick_ < tick) {
    ++lockstep_tick_;
    lockstep_.Advance(EvaluateDrive(scene_.drive, scene_.clock.TimeAt(lockstep_tick_)));
  }
  // from here on, the driver's present input held
  const double t = scene_.clock.TimeAt(tick);
  const double dt = scene_.clock.dt();
  const HeldDrive held = HeldDriveAt(scene_.drive, t);
  const Longitudinal now = EvaluateDrive(scene_.drive, t);
  rollout_.reset();
  rollout_.emplace(lockstep_);
  std::int64_t step = 0;
  for (std::size_t kb = 0; kb < block_ticks.size(); ++kb) {
    Eigen::Matrix<double, 6, 1> sum = Eigen::Matrix<double, 6, 1>::Zero();
    for (int k = 0; k < block_ticks[kb]; ++k, ++step) {
      const ChairSample& sample =
          step == 0 ? rollout_->sample()
                    : rollout_->Advance(HeldLongitudinal(now, held, static_cast<double>(step) * dt));
      const HeadMotion h = HeadMotionFromChair(sample, scene_.occupant.head_offset);
      sum += Eigen::Matrix<double, 6, 1>(h.fs[0], h.fs[1], h.fs[2] - kGravity, h.w[0], h.w[1], h.w[2]);
    }
    means.col(static_cast<Eigen::Index>(kb)) = sum / static_cast<double>(block_ticks[kb]);
  }
}

CarRolloutPredictor::CarRolloutPredictor(const vehicle::Vehicle& car, const std::vector<vehicle::CarSample>& samples,
                                         const std::array<double, 3>& head_offset, double dt, double steer_return)
    : car_(car), samples_(samples), head_offset_(head_offset), dt_(dt), steer_return_(steer_return) {
  PWSIM_DEMAND(!samples.empty() && dt > 0.0 && steer_return >= 0.0);
}

void CarRolloutPredictor::Predict(std::int64_t tick, const std::vector<int>& block_ticks, Eigen::MatrixXd& means) {
  const auto last = static_cast<std::int64_t>(samples_.size()) - 1;
  vehicle::CarSample sample = samples_[static_cast<std::size_t>(std::clamp<std::int64_t>(tick, 0, last))];
  vehicle::DriverInput held = sample.input;  // the driver's present controls, held
  held.starter = false;
  // the model stepped every `stride` ticks (kCarRolloutStep), each state held over its ticks
  const int stride = std::max(1, static_cast<int>(std::lround(kCarRolloutStep / dt_)));
  std::int64_t step = 0;
  vehicle::CarHeadMotion h = vehicle::HeadMotionOfCar(sample, head_offset_);
  for (std::size_t kb = 0; kb < block_ticks.size(); ++kb) {
    Eigen::Matrix<double, 6, 1> sum = Eigen::Matrix<double, 6, 1>::Zero();
    for (int k = 0; k < block_ticks[kb]; ++k, ++step) {
      if (step > 0 && step % stride == 0) {
        vehicle::DriverInput input = held;
        if (steer_return_ > 0.0) input.steer = held.steer * std::exp(-static_cast<double>(step) * dt_ / steer_return_);
        sample = vehicle::NextCarSample(car_, sample, input, dt_ * stride);
        h = vehicle::HeadMotionOfCar(sample, head_offset_);
      }
      sum += Eigen::Matrix<double, 6, 1>(h.fs[0], h.fs[1], h.fs[2] - kGravity, h.w[0], h.w[1], h.w[2]);
    }
    means.col(static_cast<Eigen::Index>(kb)) = sum / static_cast<double>(block_ticks[kb]);
  }
}

}  // namespace pwsim::mca
