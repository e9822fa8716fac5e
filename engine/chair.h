#pragma once
// Chair: the parameters of a power wheelchair in the sagittal plane (seed 000, Table I) and
// its file format `pwsim-chair/1` (measured-trials.md). Pure data; models read it.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/yaml_reader.h"

namespace pwsim {

inline constexpr int kMaxWheels = 8;  ///< sagittal contact points a chair may have

struct Wheel {
  std::string name;
  double x{0.0};       ///< [m] along the chair's forward axis from O_V (front positive)
  double radius{0.1};  ///< [m] wheel radius (used by the wheel_radius extension)
};

/// Weight β_ij of the slope between wheels i and j (0-based, i < j) in eq. (2).
struct PairWeight {
  int i{0};
  int j{1};
  double weight{0.0};  ///< [-]
};

/// Geometric model weights, eq. (1)-(2).
struct GeometricParams {
  std::vector<double> alpha;      ///< [-] one per wheel, eq. (1)
  std::vector<PairWeight> beta;   ///< [-] eq. (2); pairs not listed weigh 0
};

/// Lumped model stiffness and damping, eq. (3).
struct LumpedParams {
  double k_z{4.18e4};      ///< [N/m]
  double c_z{2.24e3};      ///< [N s/m]
  double k_theta{1.04e4};  ///< [N m/rad]
  double c_theta{560.0};   ///< [N m s/rad]
};

struct Chair {
  std::string name{"pw6"};
  double mass{53.0};       ///< M_0 [kg] moving mass of the empty chair
  double inertia{9.9};     ///< J_0 [kg m^2] pitch inertia of the empty chair
  double cm_height{0.43};  ///< d_CM [m]
  std::vector<Wheel> wheels;
  std::optional<GeometricParams> gm;
  std::optional<LumpedParams> lm;

  int wheel_count() const { return static_cast<int>(wheels.size()); }
};

/// M = M_0 + M_u, eq. (4) [kg].
double MovingMass(const Chair& chair, double load_kg);
/// J = J_0 + d_CM^2 M, eq. (5) [kg m^2].
double PitchInertia(const Chair& chair, double load_kg);

/// The 6-wheel chair of Table I with its identified GM and LM.
Chair MakeTableOneChair();

/// Natural frequency [rad/s] and damping ratio [-] of one axis of the lumped model.
struct Mode {
  double omega_n{0.0};
  double zeta{0.0};
};
Mode HeaveMode(const Chair& chair, double load_kg);
Mode PitchMode(const Chair& chair, double load_kg);

/// Reads the chair fields (everything but `format`) from an open mapping.
Chair ParseChair(YamlMap& map);
/// Reads a `pwsim-chair/1` file.
Chair ReadChairFile(const std::filesystem::path& file);
/// `pwsim-chair/1` text for `chair` (gm/lm written when present).
std::string ChairToYaml(const Chair& chair);

}  // namespace pwsim
