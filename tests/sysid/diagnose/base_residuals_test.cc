// What the residual analysis' evidence lines say (sysid/diagnose/base_residuals.h, Analyse):
// base-model residuals with one known signature each, built here from their physical
// description, must be reported by the line of the effect that leaves that signature, with
// the figures their closed forms give.
//
// Each trial drives the Table I chair over a 6 cm plateau: 1 s at rest, 0.8 m/s² up to its
// cruise speed, cruise, 0.8 m/s² down to rest. The base model's GM output is a smooth heave
// and pitch; the base model follows the GM but for a suspension deflection (a slow sine), and
// the measured channels are the base model plus the signature under test.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "sysid/diagnose/base_residuals.h"
#include "sysid/diagnose/format_text.h"

namespace pwsim::diagnose {
namespace {

using effects::EffectId;

constexpr double kAccel = 0.8;  ///< [m/s²] programmed acceleration and deceleration
constexpr double kRate = 100.0;  ///< [Hz]

Terrain Plateau() {
  Terrain terrain;
  terrain.x = {3.0, 3.3, 4.3, 4.6};
  terrain.z = {0.0, 0.06, 0.06, 0.0};
  return terrain;
}

struct Drive {
  double x{0.0}, v{0.0}, a{0.0};
};

/// The drive at time t: rest 1 s, accelerate to `cruise`, cruise 4 m, decelerate to rest.
Drive DriveAt(double t, double cruise) {
  const double t_up = cruise / kAccel, up = 0.5 * cruise * t_up, t_cruise = 4.0 / cruise;
  double s = t - 1.0;
  if (s <= 0.0) return {};
  if (s < t_up) return {0.5 * kAccel * s * s, kAccel * s, kAccel};
  s -= t_up;
  if (s < t_cruise) return {up + cruise * s, cruise, 0.0};
  s -= t_cruise;
  if (s < t_up) return {up + 4.0 + cruise * s - 0.5 * kAccel * s * s, cruise - kAccel * s, -kAccel};
  return {2.0 * up + 4.0, 0.0, 0.0};
}

/// A trial whose measured channels are the base model's output: add the signature to z, pitch.
std::pair<TrialAnalysis, effects::TrialRecord> Trial(double cruise, double load_kg) {
  TrialAnalysis a;
  a.name = "v" + std::to_string(cruise) + "_m" + std::to_string(load_kg);
  a.speed = cruise;
  a.load_kg = load_kg;
  const double duration = 1.0 + 2.0 * cruise / kAccel + 4.0 / cruise + 1.0;
  for (double t = 0.0; t <= duration; t += 1.0 / kRate) {
    const Drive d = DriveAt(t, cruise);
    a.t.push_back(t);
    a.x.push_back(d.x);
    a.accel.push_back(d.a);
    const double gm_z = 0.02 * std::sin(0.7 * t), gm_pitch = 0.03 * std::sin(0.9 * t + 0.4);
    a.z_gm.push_back(gm_z);
    a.pitch_gm.push_back(gm_pitch);
    a.z_base.push_back(gm_z + 0.002 * std::sin(2.0 * std::numbers::pi * 1.3 * t));
    a.pitch_base.push_back(gm_pitch + 0.003 * std::sin(2.0 * std::numbers::pi * 1.1 * t));
  }
  a.z = a.z_base;
  a.pitch = a.pitch_base;
  a.z_ext = a.z_base;
  a.pitch_ext = a.pitch_base;
  effects::TrialRecord r;
  r.name = a.name;
  r.terrain = Plateau();
  r.load_kg = load_kg;
  r.speed = cruise;
  r.t = a.t;
  r.x = a.x;
  r.z = a.z;
  r.pitch = a.pitch;
  return {a, r};
}

struct Set {
  Chair chair = MakeTableOneChair();
  std::vector<TrialAnalysis> trials;
  std::vector<effects::TrialRecord> records;
};

Set MakeSet() {
  Set set;
  for (const auto& [v, m] : {std::pair{0.6, 0.0}, std::pair{1.2, 50.0}, std::pair{1.8, 100.0}}) {
    auto [a, r] = Trial(v, m);
    r.chair = set.chair;
    set.trials.push_back(std::move(a));
    set.records.push_back(std::move(r));
  }
  return set;
}

const std::string& Line(const ResidualReport& rep, EffectId id) {
  return rep.evidence.at(static_cast<std::size_t>(id));
}

TEST(ResidualEvidenceTest, OneLinePerEffectInCatalogueOrder) {
  const Set set = MakeSet();
  const ResidualReport rep = Analyse(set.trials, set.chair, set.records);
  ASSERT_EQ(rep.evidence.size(), effects::AllEffects().size());
  EXPECT_EQ(Line(rep, EffectId::kInertialPitch).rfind("pitch residual vs a_x r = ", 0), 0u);
  EXPECT_EQ(Line(rep, EffectId::kMarkerOffset).rfind("Z residual vs model pitch: slope ", 0), 0u);
  EXPECT_EQ(Line(rep, EffectId::kCushionCompliance).rfind("obstacle-top Z residual vs drive-wheel load: ", 0), 0u);
  EXPECT_EQ(Line(rep, EffectId::kTyreCompliance).rfind("residual power above 6 Hz: ", 0), 0u);
}

// A pitch residual proportional to the longitudinal acceleration (an inertial torque the base
// model leaves out): r = 1 with a_x, and its RMS per phase is the constant times 0.8 m/s²
// accelerating and decelerating, 0 cruising.
TEST(ResidualEvidenceTest, PitchResidualInAccelerationIsInertialPitch) {
  Set set = MakeSet();
  constexpr double kRadPerAccel = 0.002;  // [rad per m/s²]
  for (TrialAnalysis& t : set.trials)
    for (std::size_t k = 0; k < t.t.size(); ++k) t.pitch[k] += kRadPerAccel * t.accel[k];
  const ResidualReport rep = Analyse(set.trials, set.chair, set.records);
  const double rms_mrad = 1e3 * kRadPerAccel * kAccel;  // 1.60
  EXPECT_EQ(Line(rep, EffectId::kInertialPitch),
            Format("pitch residual vs a_x r = 1.00; RMS pitch residual %.2f/%.2f mrad "
                   "accelerating/decelerating vs 0.00 cruising",
                   rms_mrad, rms_mrad));
  // The heave channel is untouched: no lever shows in the marker's line.
  EXPECT_EQ(Line(rep, EffectId::kMarkerOffset), "Z residual vs model pitch: slope 0.000 m (r = 0.00)");
}

// A marker 0.15 m ahead of O_V measures Z + r_x sin θ: a heave residual r_x θ of the model's
// pitch (small angles), reported as the slope r_x with r = 1.
TEST(ResidualEvidenceTest, HeaveResidualInModelPitchIsAMarkerLever) {
  Set set = MakeSet();
  constexpr double kLeverM = 0.15;
  for (TrialAnalysis& t : set.trials)
    for (std::size_t k = 0; k < t.t.size(); ++k) t.z[k] += kLeverM * t.pitch_base[k];
  const ResidualReport rep = Analyse(set.trials, set.chair, set.records);
  EXPECT_EQ(Line(rep, EffectId::kMarkerOffset), "Z residual vs model pitch: slope 0.150 m (r = 1.00)");
}

// A cushion that yields under the drive wheel: on the plateau the chair sits lower by
// c W, W the drive wheel's static load α_d (m_chair + m_load) g. The line reports the slope
// −c (in mm/kN) with r = −1 over the three trials.
TEST(ResidualEvidenceTest, PlateauSinkingWithLoadIsCushionCompliance) {
  Set set = MakeSet();
  constexpr double kMetresPerKn = 0.002;
  int drive = 0;
  for (int i = 0; i < set.chair.wheel_count(); ++i)
    if (set.chair.wheels[i].radius > set.chair.wheels[drive].radius) drive = i;
  const Terrain terrain = Plateau();
  for (TrialAnalysis& t : set.trials) {
    const double load_kn = set.chair.gm->alpha[drive] * MovingMass(set.chair, t.load_kg) * 9.81 * 1e-3;
    for (std::size_t k = 0; k < t.t.size(); ++k) {
      const double h = terrain.HeightAt(t.x[k] + set.chair.wheels[drive].x);
      if (h > 0.9 * 0.06) t.z[k] -= kMetresPerKn * load_kn;
    }
  }
  const ResidualReport rep = Analyse(set.trials, set.chair, set.records);
  EXPECT_EQ(Line(rep, EffectId::kCushionCompliance),
            Format("obstacle-top Z residual vs drive-wheel load: %.2f mm/kN (r = -1.00, 3 trials)",
                   -1e3 * kMetresPerKn));
}

}  // namespace
}  // namespace pwsim::diagnose
