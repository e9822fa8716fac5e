#include "engine/chair_simulator.h"

#include <span>

namespace pwsim {

ChairSimulator::ChairSimulator(const Chair& chair, const Terrain& terrain, double load_kg,
                               double dt, PitchTorqueParams torque)
    : terrain_(terrain),
      gm_(chair),
      lumped_(Discretize(MakeLumpedModelParams(chair, load_kg), dt)),
      torque_(torque) {}

const ChairSample& ChairSimulator::Start(const Longitudinal& drive) {
  sample_ = ChairSample{};
  sample_.drive = drive;
  gm_.ContactHeights(terrain_, drive.x, std::span<double>(sample_.z_O.data(), wheel_count()));
  sample_.gm = gm_.Evaluate(std::span<const double>(sample_.z_O.data(), wheel_count()));
  sample_.pitch_torque = torque_.constant + torque_.per_accel * drive.a;
  // Static equilibrium: springs carry the torque, no motion.
  sample_.lm.z = sample_.gm.z;
  sample_.lm.pitch = sample_.gm.pitch + sample_.pitch_torque / lumped_.params.pitch.stiffness;
  return sample_;
}

const ChairSample& ChairSimulator::Advance(const Longitudinal& drive) {
  const GeometricOutput gm_begin = sample_.gm;
  const double torque = torque_.constant + torque_.per_accel * sample_.drive.a;  // held (ZOH)

  sample_.drive = drive;
  gm_.ContactHeights(terrain_, drive.x, std::span<double>(sample_.z_O.data(), wheel_count()),
                     std::span<std::size_t>(hints_.data(), wheel_count()));
  sample_.gm = gm_.Evaluate(std::span<const double>(sample_.z_O.data(), wheel_count()));

  const LumpedInput input{gm_begin.z, sample_.gm.z, gm_begin.pitch, sample_.gm.pitch, torque};
  sample_.lm = Step(lumped_, sample_.lm, input);
  sample_.z_gm_rate = (sample_.gm.z - gm_begin.z) * lumped_.inv_dt;
  sample_.pitch_gm_rate = (sample_.gm.pitch - gm_begin.pitch) * lumped_.inv_dt;
  sample_.pitch_torque = torque;
  sample_.lm_acc = Accelerations(lumped_.params, sample_.lm, sample_.gm.z, sample_.z_gm_rate,
                                 sample_.gm.pitch, sample_.pitch_gm_rate, torque);
  ++sample_.tick;
  return sample_;
}

}  // namespace pwsim
