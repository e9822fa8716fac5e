#pragma once
// A power wheelchair driven live through a circuit by a joystick, as a session source (the
// car's twin: car_drive_source.h). Each session step polls the joystick and steps the full-DoF
// chair through the circuit (engine/circuit.h CircuitRunner::AdvanceWith: walls, obstacles,
// gates) over every engine tick since the last step with that reading; the head motion of each
// tick goes through the session's MCA (mca::McaStepper: the scene's algorithm, or the command
// line's --mca washout|mpc over it, mca::ChooseAlgorithm) on the session's platform (the
// scene's own, pw4dof by default: heave, roll, pitch and yaw on five drives; or --platform's),
// whose pose command goes to the core (inverse kinematics -> the CiA 402 setpoints), exactly as
// `pwsim session` runs a chair scene; its peak use per axis is reported.
// Live there is no trial ahead: the MPC predicts with the current input held (no preview).
// The head motion of tick k is differenced from the head poses of k-1, k, k+1
// (mca::HeadMotionAt), so the MCA runs one engine tick (1 ms at 1 kHz) behind the chair.
// On frame ticks the camera is the head's pose (position, yaw, pitch, roll of the chair).
//
// Joystick -> chair deflection (pure): forward f = y, turn t = -x (x right, t left +), both
// clamped to [-1, 1]; an invalid reading (lost device, R-Net watchdog) releases the joystick:
// (0, 0), and the controller profile brakes the chair to rest.
//
// Every tick's TrainingTick is kept (capacity reserved up front: no allocation in the tick)
// for the training metrics of the drive (engine/training_metrics.h).

#include <array>
#include <optional>
#include <vector>

#include "engine/circuit.h"
#include "engine/scene.h"
#include "engine/training_metrics.h"
#include "hardware/joystick_source.h"
#include "hardware/session_runner.h"
#include "mca/config.h"
#include "mca/cueing.h"
#include "mca/head_motion.h"

namespace pwsim::hw {

JoystickInput ChairDeflectionFromJoystick(const JoystickSample& joystick);

class ChairDriveSource final : public SessionSource {
 public:
  /// @pre scene.is_circuit(); scene's clock = the session's; `joystick` outlives this;
  /// `max_ticks`: the trace keeps ticks 0..max_ticks (the drive; not the park after it);
  /// `mca`: the session's MCA (SessionMcaConfig: the scene's platform or --platform's, the
  /// scene's algorithm or --mca's).
  /// @throws std::invalid_argument (an MPC that cannot start from rest).
  ChairDriveSource(const Scene& scene, JoystickSource& joystick, std::int64_t max_ticks, const mca::McaConfig& mca);
  void Fill(std::int64_t tick, bool drive, bool frame, std::int64_t now_ns, SessionInputs* in) override;
  InputStamp input() const override { return {last_.input_seq, last_.input_ns}; }
  bool has_live_input() const override { return true; }
  int input_fd() const override { return joystick_.fd(); }
  void TakeInput(std::int64_t next_tick, std::int64_t now_ns) override { joystick_.Take(next_tick, now_ns); }

  const FullChairSample& last_sample() const { return runner_.sample(); }
  const std::vector<TrainingTick>& trace() const { return trace_; }
  const mca::McaConfig& mca() const { return mca_; }
  /// The MPC's solves and fallbacks (zero with the washout).
  mca::MpcStats mpc_stats() const { return cue_.mpc_stats(); }
  /// Largest |pose command| per axis of the MCA so far [m | rad].
  const mca::DofArray& peak() const { return peak_; }
  /// Polls of ticks 0..max_ticks (the drive; not the park after it) that found the joystick invalid.
  std::uint64_t invalid_polls() const { return invalid_polls_; }

 private:
  void StepChair(const JoystickInput& deflection);
  void Record();

  const Scene& scene_;
  JoystickSource& joystick_;
  CircuitRunner runner_;
  mca::McaConfig mca_;
  mca::McaStepper cue_;
  std::array<mca::PointPose, 3> head_{};  ///< head at ticks k-2, k-1, k (k = chair_tick_)
  std::int64_t chair_tick_{0};            ///< the chair has been stepped up to this tick
  JoystickSample last_;
  std::uint64_t invalid_polls_{0};
  mca::DofArray peak_{};
  std::int64_t max_ticks_{0};
  std::vector<TrainingTick> trace_;
};

}  // namespace pwsim::hw
