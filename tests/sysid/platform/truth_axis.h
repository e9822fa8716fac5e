#pragma once
// An independent truth model of one electro-mechanical axis (EMPS-like: motor + ball screw +
// load) under the EMPS position loop, used to generate recordings with hidden effects for the
// diagnosis tests. It shares no code with sysid/platform/: the axis is two bodies (motor side,
// measured; load side) joined by a transmission that is rigid, a spring-damper, or a spring
// with a dead band; friction acts on the load with a Karnopp stick band; the integrator is
// semi-implicit Euler at 10 µs; the position is quantised like an encoder and a white force
// disturbance plays the part of unmodelled noise. Truth never enters the recording.

#include <cstdint>

#include "sysid/platform/axis_recording.h"

namespace pwsim::test {

struct TruthAxisParams {
  double motor_mass{25.0};   ///< [kg] equivalent mass of the motor side
  double load_mass{70.0};    ///< [kg]
  double fv_pos{200.0}, fv_neg{200.0};  ///< [N s/m] viscous, moving + / −
  double fc_pos{20.0}, fc_neg{20.0};    ///< [N] Coulomb, moving + / −
  double offset{-3.0};                  ///< [N] constant force (gravity, cable)
  double stribeck_extra{0.0};           ///< [N] breakaway − Coulomb
  double stribeck_speed{0.01};          ///< [m/s]
  double coulomb_slope{0.0};            ///< [1/m] relative Coulomb change per metre from 0.12 m
  double cogging_amplitude{0.0};        ///< [N]
  double cogging_period{0.02};          ///< [m]
  double stiffness{0.0};                ///< [N/m] transmission; 0 = rigid
  double damping{0.0};                  ///< [N s/m] transmission
  double backlash_gap{0.0};             ///< [m] total dead band (needs stiffness > 0)
  double force_noise{1.5};              ///< [N] std of a white force disturbance at 1 kHz
  double encoder_quantum{1e-6};         ///< [m]
  // EMPS loop.
  double kp{160.18}, kv{243.45}, gain{35.150652}, limit{10.0};
  int delay_samples{1};                 ///< 0 or 1: command applied now or one sample later
  double duration{25.0};                ///< [s]
  std::uint64_t seed{1};
};

/// Simulates the axis tracking a random sequence of trapezoidal-velocity moves (speeds 0.03 to
/// 0.3 m/s, accelerations 0.5 to 3 m/s², stroke 0.01 to 0.23 m), sampled at 1 kHz.
sysid::platform::AxisRecording SimulateTruthAxis(const TruthAxisParams& params);

}  // namespace pwsim::test
