#include "hardware/car_drive_source.h"

#include <algorithm>
#include <cmath>

#include "hardware/car_session_streams.h"

namespace pwsim::hw {

vehicle::DriverInput CarControlsFromJoystick(const JoystickSample& joystick, double speed_mps,
                                             const JoystickCarParams& params) {
  vehicle::DriverInput in;
  in.gear = params.gear;
  if (!joystick.valid) {  // lost joystick: stop
    in.brake = 1.0;
    in.clutch = 1.0;
    return in;
  }
  in.throttle = std::min(std::max(0.0, joystick.y), 1.0);  // max first: no -0 in the logs
  in.brake = std::min(std::max(0.0, -joystick.y), 1.0);
  in.steer = -std::clamp(joystick.x, -1.0, 1.0) * params.steer_lock_rad;
  const double slip = params.bite_clutch * std::clamp(1.0 - speed_mps / params.engage_speed_mps, 0.0, 1.0);
  in.clutch = in.throttle < 0.05 && speed_mps < params.engage_speed_mps ? 1.0 : slip;
  return in;
}

Pose CarEyePose(const vehicle::CarScene& scene, const vehicle::VehicleState& s) {
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const auto& o = scene.head_offset;
  const std::array<double, 3> eye{s.x + c * o[0] - sn * o[1], s.y + sn * o[0] + c * o[1],
                                  scene.car.chassis.cg_height + o[2]};
  return CarCameraPose(eye, s.yaw, s.pitch, s.roll);
}

CarDriveSource::CarDriveSource(const vehicle::CarScene& scene, const mca::McaConfig& mca, JoystickSource& joystick,
                               JoystickCarParams params)
    : scene_(scene), loop_(scene, mca), joystick_(joystick), params_(params) {}

void CarDriveSource::Fill(std::int64_t tick, bool drive, bool frame, std::int64_t now_ns, SessionInputs* in) {
  last_ = joystick_.Poll(tick, now_ns);
  if (!last_.valid) ++invalid_polls_;
  for (; car_tick_ < tick; ++car_tick_) {
    const double v = vehicle::Speed(loop_.last().sample.state);
    loop_.Step(CarControlsFromJoystick(last_, v, params_));
  }
  const CarLiveTick& t = loop_.last();
  if (drive) {
    in->setpoint = t.command.pose;
  }
  if (frame) in->camera = CarEyePose(scene_, t.sample.state);
}

}  // namespace pwsim::hw
