#pragma once
// A motion platform as a mechanism: the actuators that move its top P relative to its base B,
// actuator by actuator (prismatic legs between anchors, linear rails, rotary stages), with the
// inverse and forward kinematics, the Jacobian, the reachable-with-margin test and the static
// actuator forces. Frames and conventions: docs/notation.md; platforms: docs/platforms.md.
//
// Pose. The pose x of P relative to B is a DofArray {surge, sway, heave [m], roll, pitch,
// yaw [rad]} (mca/dof.h) with
//
//   X_BP(x) = Rz(ψ) · Trans(s, w, h₀ + z) · Ry(−θ) · Rx(φ)
//
// (s surge, w sway, z heave, φ roll left side up, θ pitch nose-up, ψ yaw turning left, h₀ the
// pivot height): the translations are in the frame the yaw has already turned, and P's origin
// (the "pivot") is the centre of rotation.
//
// Actuators.
//  - A rail or a rotary stage drives one pose axis directly: its coordinate q is that pose entry
//    (serial stages). The serial stages carry a frame F,
//      X_BF(x) = Rz(ψ_s) · Trans(s_s, w_s, z_s) · Ry(−θ_s) · Rx(φ_s),
//    where an axis with the subscript s is the pose entry when a stage drives it and 0 otherwise
//    (no pivot height: F is the floor of whatever the stages carry).
//  - A leg is a prismatic actuator between a base anchor a_F (in F) and a plate anchor a_P (in
//    P); its coordinate is its length, in closed form
//      q = | X_BP(x)·a_P − X_BF(x)·a_F |.
//    The legs together move the plate relative to F on `leg_axes`; the other axes of the plate
//    relative to F are held by a passive guide (e.g. the PW platform's central column blocks
//    surge, sway and yaw) or absent.
//  A mechanism moves the union of its stages' axes and its leg axes; the other pose entries stay 0.
//
// Jacobian. J = ∂q/∂x (actuator_count × 6), analytic: a stage's row is the unit vector of its
// axis; a leg's row is uᵀ·(∂p/∂x − ∂b/∂x) with p = X_BP·a_P, b = X_BF·a_F and u = (p − b)/q, where
//   ∂p/∂s = Rz e_x,  ∂p/∂w = Rz e_y,  ∂p/∂z = Rz e_z,  ∂p/∂ψ = e_z × p,
//   ∂p/∂φ = Rz Ry(−θ) Rx (e_x × a_P),
//   ∂p/∂θ = −Rz Ry(−θ) (e_y × Rx a_P),
// and the same for b with the stage-driven axes only. Columns of axes the mechanism does not
// move are 0.
//
// Forward kinematics. The stage-driven axes are read off their actuators; the leg axes solve
// q_legs(x) = q by Gauss–Newton from a guess (the last pose), x ← x − (J_LᵀJ_L)⁻¹ J_Lᵀ r with J_L
// the legs' rows restricted to the leg axes and a halving line search on |r|. With more legs
// than leg axes (redundant: the PW platform's four legs on heave, roll and pitch) that is the
// least-squares pose; `residual` tells how far the measured lengths are from consistent.
//
// Static forces. Virtual work on the admissible motions (the moved axes) gives
//   J_mᵀ f = T_mᵀ w,
// with w = (F, M) the wrench [N, N m] the actuators together must exert on the plate, at the
// pivot and in B (to hold a payload: its weight upwards and that weight's moment), T = ∂(ȯ, ω)/∂ẋ
// the map from pose rates to the pivot's velocity and P's angular velocity in B, and J_m, T_m
// restricted to the moved axes (a guide takes the rest). For the stage-free, non-redundant case
// (the Stewart platform) this is Σ f_i (u_i, r_i × u_i) = w. With more actuators than moved axes
// the choice is the minimum-norm one, f = J_m (J_mᵀ J_m)⁻¹ T_mᵀ w: on a rigid plate the true split
// depends on the legs' stiffness, which no file gives; minimum norm is what equal, stiff legs
// share. Leg force positive = pushing (extending); a stage's force/torque is along its axis.
//
// Reachability: every actuator inside its stroke less a margin, and not singular: the smallest
// singular value of J restricted to the moved axes at least kSingularTolerance (m per m or m per
// rad: the columns mix units, so the figure is per axis kind, and a value below 1e-3 means a
// millimetre of stroke moves the plate by a metre or a radian).
//
//   PlatformSpec pw = ReadPlatformFile("scenes/platforms/pw4dof.yaml");
//   ActuatorVector q;  pw.mechanism.Inverse(pose, &q);
//   if (std::string why = pw.mechanism.Reachability(pose, 0.05); !why.empty()) refuse(why);

