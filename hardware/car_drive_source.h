#pragma once
// A car driven live by a joystick through a session: each session step polls the joystick,
// steps the car (vehicle::NextCarSample via CarLiveLoop) over every engine tick since the last
// step with that reading, and hands the session the MCA's rail + yaw pose command (the core's
// inverse kinematics: yaw -> q1, surge -> q2) on drive ticks and the driver's eye pose on frame ticks. The chair's live drive
// plugs in the same way (chair_drive_source.h).
//
// Joystick -> car controls (a two-pedal car with an automatic clutch, pure):
//   throttle = max(y, 0), brake = max(-y, 0), steer = -x * steer_lock (x right, steer left +),
//   gear = first; clutch = 1 (pedal pressed: open) when the throttle is below 5 % and the car is
//   slower than v_engage, else c_bite (1 - v / v_engage) clamped to [0, c_bite] (slipping at the
//   biting point from standstill, closed above v_engage); an invalid joystick reading brakes
//   fully with the clutch open.

#include <memory>

#include "engine/vehicle/car_scene.h"
#include "hardware/car_live.h"
#include "hardware/joystick_source.h"
#include "hardware/session_runner.h"

namespace pwsim::hw {

struct JoystickCarParams {
  double steer_lock_rad{7.854};   ///< steering-wheel angle at full deflection (±450°)
  int gear{1};
  double engage_speed_mps{3.0};   ///< clutch fully closed from this speed on
  double bite_clutch{0.65};       ///< pedal travel of the biting point (car_launch.yaml's launch)
};

vehicle::DriverInput CarControlsFromJoystick(const JoystickSample& joystick, double speed_mps,
                                             const JoystickCarParams& params);

/// The driver's eye pose in W for the car state `s` (head offset from the CoG, at CoG height).
Pose CarEyePose(const vehicle::CarScene& scene, const vehicle::VehicleState& s);

class CarDriveSource final : public SessionSource {
 public:
  /// @pre scene's clock = the session's; `joystick` outlives this.
  CarDriveSource(const vehicle::CarScene& scene, const mca::McaConfig& mca, JoystickSource& joystick,
                 JoystickCarParams params = {});
  void Fill(std::int64_t tick, bool drive, bool frame, std::int64_t now_ns, SessionInputs* in) override;
  InputStamp input() const override { return {last_.input_seq, last_.input_ns}; }
  bool has_live_input() const override { return true; }
  int input_fd() const override { return joystick_.fd(); }
  void TakeInput(std::int64_t next_tick, std::int64_t now_ns) override { joystick_.Take(next_tick, now_ns); }
  const CarLiveTick& last_tick() const { return loop_.last(); }
  const JoystickSample& last_joystick() const { return last_; }
  std::uint64_t invalid_polls() const { return invalid_polls_; }

 private:
  const vehicle::CarScene& scene_;
  CarLiveLoop loop_;
  JoystickSource& joystick_;
  JoystickCarParams params_;
  std::int64_t car_tick_{0};  ///< the car has been stepped up to this tick
  JoystickSample last_;
  std::uint64_t invalid_polls_{0};
};

}  // namespace pwsim::hw
