#pragma once
// The six cueing axes shared by every mca/ unit: three translations of the platform (surge x
// forward, sway y left, heave z up) and three rotations (roll about x, left side up positive;
// pitch nose-up positive, as everywhere in pwsim; yaw about z, turning left positive).
// A platform has a subset of them; interfaces always carry all six.

#include <array>
#include <string_view>

namespace pwsim::mca {

inline constexpr double kGravity = 9.80665;  ///< standard gravity g [m/s^2]
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegToRad = kPi / 180.0;

enum class Dof : int { kSurge = 0, kSway = 1, kHeave = 2, kRoll = 3, kPitch = 4, kYaw = 5 };
inline constexpr int kDofCount = 6;
inline constexpr std::array<Dof, kDofCount> kAllDofs{Dof::kSurge, Dof::kSway, Dof::kHeave,
                                                    Dof::kRoll,  Dof::kPitch, Dof::kYaw};

constexpr int Index(Dof dof) { return static_cast<int>(dof); }
constexpr bool IsRotational(Dof dof) { return Index(dof) >= Index(Dof::kRoll); }
/// "surge", "sway", "heave", "roll", "pitch", "yaw".
std::string_view DofName(Dof dof);
/// SI unit of a pose of this axis: "m" or "rad".
constexpr std::string_view DofUnit(Dof dof) { return IsRotational(dof) ? "rad" : "m"; }

/// One value per axis, indexed by Index(dof).
using DofArray = std::array<double, kDofCount>;

}  // namespace pwsim::mca
