#pragma once
// The MPC's vehicle prediction without a preview, as a live loop has it: the vehicle model run
// forward from its present state with the driver's present input held (mca/mpc.h,
// VehiclePredictor). What lies ahead of the vehicle in the virtual world (the terrain) is the
// simulator's own; what the driver will do next is not known and is taken as what they do now.
//
// The straight run (engine/chair_simulator.h): the driver's input is the power module's speed
// command, read from the drive profile's phase at the present time t_k (engine/drive_profile.h):
//   still            → no command: the chair stays at rest
//   accelerate, cruise → the cruise speed V, reached at the programmed acceleration A
//   decelerate, stopped → 0, reached at the programmed deceleration D
// held: from the present (x₀, v₀) the speed moves towards the command at that rate and stays,
//   v(τ) = v₀ + clamp(V_cmd − v₀, −R τ, R τ),  x(τ) = x₀ + ∫₀^τ v,  a = dv/dτ.
// The chair model itself (the same simulator as the trial's, advanced in lockstep with it, then
// copied at each control step) turns that into the motion at the head over the terrain ahead:
// HeadMotionFromChair per tick, averaged over each block.
// Cost: one copy of the simulator and one simulated horizon (≈ 1000 ticks) per control period;
// the copy allocates (offline runs only: `pwsim run`).
//
// The car (engine/vehicle/): the driver's input is the pedals, gear and steering wheel of the
// present tick (CarSample::input, the starter released): pedals and gear held, the steering
// wheel returning to centre at `steer_return` (0.3 s; 0 holds it too) — on roads that run
// straight a steering input is a transient (held, a lane change's first half predicts a
// sustained turn: on stewart6dof, whose sway and roll render it, the MPC's perceived error on
// car_lane_change was 0.496 with the wheel held, 0.425 returning at 0.3 s, against the
// washout's 0.434; on car2dof, without sway, the same either way). The car model
// (NextCarSample, a pure step from the present sample) runs the horizon from the present state
// in steps of kCarRolloutStep, HeadMotionOfCar per step held over its ticks. Cost: ≈ 200 vehicle
// steps (0.45 µs each) per control period; no allocation. (5 ms steps against the trial's 1 ms:
// the perceived error of the MPC on car_launch 0.5882 against 0.5884, car_seed_drive 0.5402
// both, in half the run time.)
//
//   ChairRolloutPredictor predictor(scene);
//   McaStepper stepper(config, dt);  stepper.SetPredictor(&predictor);

#include <Eigen/Dense>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "engine/chair_simulator.h"
#include "engine/scene.h"
#include "engine/vehicle/car_scene.h"
#include "mca/mpc.h"

namespace pwsim::mca {

/// The held drive command at time t: the speed the power module is asked for and the rate it
/// approaches it at (the profile's acceleration or deceleration).
struct HeldDrive {
  double speed{0.0};  ///< [m/s]
  double rate{0.0};   ///< [m/s²] > 0
};
HeldDrive HeldDriveAt(const DriveProfile& profile, double t);
/// The longitudinal state τ after `from` with `held` (closed form of the header).
Longitudinal HeldLongitudinal(const Longitudinal& from, const HeldDrive& held, double tau);

class ChairRolloutPredictor final : public VehiclePredictor {
 public:
  /// The straight run of `scene` (SimulateScene's simulator); `scene` must outlive this.
  explicit ChairRolloutPredictor(const Scene& scene);

  void Predict(std::int64_t tick, const std::vector<int>& block_ticks, Eigen::MatrixXd& means) override;

 private:
  const Scene& scene_;
  ChairSimulator lockstep_;          ///< the trial's simulator, advanced to the present tick
  std::int64_t lockstep_tick_{-1};
  std::optional<ChairSimulator> rollout_;
};

/// [s] the car rollout's step.
inline constexpr double kCarRolloutStep = 5e-3;

class CarRolloutPredictor final : public VehiclePredictor {
 public:
  /// The trial's own samples (state and driver input per tick; they must outlive this), the
  /// car, the driver's head p_VH and the tick dt [s].
  CarRolloutPredictor(const vehicle::Vehicle& car, const std::vector<vehicle::CarSample>& samples,
                      const std::array<double, 3>& head_offset, double dt, double steer_return = 0.3);

  void Predict(std::int64_t tick, const std::vector<int>& block_ticks, Eigen::MatrixXd& means) override;

 private:
  const vehicle::Vehicle& car_;
  const std::vector<vehicle::CarSample>& samples_;
  std::array<double, 3> head_offset_;
  double dt_;
  double steer_return_;  ///< [s]
};

}  // namespace pwsim::mca
