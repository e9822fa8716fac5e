#include "hardware/car_live.h"

namespace pwsim::hw {

CarLiveLoop::CarLiveLoop(const vehicle::CarScene& scene, const mca::McaConfig& config)
    : scene_(scene), mca_(config, scene.clock.dt()) {
  tick_.sample = vehicle::FirstCarSample(scene);
  Cue();
}

void CarLiveLoop::Cue() {
  const vehicle::CarHeadMotion m = vehicle::HeadMotionOfCar(tick_.sample, scene_.head_offset);
  mca::HeadMotion head;
  head.fs = m.fs;
  head.w = m.w;
  tick_.command = mca_.Step(head);
  const auto& c = tick_.command;
  const double x = c.pose[mca::Index(mca::Dof::kSurge)];
  const double r = c.rate[mca::Index(mca::Dof::kYaw)];
  tick_.false_cue_surge = -r * r * x;
  tick_.false_cue_sway = c.accel[mca::Index(mca::Dof::kYaw)] * x + 2.0 * r * c.rate[mca::Index(mca::Dof::kSurge)];
}

const CarLiveTick& CarLiveLoop::Step(const vehicle::DriverInput& input) {
  tick_.sample = vehicle::NextCarSample(scene_.car, tick_.sample, input, scene_.clock.dt());
  Cue();
  return tick_;
}

}  // namespace pwsim::hw
