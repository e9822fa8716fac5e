#include "mca/mechanism.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "engine/input_error.h"
#include "mca/platform.h"

namespace pwsim::mca {
namespace {

const std::filesystem::path kPlatforms = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/platforms";

constexpr std::size_t At(Dof dof) { return static_cast<std::size_t>(Index(dof)); }

// --- an independent model of the pose, built from Eigen's geometry module (not mca/mechanism.cc) ---

/// X_BP(x) = Rz(ψ)·Trans(s, w, h + z)·Ry(−θ)·Rx(φ) as an Eigen isometry.
Eigen::Isometry3d PlateFrame(const DofArray& x, double pivot_height) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.rotate(Eigen::AngleAxisd(x[At(Dof::kYaw)], Eigen::Vector3d::UnitZ()));
  t.translate(Eigen::Vector3d(x[At(Dof::kSurge)], x[At(Dof::kSway)], pivot_height + x[At(Dof::kHeave)]));
  t.rotate(Eigen::AngleAxisd(-x[At(Dof::kPitch)], Eigen::Vector3d::UnitY()));
  t.rotate(Eigen::AngleAxisd(x[At(Dof::kRoll)], Eigen::Vector3d::UnitX()));
  return t;
}

/// The frame after the serial stages: the pose with only the stage-driven axes, no pivot height.
Eigen::Isometry3d StageFrame(const Mechanism& m, const DofArray& x) {
  DofArray xs{};
  for (int i = 0; i < m.actuator_count(); ++i) {
    if (m.actuator(i).kind != ActuatorKind::kLeg) xs[At(m.actuator(i).dof)] = x[At(m.actuator(i).dof)];
  }
  return PlateFrame(xs, 0.0);
}

/// Leg i's length, direction and plate anchor from the pivot, all in B, from the independent model.
struct LegTruth {
  double length;
  Eigen::Vector3d u, r;
};
LegTruth Leg(const Mechanism& m, int i, const DofArray& x) {
  const Eigen::Isometry3d plate = PlateFrame(x, m.pivot_height());
  const Eigen::Vector3d p = plate * m.actuator(i).plate_anchor;
  const Eigen::Vector3d b = StageFrame(m, x) * m.actuator(i).base_anchor;
  return {(p - b).norm(), (p - b).normalized(), p - plate.translation()};
}

std::vector<std::pair<std::string, PlatformSpec>> Shipped() {
  return {{"pw4dof", ReadPlatformFile(kPlatforms / "pw4dof.yaml")},
          {"car2dof", ReadPlatformFile(kPlatforms / "car2dof.yaml")},
          {"stewart6dof", ReadPlatformFile(kPlatforms / "stewart6dof.yaml")}};
}

/// Random poses inside each axis box (free axes: ±π) that the mechanism reaches with `margin`.
std::vector<DofArray> ReachablePoses(const PlatformSpec& p, int count, double margin, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<DofArray> poses;
  for (int tries = 0; tries < 100 * count && static_cast<int>(poses.size()) < count; ++tries) {
    DofArray x{};
    for (Dof dof : kAllDofs) {
      if (!p.Has(dof)) continue;
      const double travel = std::isfinite(p.limits(dof).travel) ? p.limits(dof).travel : kPi;
      x[At(dof)] = travel * unit(rng);
    }
    if (p.mechanism.Reachability(x, margin).empty()) poses.push_back(x);
  }
  return poses;
}

// Tests that the shipped platforms load with the mechanisms their files describe, and that the
// built-in PW and car platforms are the files' mechanisms.
TEST(MechanismTest, ShippedPlatformsLoad) {
  for (const auto& [name, p] : Shipped()) {
    EXPECT_EQ(p.mechanism.Validate(), "") << name;
    for (Dof dof : kAllDofs) EXPECT_EQ(p.mechanism.Moves(dof), p.Has(dof)) << name << " " << DofName(dof);
  }
  const PlatformSpec pw = ReadPlatformFile(kPlatforms / "pw4dof.yaml");
  EXPECT_EQ(pw.mechanism.actuator_count(), 5);
  EXPECT_EQ(pw.mechanism.moved_axis_count(), 4);
  EXPECT_EQ(pw.mechanism.redundancy(), 1);
  EXPECT_EQ(ReadPlatformFile(kPlatforms / "stewart6dof.yaml").mechanism.actuator_count(), 6);
  const PlatformSpec car = ReadPlatformFile(kPlatforms / "car2dof.yaml");
  ASSERT_EQ(car.mechanism.actuator_count(), 2);
  EXPECT_TRUE(std::isinf(car.mechanism.actuator(car.mechanism.Find("yaw")).limits.max));

  for (const auto& [file, builtin] : {std::pair{pw, MakePw4DofPlatform()}, std::pair{car, MakeCar2DofPlatform()}}) {
    const Mechanism& a = file.mechanism;
    const Mechanism& b = builtin.mechanism;
    ASSERT_EQ(a.actuator_count(), b.actuator_count()) << file.name;
    EXPECT_DOUBLE_EQ(a.pivot_height(), b.pivot_height());
    EXPECT_DOUBLE_EQ(a.payload().mass, b.payload().mass);
    EXPECT_TRUE(a.payload().com_from_pivot.isApprox(b.payload().com_from_pivot));
    for (int i = 0; i < a.actuator_count(); ++i) {
      EXPECT_EQ(a.actuator(i).name, b.actuator(i).name);
      EXPECT_EQ(a.actuator(i).kind, b.actuator(i).kind);
      EXPECT_TRUE(a.actuator(i).base_anchor.isApprox(b.actuator(i).base_anchor));
      EXPECT_TRUE(a.actuator(i).plate_anchor.isApprox(b.actuator(i).plate_anchor));
      for (auto [x, y] : {std::pair{a.actuator(i).limits.min, b.actuator(i).limits.min},
                          std::pair{a.actuator(i).limits.max, b.actuator(i).limits.max}}) {
        if (std::isinf(x) || std::isinf(y)) {
          EXPECT_EQ(x, y) << a.actuator(i).name;
        } else {
          EXPECT_NEAR(x, y, 1e-12) << a.actuator(i).name;
        }
      }
      EXPECT_NEAR(a.actuator(i).limits.speed, b.actuator(i).limits.speed, 1e-12);
      EXPECT_NEAR(a.actuator(i).limits.accel, b.actuator(i).limits.accel, 1e-9);
      EXPECT_NEAR(a.actuator(i).limits.force, b.actuator(i).limits.force, 1e-9);
    }
  }
}

// Tests the closed-form IK against the independent Eigen model of the pose, and that every axis
// box is reachable one axis at a time on every shipped platform, with a 5 % stroke margin on the
// platforms with legs (the car's rail box is the seed's whole 1.2 m rail).
TEST(MechanismTest, InverseMatchesIndependentModelAndBoxesReachableAlone) {
  std::mt19937_64 rng(39);
  for (const auto& [name, p] : Shipped()) {
    const Mechanism& m = p.mechanism;
    for (const DofArray& x : ReachablePoses(p, 50, 0.0, rng)) {
      ActuatorVector q;
      ASSERT_TRUE(m.Inverse(x, &q));
      for (int i = 0; i < m.actuator_count(); ++i) {
        const double truth = m.actuator(i).kind == ActuatorKind::kLeg ? Leg(m, i, x).length : x[At(m.actuator(i).dof)];
        EXPECT_NEAR(q[i], truth, 1e-12) << name << " " << m.actuator(i).name;
      }
    }
    for (Dof dof : kAllDofs) {
      if (!p.Has(dof) || !std::isfinite(p.limits(dof).travel)) continue;
      for (double sign : {-1.0, 1.0}) {
        DofArray x{};
        x[At(dof)] = sign * p.limits(dof).travel;
        const double margin = name == "car2dof" ? 0.0 : 0.05;
        EXPECT_EQ(m.Reachability(x, margin), "") << name << " " << DofName(dof) << " " << sign;
      }
    }
  }
}

// Tests IK∘FK and FK∘IK to 1e-9 over random reachable poses of each shipped platform, FK
// starting from the neutral pose (not from the answer).
TEST(MechanismTest, ForwardInvertsInverse) {
  std::mt19937_64 rng(2024);
  for (const auto& [name, p] : Shipped()) {
    const Mechanism& m = p.mechanism;
    const std::vector<DofArray> poses = ReachablePoses(p, 300, 0.0, rng);
    ASSERT_GE(poses.size(), 100u) << name;
    int worst_iterations = 0;
    for (const DofArray& x : poses) {
      ActuatorVector q;
      ASSERT_TRUE(m.Inverse(x, &q));
      DofArray back{};
      const KinematicsStatus s = m.Forward(q, DofArray{}, &back);
      ASSERT_TRUE(s.ok) << name << ": " << s.reason;
      EXPECT_LE(s.residual, 1e-9);
      worst_iterations = std::max(worst_iterations, s.iterations);
      for (std::size_t k = 0; k < x.size(); ++k) EXPECT_NEAR(back[k], x[k], 1e-9) << name << " axis " << k;
      ActuatorVector q2;
      ASSERT_TRUE(m.Inverse(back, &q2));
      EXPECT_LE((q2 - q).cwiseAbs().maxCoeff(), 1e-9) << name;
    }
    EXPECT_LE(worst_iterations, 12) << name;  // Gauss–Newton converges quadratically
  }
}

// Tests that the least-squares FK of the redundant PW platform recovers the pose from leg
// lengths with a small inconsistency and reports it in `residual`.
TEST(MechanismTest, ForwardIsLeastSquaresForRedundantLegs) {
  const Mechanism m = ReadPlatformFile(kPlatforms / "pw4dof.yaml").mechanism;
  const DofArray x{0.0, 0.0, 0.03, 0.05, -0.08, 0.2};
  ActuatorVector q;
  ASSERT_TRUE(m.Inverse(x, &q));
  // the null vector of J_mᵀ on the legs: the plate's "twist" mode, no pose explains it
  ActuatorJacobian j;
  m.Jacobian(x, &j);
  Eigen::MatrixXd legs_on_moved(4, 3);
  for (int i = 0; i < 4; ++i) {
    legs_on_moved.row(i) << j(i + 1, Index(Dof::kHeave)), j(i + 1, Index(Dof::kRoll)), j(i + 1, Index(Dof::kPitch));
  }
  const Eigen::VectorXd twist = Eigen::FullPivLU<Eigen::MatrixXd>(legs_on_moved.transpose()).kernel().col(0).normalized();
  ActuatorVector measured = q;
  measured.tail<4>() += 1e-4 * twist;  // 0.1 mm inconsistency
  DofArray pose{};
  const KinematicsStatus s = m.Forward(measured, DofArray{}, &pose);
  ASSERT_TRUE(s.ok);
  EXPECT_NEAR(s.residual, 1e-4 * twist.cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_NE(std::string(s.reason).find("least squares"), std::string::npos);
  for (std::size_t k = 0; k < x.size(); ++k) EXPECT_NEAR(pose[k], x[k], 1e-7);
}

// Tests the analytic Jacobian against central finite differences of the IK on every shipped
// platform, and that the columns of axes a mechanism does not move are zero.
TEST(MechanismTest, JacobianMatchesFiniteDifferences) {
  std::mt19937_64 rng(7);
  const double h = 1e-6;
  for (const auto& [name, p] : Shipped()) {
    const Mechanism& m = p.mechanism;
    for (const DofArray& x : ReachablePoses(p, 30, 0.02, rng)) {
      ActuatorJacobian j;
      m.Jacobian(x, &j);
      ASSERT_EQ(j.rows(), m.actuator_count());
      for (Dof dof : kAllDofs) {
        if (!m.Moves(dof)) {
          EXPECT_EQ(j.col(Index(dof)).cwiseAbs().maxCoeff(), 0.0);
          continue;
        }
        DofArray plus = x, minus = x;
        plus[At(dof)] += h;
        minus[At(dof)] -= h;
        ActuatorVector qp, qm;
        ASSERT_TRUE(m.Inverse(plus, &qp) && m.Inverse(minus, &qm));
        const ActuatorVector fd = (qp - qm) / (2.0 * h);
        EXPECT_LE((fd - j.col(Index(dof))).cwiseAbs().maxCoeff(), 1e-8) << name << " " << DofName(dof);
      }
    }
  }
}

// Tests that unreachable poses are refused with a message naming the actuator and the numbers:
// the PW platform reaches ±15 deg of roll and of pitch one at a time but not together.
TEST(MechanismTest, UnreachablePosesAreRefusedWithNumbers) {
  const Mechanism m = ReadPlatformFile(kPlatforms / "pw4dof.yaml").mechanism;
  const double d = kDegToRad;
  EXPECT_EQ(m.Reachability({0, 0, 0, 15 * d, 0, 0}, 0.05), "");
  EXPECT_EQ(m.Reachability({0, 0, 0, 0, -15 * d, 0}, 0.05), "");
  const std::string both = m.Reachability({0, 0, 0, 15 * d, 15 * d, 0}, 0.0);
  EXPECT_NE(both.find("leg 'leg_front_left'"), std::string::npos) << both;  // the leg that rises most
  EXPECT_NE(both.find("outside its stroke [0.3700, 0.6300] m"), std::string::npos) << both;
  const std::string yaw = m.Reachability({0, 0, 0, 0, 0, 27 * d}, 0.05);
  EXPECT_NE(yaw.find("rotary 'yaw' at 27.0000 deg"), std::string::npos) << yaw;
  EXPECT_NE(yaw.find("5 % margin, i.e. [-25.2000, 25.2000] deg"), std::string::npos) << yaw;
  const std::string surge = m.Reachability({0.01, 0, 0, 0, 0, 0}, 0.0);
  EXPECT_NE(surge.find("does not move surge"), std::string::npos) << surge;
  const DofArray nan{0, 0, 0, 0, 0, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_NE(m.Reachability(nan, 0.0).find("not finite"), std::string::npos);
  ActuatorVector q;
  EXPECT_FALSE(m.Inverse(nan, &q));
}

// Tests that a singular pose is refused: one leg on heave whose direction turns horizontal,
// where dq/dz = u_z = 0, closed form (q = sqrt(0.5² + (h + z)²)).
TEST(MechanismTest, SingularPoseIsRefused) {
  Actuator leg;
  leg.name = "lift";
  leg.kind = ActuatorKind::kLeg;
  leg.base_anchor = Eigen::Vector3d(0.5, 0.0, 0.0);
  leg.plate_anchor = Eigen::Vector3d::Zero();
  leg.limits = {.min = 0.3, .max = 1.0, .speed = 1.0, .accel = 1.0, .force = 1000.0};
  DofMask heave{};
  heave[At(Dof::kHeave)] = true;
  const Mechanism m(0.3, {leg}, heave);
  EXPECT_EQ(m.Validate(), "");
  ActuatorJacobian j;
  m.Jacobian({0, 0, 0.1, 0, 0, 0}, &j);
  EXPECT_NEAR(j(0, Index(Dof::kHeave)), 0.4 / std::sqrt(0.25 + 0.16), 1e-12);
  const std::string why = m.Reachability({0, 0, -0.3, 0, 0, 0}, 0.0);
  EXPECT_NE(why.find("singular"), std::string::npos) << why;
  ActuatorVector f;
  EXPECT_FALSE(m.ActuatorForces({0, 0, -0.3, 0, 0, 0}, Wrench::Zero(), &f));
  DofArray pose{};
  ActuatorVector q(1);
  q << 0.5;  // the singular length
  EXPECT_FALSE(m.Forward(q, DofArray{0, 0, -0.3, 0, 0, 0}, &pose).ok);
}

// Tests the leg forces on the Stewart platform: the legs' own wrench Σ f_i (u_i, r_i × u_i),
// from the independent model, reproduces the wrench asked for, at random poses.
TEST(MechanismTest, StewartForcesReproduceTheWrench) {
  const PlatformSpec p = ReadPlatformFile(kPlatforms / "stewart6dof.yaml");
  const Mechanism& m = p.mechanism;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1000.0);
  for (const DofArray& x : ReachablePoses(p, 20, 0.05, rng)) {
    Wrench w;
    for (int k = 0; k < 6; ++k) w[k] = n(rng);
    ActuatorVector f;
    ASSERT_TRUE(m.ActuatorForces(x, w, &f));
    Wrench sum = Wrench::Zero();
    for (int i = 0; i < 6; ++i) {
      const LegTruth leg = Leg(m, i, x);
      sum.head<3>() += f[i] * leg.u;
      sum.tail<3>() += f[i] * leg.r.cross(leg.u);
    }
    EXPECT_LE((sum - w).cwiseAbs().maxCoeff(), 1e-6 * w.cwiseAbs().maxCoeff());
  }
}

// Tests the PW platform's leg forces: at neutral with the payload centred, the closed-form equal
// split W/(4 u_z) and no yaw torque; at tilted poses the forces do the payload's virtual work on
// every admissible motion (finite differences of the independent model), and the minimum-norm
// choice has no component along the legs' internal (twist) mode.
TEST(MechanismTest, PwLegForcesSplitTheWeight) {
  const Mechanism m = ReadPlatformFile(kPlatforms / "pw4dof.yaml").mechanism;
  const double weight = m.payload().mass * kGravity;
  ActuatorVector f;
  ASSERT_TRUE(m.ActuatorForces(DofArray{}, m.PayloadWrench(DofArray{}), &f));
  // the file's anchors: plate joints 0.60 − 0.05 m up, base joints 0.05 m up, 0.02 m further out
  // in x and in y: every leg leans in by the same angle, u_z = 0.5 / |(0.02, 0.02, 0.5)|
  const double u_z = 0.5 / std::hypot(0.02, 0.02, 0.5);
  EXPECT_NEAR(f[0], 0.0, 1e-9);  // the yaw stage
  for (int i = 1; i < 5; ++i) EXPECT_NEAR(f[i], weight / (4.0 * u_z), 1e-9) << m.actuator(i).name;

  const double h = 1e-6;
  for (const DofArray& x : {DofArray{0, 0, 0.05, 0.1, -0.05, 0.3}, DofArray{0, 0, -0.04, -0.12, 0.08, -0.2}}) {
    const Wrench w = m.PayloadWrench(x);
    ASSERT_TRUE(m.ActuatorForces(x, w, &f));
    for (Dof dof : {Dof::kHeave, Dof::kRoll, Dof::kPitch, Dof::kYaw}) {
      DofArray plus = x, minus = x;
      plus[At(dof)] += h;
      minus[At(dof)] -= h;
      double actuator_work = 0.0;
      for (int i = 0; i < 5; ++i) {
        const double dq = m.actuator(i).kind == ActuatorKind::kLeg ? Leg(m, i, plus).length - Leg(m, i, minus).length
                                                                    : plus[At(m.actuator(i).dof)] - minus[At(m.actuator(i).dof)];
        actuator_work += f[i] * dq;
      }
      // the wrench's work: F·δo + M·δθ, δθ from the rotation change R⁺ R⁻ᵀ
      const Eigen::Isometry3d a = PlateFrame(plus, m.pivot_height()), b = PlateFrame(minus, m.pivot_height());
      const Eigen::AngleAxisd turn(a.linear() * b.linear().transpose());
      const Eigen::Vector3d dtheta = turn.angle() * turn.axis();
      const double wrench_work = w.head<3>().dot(a.translation() - b.translation()) + w.tail<3>().dot(dtheta);
      EXPECT_NEAR(actuator_work, wrench_work, 1e-6 * weight * h) << DofName(dof);
    }
    ActuatorJacobian j;
    m.Jacobian(x, &j);
    Eigen::MatrixXd legs(4, 3);
    for (int i = 0; i < 4; ++i) legs.row(i) << j(i + 1, 2), j(i + 1, 3), j(i + 1, 4);
    const Eigen::VectorXd mode = Eigen::FullPivLU<Eigen::MatrixXd>(legs.transpose()).kernel().col(0);
    EXPECT_NEAR(mode.dot(f.tail<4>()) / mode.norm(), 0.0, 1e-9 * weight);
  }
}

// Tests the workspace figures: stroke use in closed form for a stage (25 of 28 deg) and a leg
// at pure heave; the PW box is not all reachable (heave, roll and pitch share the legs) while
// an axis-box mechanism reaches its whole box.
TEST(MechanismTest, WorkspaceShareAndStrokeUse) {
  const PlatformSpec pw = ReadPlatformFile(kPlatforms / "pw4dof.yaml");
  const Mechanism& m = pw.mechanism;
  ActuatorVector q, use;
  ASSERT_TRUE(m.Inverse({0, 0, 0.1, 0, 0, 0.4}, &q));
  m.StrokeUse(q, &use);
  EXPECT_NEAR(use[0], 0.4 / (28.0 * kDegToRad), 1e-12);
  // pure heave: every leg's plate end rises by 0.1 m, length sqrt(0.02² + 0.02² + 0.6²)
  const double neutral = std::hypot(0.02, 0.02, 0.5), up = std::hypot(0.02, 0.02, 0.6);
  EXPECT_NEAR(use[1], (up - neutral) / (0.63 - neutral), 1e-12);
  const double share = BoxShareReachable(pw, 0.0, 7);
  EXPECT_GT(share, 0.1);
  EXPECT_LT(share, 0.9);
  EXPECT_DOUBLE_EQ(BoxShareReachable(MakeCar2DofPlatform(), 0.0, 7), 1.0);
  const std::string text = DescribePlatform(pw, 0.05);
  EXPECT_NE(text.find("redundant by 1"), std::string::npos) << text;
  EXPECT_NE(text.find("leg_rear_right"), std::string::npos) << text;
}

// --- parsing ---

PlatformSpec ParseText(const std::string& text) {
  const YamlDocument doc = LoadYamlString(text, "inline.yaml");
  YamlMap root(doc.root, doc.file, "");
  PlatformSpec p = ParsePlatform(root);
  root.Finish();
  return p;
}

InputError ParseError(const std::string& text) {
  try {
    ParseText(text);
  } catch (const InputError& error) {
    return error;
  }
  ADD_FAILURE() << "expected an InputError for:\n" << text;
  return InputError("", 0, "", "", "");
}

const std::string kLegs =
    "name: t\n"                                                                    // 1
    "dofs:\n"                                                                      // 2
    "  heave: {travel_m: 0.05, speed_mps: 0.3, accel_mps2: 5}\n"                   // 3
    "  roll: {travel_deg: 5, speed_degps: 30, accel_degps2: 200}\n"                // 4
    "  pitch: {travel_deg: 5, speed_degps: 30, accel_degps2: 200}\n"               // 5
    "pivot_height_m: 0.5\n"                                                        // 6
    "leg_dofs: [heave, roll, pitch]\n"                                             // 7
    "actuators:\n"                                                                 // 8
    "  - {name: a, kind: leg, base_m: [0.3, 0.2, 0], plate_m: [0.3, 0.2, 0], stroke_m: [0.3, 0.7], "
    "speed_mps: 0.5, accel_mps2: 10, force_N: 1000}\n"                             // 9
    "  - {name: b, kind: leg, base_m: [0.3, -0.2, 0], plate_m: [0.3, -0.2, 0], stroke_m: [0.3, 0.7], "
    "speed_mps: 0.5, accel_mps2: 10, force_N: 1000}\n"                             // 10
    "  - {name: c, kind: leg, base_m: [-0.3, 0, 0], plate_m: [-0.3, 0, 0], stroke_m: [0.3, 0.7], "
    "speed_mps: 0.5, accel_mps2: 10, force_N: 1000}\n";                            // 11

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Tests that a valid three-leg file parses into the mechanism it describes.
TEST(MechanismTest, ParsesLegs) {
  const PlatformSpec p = ParseText(kLegs);
  ASSERT_EQ(p.mechanism.actuator_count(), 3);
  EXPECT_TRUE(p.mechanism.Moves(Dof::kRoll));
  EXPECT_FALSE(p.mechanism.Moves(Dof::kYaw));
  EXPECT_NEAR(p.mechanism.Neutral()[2], 0.5, 1e-15);
}

// Tests that file errors name the line, the field and what was expected.
TEST(MechanismTest, ParseErrorsNameLineAndField) {
  struct Case {
    std::string text;
    int line;
    std::string field;
    std::string expected_part;
  };
  const std::vector<Case> cases = {
      // neutral length 0.5 outside the stroke of leg b
      {Replace(kLegs, "plate_m: [0.3, -0.2, 0], stroke_m: [0.3, 0.7]", "plate_m: [0.3, -0.2, 0], stroke_m: [0.6, 0.7]"),
       10, "actuators[1].stroke_m", "neutral length 0.5 m"},
      {Replace(kLegs, "name: c, kind: leg", "name: c, kind: piston"), 11, "actuators[2].kind", "one of"},
      {Replace(kLegs, "name: b,", "name: a,"), 10, "actuators[1].name", "a name no other actuator has"},
      {Replace(kLegs, "leg_dofs: [heave, roll, pitch]", "leg_dofs: [heave, rol, pitch]"), 7, "leg_dofs[1]",
       "one of surge"},
      {Replace(kLegs, "stroke_m: [0.3, 0.7], speed_mps: 0.5, accel_mps2: 10, force_N: 1000}\n  - {name: c",
               "stroke_m: [0.3, 0.7], speed_mps: 0.5, accel_mps2: 10}\n  - {name: c"),
       10, "actuators[1].force_N", "required field"},
      // a yaw box but nothing moves yaw
      {Replace(kLegs, "pivot_height_m", "  yaw: {travel_deg: 5, speed_degps: 30, accel_degps2: 200}\npivot_height_m"),
       2, "dofs", "boxes only on axes the actuators move"},
      // three legs in a line cannot roll the plate independently of heave... (all on y = 0)
      {Replace(Replace(kLegs, "base_m: [0.3, 0.2, 0], plate_m: [0.3, 0.2, 0]", "base_m: [0.3, 0, 0], plate_m: [0.3, 0, 0]"),
               "base_m: [0.3, -0.2, 0], plate_m: [0.3, -0.2, 0]", "base_m: [0.1, 0, 0], plate_m: [0.1, 0, 0]"),
       8, "actuators", "a consistent mechanism"},
      {Replace(kLegs, "stroke_m: [0.3, 0.7], speed_mps: 0.5, accel_mps2: 10, force_N: 1000}\n  - {name: c",
               "stroke_m: [0.7, 0.3], speed_mps: 0.5, accel_mps2: 10, force_N: 1000}\n  - {name: c"),
       10, "actuators[1].stroke_m", "min < max"},
  };
  for (const Case& c : cases) {
    const InputError e = ParseError(c.text);
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_EQ(e.field(), c.field) << e.what();
    EXPECT_NE(e.expected().find(c.expected_part), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("inline.yaml"), std::string::npos) << e.what();
  }
}

// Tests that a file with axis boxes only still loads, with one rail or rotary stage per box
// whose coordinate is the pose entry and whose stroke is the box's travel.
TEST(MechanismTest, AxisBoxFilesKeepWorking) {
  const PlatformSpec p = ParseText(
      "name: old\n"
      "dofs:\n"
      "  surge: {travel_m: 0.6, speed_mps: 2.0, accel_mps2: 9}\n"
      "  pitch: {travel_deg: 10, speed_degps: 20, accel_degps2: 100}\n"
      "  yaw: {speed_degps: 20, accel_degps2: 100}\n");
  const Mechanism& m = p.mechanism;
  EXPECT_EQ(m.Validate(), "");
  ASSERT_EQ(m.actuator_count(), 3);
  EXPECT_EQ(m.actuator(0).kind, ActuatorKind::kRail);
  EXPECT_EQ(m.actuator(1).kind, ActuatorKind::kRotary);
  for (Dof dof : kAllDofs) EXPECT_EQ(m.Moves(dof), p.Has(dof));
  EXPECT_DOUBLE_EQ(m.actuator(0).limits.max, 0.6);
  EXPECT_DOUBLE_EQ(m.actuator(1).limits.min, -10.0 * kDegToRad);
  EXPECT_DOUBLE_EQ(m.actuator(1).limits.speed, 20.0 * kDegToRad);
  EXPECT_TRUE(std::isinf(m.actuator(2).limits.max));
  EXPECT_TRUE(std::isinf(m.actuator(0).limits.force));
  const DofArray x{0.3, 0.0, 0.0, 0.0, 0.1, 2.5};
  ActuatorVector q;
  ASSERT_TRUE(m.Inverse(x, &q));
  EXPECT_EQ(q[0], 0.3);
  EXPECT_EQ(q[1], 0.1);
  EXPECT_EQ(q[2], 2.5);
  EXPECT_EQ(m.Reachability(x, 0.0), "");
  EXPECT_NE(m.Reachability({0.7, 0, 0, 0, 0, 0}, 0.0).find("rail 'surge'"), std::string::npos);
  DofArray back{};
  EXPECT_TRUE(m.Forward(q, DofArray{}, &back).ok);
  EXPECT_EQ(back, x);
}

}  // namespace
}  // namespace pwsim::mca
