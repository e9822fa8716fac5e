#pragma once
// law_space: the independent truth's evaluation draw. For a set seed and the effects it hides,
// each effect's physical law, its parameters and its strength are drawn from ranges, and the
// measurement noise from white, low-pass filtered, drifting, outlying or mixed noise
// (measurement_noise.h). Nothing here is tuned to pwsim's candidate models (sysid/effects).
//
// Seeds 1-999 form the development set (tests may pin them; verdict calibration uses them);
// seeds >= 1000 are the evaluation set that no change is tuned on
// (scripts/evaluate-diagnosis.sh). The chair and the cushion come from the seed as in
// SimulateTruthSet; the laws and the noise from a generator of their own, so adding an effect
// does not change the chair.
//
// Laws per effect (ranges uniform unless "log", strength within each range):
//   wheel_radius          discs of 0.6-1.4 × the nominal radius
//   tyre_compliance       unsprung mass on a tyre (casters 5-12 Hz, 2-4 kg; drive wheels
//                         8-25 Hz on 5-10 kg or rigid; ζ 0.04-0.2) | massless series spring-
//                         damper (k_t/k 0.4-3 log on casters, the drive wheels the same, 2-3 × or
//                         rigid; τ_t 2-10 ms; not beside suspension_friction)
//   cushion_compliance    sinks under each wheel's load, (F/F_ref)^p, p 0.5-1.5, F_ref 500 N |
//                         under the whole chair's weight, F_ref 1500 N | yields a fixed share;
//                         yield a 0.08-0.25 at F_ref, foam τ 10-30 ms
//   heave_pitch_coupling  front springs × (1 ± e), rear × (1 ∓ e), |e| 0.15-0.4, dampers too or not
//   nonlinear_stiffness   stops at gap 2-6 mm, gain 0.3-1.2, on compression | rebound | both
//   suspension_friction   Dahl per wheel (presliding 0.3-1.5 mm) | smooth Coulomb per wheel |
//                         smooth Coulomb at chair level | Stribeck per wheel (F_s/F_c 1.3-2,
//                         v_St 5-20 mm/s); F_c 20-60 N, v_s 2-10 mm/s, viscous share 0-30 % of c
//   inertial_pitch        chassis CM 0.5-1.5 × d_CM, load CM 0.35-0.8 m above O_V
//   marker_offset         lever ±(0.05-0.2) m forward, 0.2-0.7 m up
//   occupant_seat         (outside the catalogue) share 0.4-0.9 on a seat spring 3-6 Hz,
//                         ζ 0.15-0.4, 0.1 m either side of O_V
// Noise kinds (σ of the white part 0.15-0.6 mm log, pitch 1.2-2 rad/m × that):
//   white | lowpass (Butterworth order 2-4 at 6-15 Hz, zero phase, σ after the filter in the
//   same range) | drift (random walk reaching 0.5-2 mm over 10 s, or a 0.3-1.5 mm sinusoid at
//   0.05-0.3 Hz) | outliers (p 0.1-0.5 % per sample, 3-10 mm, pitch 1-3 rad/m × that) |
//   mix (lowpass + drift + outliers).
// Kinds never drawn, only forced (`--noise KIND`), to try the diagnosis on noise it was not
// calibrated on (measurement_noise.h): pink (1/f from 0.05-0.2 to 40 Hz) | sine (a 0.5-1.5 mm
// sinusoid at 0.05-0.15 Hz alone) | step (a level step of 0.3-1.5 mm at a random time) | burst
// (outliers in bursts of 2-5 samples, p 0.05-0.2 %) | quantised (rounded to 1-3 σ); each on
// white noise of the range above. Forcing one leaves the effects' laws as drawn.

#include <cstdint>
#include <string>
#include <vector>

#include "tests/truth/independent_truth.h"

namespace pwsim::truth {

struct LawDraw {
  TruthEffects effects;
  MeasurementNoise noise;
  std::vector<std::string> laws;  ///< one line per effect and one for the noise, for the truth file
};

std::vector<std::string> NoiseKinds();  ///< white, lowpass, drift, outliers, mix
std::vector<std::string> ExtraNoiseKinds();  ///< pink, sine, step, burst, quantised (forced only)

/// The laws of `effects` (TruthEffectNames()) and the noise for set `seed`. `noise_kind` empty:
/// drawn; otherwise one of NoiseKinds() or ExtraNoiseKinds(). @throws std::invalid_argument for an unknown name or kind.
LawDraw DrawLaws(std::uint64_t seed, const std::vector<std::string>& effects, const TruthChair& chair,
                 const std::string& noise_kind = "");

}  // namespace pwsim::truth
