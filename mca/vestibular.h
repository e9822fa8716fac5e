#pragma once
// Vestibular models: what the occupant perceives of a head motion.
//   otolith (Young–Meiry form, Reid & Nahon constants), per axis of specific force:
//     H_oto(s) = K (τa s + 1) / ((τL s + 1)(τS s + 1)),  K 0.4, τa 13.2 s, τL 5.33 s, τS 0.66 s
//   semicircular canals, per axis of angular velocity:
//     H_scc(s) = τa τL s² / ((τa s + 1)(τL s + 1)(τS s + 1)),
//     τL 6.1 s (roll, x), 5.3 s (pitch, y), 10.2 s (yaw, z); τS 0.1 s; τa 30 s
// The otolith acts on the deviation of specific force from rest, fs - (0, 0, g), so a head at
// rest perceives zero on every axis. Constants: docs/mca.md (source status noted there).
//
//   VestibularModel model(VestibularParams{}, dt);
//   Perceived p = model.Step(head_motion);   // no allocation

#include <array>
#include <string>

#include "engine/yaml_reader.h"
#include "mca/head_motion.h"
#include "mca/lti.h"

namespace pwsim::mca {

struct OtolithParams {
  double gain{0.4};    ///< K [-]
  double tau_a{13.2};  ///< lead τa [s]
  double tau_l{5.33};  ///< long lag τL [s]
  double tau_s{0.66};  ///< short lag τS [s]
  bool operator==(const OtolithParams&) const = default;
};

struct CanalParams {
  double tau_a{30.0};                      ///< adaptation τa [s]
  double tau_s{0.1};                       ///< short τS [s]
  std::array<double, 3> tau_l{6.1, 5.3, 10.2};  ///< long τL per axis x (roll), y (pitch), z (yaw) [s]
  bool operator==(const CanalParams&) const = default;
};

/// Perception thresholds used to call a cue false (see consistency metrics).
struct PerceptionThresholds {
  std::array<double, 3> fs{0.17, 0.17, 0.28};  ///< specific force x, y, z [m/s^2]
  std::array<double, 3> w{3.0 * kDegToRad, 3.6 * kDegToRad, 2.6 * kDegToRad};  ///< [rad/s]
  double tilt_rate{3.0 * kDegToRad};           ///< [rad/s] tilt perceived as rotation above this
  bool operator==(const PerceptionThresholds&) const = default;
};

struct VestibularParams {
  OtolithParams otolith;
  CanalParams canals;
  PerceptionThresholds thresholds;
  bool operator==(const VestibularParams&) const = default;
  std::string Validate() const;
};

/// Reads `mca.vestibular` over `base` (otolith, canals, thresholds; every field optional).
VestibularParams ParseVestibularParams(YamlMap& map, const VestibularParams& base);

ContinuousSystem OtolithSystem(const OtolithParams& params);
/// @pre axis in 0..2.
ContinuousSystem CanalSystem(const CanalParams& params, int axis);

/// Perceived motion: otolith output per specific-force axis [m/s^2], canal output per
/// angular-velocity axis [rad/s] (right-handed x, y, z like HeadMotion::w).
struct Perceived {
  std::array<double, 3> fs{};
  std::array<double, 3> w{};
};

class VestibularModel {
 public:
  VestibularModel(const VestibularParams& params, double dt);
  void Reset();
  /// One tick; a non-finite input is treated as rest. No allocation.
  Perceived Step(const HeadMotion& motion);

 private:
  std::array<DiscreteSystem, 3> otolith_{};
  std::array<DiscreteSystem, 3> canal_{};
  std::array<FilterState, 3> otolith_state_{};
  std::array<FilterState, 3> canal_state_{};
};

}  // namespace pwsim::mca