#include <Eigen/Dense>

#include <array>
#include <string>
#include <vector>

#include "mca/dof.h"

namespace pwsim::mca {

inline constexpr int kMaxActuators = 8;
using ActuatorVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxActuators, 1>;    // no heap
using ActuatorJacobian = Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxActuators, 6>;  // dq_i/dpose_k
using Wrench = Eigen::Matrix<double, 6, 1>;  ///< (force [N], moment [N m]) at the pivot, in B
/// One flag per pose axis, indexed by Index(dof).
using DofMask = std::array<bool, kDofCount>;

enum class ActuatorKind { kLeg, kRail, kRotary };
/// "leg", "rail", "rotary".
const char* ActuatorKindName(ActuatorKind kind);

struct ActuatorLimits {            // in the actuator's own coordinate
  double min{0.0}, max{0.0};       // stroke [m] (leg length, rail position) or [rad] (stage angle); rotary may be ±inf
  double speed{0.0};               // [m/s | rad/s]
  double accel{0.0};               // [m/s² | rad/s²]
  double force{0.0};               // [N | N m]
};

struct Actuator {
  std::string name;                // "leg_front_left", "yaw", "rail" ...
  ActuatorKind kind{ActuatorKind::kLeg};
  Dof dof{Dof::kHeave};            // rail/rotary: the pose axis it drives (its coordinate == that pose entry)
  Eigen::Vector3d base_anchor{0, 0, 0};   // leg: in the frame below the legs (after the serial stages) [m]
  Eigen::Vector3d plate_anchor{0, 0, 0};  // leg: in P [m]
  ActuatorLimits limits;

  /// "m" for legs and rails, "rad" for rotary stages (the SI unit of q).
  const char* unit() const { return kind == ActuatorKind::kRotary ? "rad" : "m"; }
};

struct KinematicsStatus { bool ok{false}; int iterations{0}; double residual{0.0}; const char* reason{""}; };

/// What the platform carries, for the leg forces: a rigid mass at a point of P.
struct Payload {
  double mass{0.0};                          ///< [kg]
  Eigen::Vector3d com_from_pivot{0, 0, 0};   ///< p_PC: centre of mass in P [m]
};

class Mechanism {                  // value type; built from a platform file or from axis boxes
 public:
  /// Below this smallest singular value of J on the moved axes a pose is singular [m/m | m/rad].
  static constexpr double kSingularTolerance = 1e-3;
  /// Forward(): the iteration stops when the step is below this [m | rad].
  static constexpr double kStepTolerance = 1e-13;
  static constexpr int kMaxIterations = 50;

  /// No actuators: moves nothing.
  Mechanism() = default;
  /// `leg_axes`: the axes the legs move the plate on relative to F (all false without legs).
  /// Not checked here: call Validate().
  Mechanism(double pivot_height_m, std::vector<Actuator> actuators, DofMask leg_axes,
            Payload payload = {});

