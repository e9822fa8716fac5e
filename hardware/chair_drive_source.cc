#include "hardware/chair_drive_source.h"

#include <algorithm>
#include <cmath>

#include "engine/check.h"
#include "hardware/car_session_streams.h"

namespace pwsim::hw {
namespace {

mca::DofArray BodyPose(const FullChairSample& s) {
  return {s.planar.x, s.planar.y, s.lm.z, s.roll, s.lm.pitch, s.planar.yaw};
}

}  // namespace

JoystickInput ChairDeflectionFromJoystick(const JoystickSample& joystick) {
  if (!joystick.valid) return {};
  // max/min first, then negate only a non-zero turn: no -0 in the logs
  const double turn = std::clamp(joystick.x, -1.0, 1.0);
  return {std::clamp(joystick.y, -1.0, 1.0), turn == 0.0 ? 0.0 : -turn};
}

ChairDriveSource::ChairDriveSource(const Scene& scene, JoystickSource& joystick, std::int64_t max_ticks,
                                   const mca::McaConfig& mca)
    : scene_(scene),
      joystick_(joystick),
      runner_(scene.chair, *scene.circuit, scene.load_kg, scene.clock.dt(), scene.pitch_torque),
      mca_(mca),
      cue_(mca_, scene.clock.dt()) {
  PWSIM_DEMAND(scene.is_circuit() && max_ticks >= 0);
  max_ticks_ = max_ticks;
  trace_.reserve(static_cast<std::size_t>(max_ticks) + 1);
  const FullChairSample& start = runner_.Start();
  const mca::PointPose head = mca::PointOnBody(BodyPose(start), scene_.occupant.head_offset);
  head_ = {head, head, head};  // at rest before the start
  Record();
}

void ChairDriveSource::Record() {
  const FullChairSample& s = runner_.sample();
  trace_.push_back(TrainingTickOf(s, scene_.clock.TimeAt(chair_tick_), head_[2].p));
}

void ChairDriveSource::StepChair(const JoystickInput& deflection) {
  const FullChairSample& s = runner_.AdvanceWith(deflection);
  ++chair_tick_;
  head_[0] = head_[1];
  head_[1] = head_[2];
  head_[2] = mca::PointOnBody(BodyPose(s), scene_.occupant.head_offset);
  const mca::HeadMotion motion = mca::HeadMotionAt(head_[0], head_[1], head_[2], scene_.clock.dt());
  const mca::McaCommand& c = cue_.Step(motion);
  for (std::size_t i = 0; i < c.pose.size(); ++i) peak_[i] = std::max(peak_[i], std::abs(c.pose[i]));
  if (chair_tick_ <= max_ticks_) Record();
}

void ChairDriveSource::Fill(std::int64_t tick, bool drive, bool frame, std::int64_t now_ns, SessionInputs* in) {
  last_ = joystick_.Poll(tick, now_ns);
  if (!last_.valid && tick <= max_ticks_) ++invalid_polls_;  // during the drive, not the park after it
  const JoystickInput deflection = ChairDeflectionFromJoystick(last_);
  while (chair_tick_ < tick) StepChair(deflection);
  if (drive) in->setpoint = cue_.command().pose;
  if (frame) {
    const FullChairSample& s = runner_.sample();
    in->camera = CarCameraPose(head_[2].p, s.planar.yaw, s.lm.pitch, s.roll);
  }
}

}  // namespace pwsim::hw
