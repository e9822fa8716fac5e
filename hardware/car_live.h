#pragma once
// A car driven live, tick by tick: the controls of this tick in (a real wheel through
// hardware/sdl, or any other source), the car's step and the MCA's platform command out.
// The same per-tick functions as the offline run (vehicle::NextCarSample, the MCA through
// mca::McaStepper: the washout or, with `mca: {algorithm: mpc}`, the MPC with the held-input
// prediction; the rail-yaw false cue), so a live drive and `pwsim run` of the same controls agree
// exactly.
//
//   CarLiveLoop loop(scene, mca::LoadCarMcaConfig(scene));
//   while (running) { const CarLiveTick& t = loop.Step(wheel.Poll()); send(t.command.pose); }

#include "engine/vehicle/car_scene.h"
#include "mca/config.h"
#include "mca/cueing.h"

namespace pwsim::hw {

struct CarLiveTick {
  vehicle::CarSample sample;
  mca::McaCommand command;
  double false_cue_surge{0.0};  ///< -r² x [m/s^2] of the command (mca/rail_yaw.h)
  double false_cue_sway{0.0};   ///< r' x + 2 r x' [m/s^2]
};

class CarLiveLoop {
 public:
  /// Tick 0 (the scene's start state) is processed here. @pre config validated.
  CarLiveLoop(const vehicle::CarScene& scene, const mca::McaConfig& config);
  /// Advances one clock tick with `input`. No allocation.
  const CarLiveTick& Step(const vehicle::DriverInput& input);
  const CarLiveTick& last() const { return tick_; }

 private:
  void Cue();

  const vehicle::CarScene& scene_;
  mca::McaStepper mca_;  ///< the washout or the MPC, as config.algorithm says
  CarLiveTick tick_;
};

}  // namespace pwsim::hw