  int actuator_count() const;
  const Actuator& actuator(int i) const;
  bool Moves(Dof dof) const;                     // the pose axes this mechanism can move (others stay 0)
  double pivot_height() const;
  // IK: pose -> actuator positions. false (q untouched) when not computable. No allocation.
  // (Entries of axes the mechanism does not move are read as 0; a non-finite moved entry or a leg
  // of zero length is not computable.)
  bool Inverse(const DofArray& pose, ActuatorVector* q) const;
  // FK: actuator positions -> pose, Newton/Gauss-Newton from `guess` (the last pose). No allocation.
  KinematicsStatus Forward(const ActuatorVector& q, const DofArray& guess, DofArray* pose) const;
  // dq/dpose at `pose` (actuator_count x 6; columns of axes the mechanism does not move are 0). No allocation.
  void Jacobian(const DofArray& pose, ActuatorJacobian* jacobian) const;
  // "" when reachable: every actuator within [min + margin·(max−min), max − margin·(max−min)] and not
  // singular; else a message naming the actuator (or singularity) and the numbers. (allocates: not per tick)
  std::string Reachability(const DofArray& pose, double margin_fraction) const;
  // Actuator forces f that balance `wrench_P` (force [N] and moment [N m] on the plate at the pivot, in B)
  // via Jᵀ f = wrench; redundant mechanisms: minimum-norm (the distribution is reported). No allocation.
  // (Precisely: J_mᵀ f = T_mᵀ w on the moved axes, see the header comment; w is what the actuators
  // must exert on the plate.) false (f untouched) when singular.
  bool ActuatorForces(const DofArray& pose, const Eigen::Matrix<double, 6, 1>& wrench, ActuatorVector* f) const;

  // --- additions ---
  const std::vector<Actuator>& actuators() const { return actuators_; }
  /// The axes the legs move (relative to F); the rest of Moves() is stage-driven.
  const DofMask& leg_axes() const { return leg_axes_; }
  /// Every axis Moves() is true for.
  DofMask moved_axes() const;
  int moved_axis_count() const;
  /// actuator_count() − moved_axis_count(): how many actuators the statics has to spare.
  int redundancy() const { return actuator_count() - moved_axis_count(); }
  const Payload& payload() const { return payload_; }
  /// Empty when consistent (at most kMaxActuators, positive finite limits, each stage on its own
  /// axis not shared with the legs, legs of positive length, neutral inside every stroke, J of
  /// full rank on the moved axes at neutral), else which actuator or field is wrong and why.
  std::string Validate() const;
  /// q at the neutral pose (all zeros).
  ActuatorVector Neutral() const;
  /// Stroke use of each actuator at positions q: (q − q₀)/(max − q₀) above neutral q₀,
  /// (q₀ − q)/(q₀ − min) below; 0 at neutral, 1 at the end of the stroke, > 1 beyond; 0 on a
  /// free (infinite) side. No allocation.
  void StrokeUse(const ActuatorVector& q, ActuatorVector* use) const;
  /// Smallest singular value of J restricted to the moved axes (0 when nothing moves).
  double SmallestSingularValue(const DofArray& pose) const;
  /// Index of the actuator named `name`, −1 if none.
  int Find(const std::string& name) const;
  /// T_mᵀ w: the generalised force on each pose axis of wrench w (0 on axes not moved). No allocation.
  Eigen::Matrix<double, 6, 1> GeneralizedForce(const DofArray& pose, const Wrench& wrench) const;
  /// The wrench the actuators must exert to hold the payload still at `pose`: (m g e_z, p_C × m g e_z)
  /// with p_C = R_BP·com_from_pivot. No allocation.
  Wrench PayloadWrench(const DofArray& pose) const;
  /// Leg i's unit vector u (base → plate anchor, in B) and plate anchor from the pivot r (in B) at
  /// `pose`; false unless actuator i is a leg of positive length. No allocation.
  bool LegGeometry(int i, const DofArray& pose, Eigen::Vector3d* u, Eigen::Vector3d* r) const;
  /// Base and plate anchors of leg i in B at `pose` (for drawings). No allocation.
  bool LegEndpoints(int i, const DofArray& pose, Eigen::Vector3d* base_B, Eigen::Vector3d* plate_B) const;

 private:
  std::vector<Actuator> actuators_;
  double pivot_height_{0.0};
  DofMask leg_axes_{};
  DofMask stage_axes_{};          ///< axes a rail or rotary stage drives
  std::array<int, kDofCount> stage_of_axis_{-1, -1, -1, -1, -1, -1};
  Payload payload_;
  ActuatorVector neutral_;        ///< q at the neutral pose (0 for a leg of zero length)
};

}  // namespace pwsim::mca
