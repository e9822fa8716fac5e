// The simulated CiA 402 drives of any mechanism, driven through CANopen frames on a fake clock
// (4 ms drive cycles, no sleeps): boot-up, the start-up, CSP following, the limits as measured
// from the simulated actuator states, following-error trips, quick stop on master loss,
// restarts, and the car kept on its Lagrange plant. Truth: closed-form leg lengths (written
// here, not the mechanism's code), the seed-001 plant stepped directly, the limits themselves.
#include "hardware/simulated_drives.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hardware/canopen.h"
#include "mca/platform.h"

namespace pwsim::hw {
namespace {

using canopen::DriveState;
using canopen::NmtState;
using mca::ActuatorKind;
using mca::Dof;
using mca::DofArray;

const std::filesystem::path kPlatforms = std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/platforms";
constexpr double kCycleS = 0.004;
constexpr std::int64_t kCycleNs = 4'000'000;

// --- the shipped PW platform: a yaw stage carrying a plate on four legs ---------------------
mca::Mechanism Pw4Dof() {
  const mca::PlatformSpec spec = mca::ReadPlatformFile(kPlatforms / "pw4dof.yaml");
  EXPECT_EQ(spec.mechanism.actuator_count(), 5);
  EXPECT_EQ(spec.mechanism.actuator(0).kind, ActuatorKind::kRotary);
  EXPECT_GT(spec.mechanism.payload().mass, 0.0);
  return spec.mechanism;
}

/// Leg vector in closed form: the yaw stage turns base and plate alike, so, yaw aside,
/// d = (0, 0, h0 + z) + Ry(−θ) Rx(φ) a_P − a_F and q = |d|.
Eigen::Vector3d LegVector(double pivot_height, const mca::Actuator& leg, const DofArray& x) {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(-x[mca::Index(Dof::kPitch)], Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(x[mca::Index(Dof::kRoll)], Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const Eigen::Vector3d t(0.0, 0.0, pivot_height + x[mca::Index(Dof::kHeave)]);
  return t + r * leg.plate_anchor - leg.base_anchor;
}
double LegLength(const mca::Mechanism& m, int i, const DofArray& x) {
  return LegVector(m.pivot_height(), m.actuator(i), x).norm();
}

// --- a scripted CANopen master: the protocol's own frames, nothing of the session -----------
struct Bench {
  SimulatedDrives drives;
  std::int64_t now_ns = 1'000'000'000;
  std::uint8_t sync_counter = 0;
  std::vector<CanFrame> rx;  // what the drives sent this step
  std::array<int, 128> boot_ups{};
  std::array<canopen::CspStatus, 128> status{};
  std::array<int, 128> tpdos{};
  std::array<std::vector<std::uint16_t>, 128> emcy;
  std::array<NmtState, 128> heartbeat{};

  explicit Bench(const mca::Mechanism& m, DriveSimConfig config = {}) : drives(m, config) {}
  Bench() = default;

  int n() const { return drives.axis_count(); }
  std::uint8_t node(int i) const { return drives.node(i); }

  void Collect() {
    for (const CanFrame& f : rx) {
      std::uint8_t node_id = 0;
      switch (canopen::Classify(f, &node_id)) {
        case canopen::FrameKind::kHeartbeat: {
          NmtState s{};
          ASSERT_TRUE(canopen::DecodeHeartbeat(f, &node_id, &s));
          heartbeat[node_id] = s;
          if (s == NmtState::kBootUp) ++boot_ups[node_id];
          break;
        }
        case canopen::FrameKind::kTpdo1: {
          canopen::CspStatus s;
          ASSERT_TRUE(canopen::DecodeCspStatus(f, &node_id, &s));
          status[node_id] = s;
          ++tpdos[node_id];
          break;
        }
        case canopen::FrameKind::kEmcy: {
          canopen::Emcy e;
          ASSERT_TRUE(canopen::DecodeEmcy(f, &node_id, &e));
          emcy[node_id].push_back(e.code);
          break;
        }
        default:
          break;
      }
    }
    rx.clear();
  }
  void Send(const CanFrame& f) {
    drives.OnFrame(f, now_ns, &rx);
    Collect();
  }
  void Poll() {
    drives.Poll(now_ns, &rx);
    Collect();
  }
  /// One drive cycle: RPDO1 per node, SYNC, then the drives' time-based duties.
  void Cycle(const std::array<std::uint16_t, 8>& cw, const std::array<std::int32_t, 8>& target) {
    for (int i = 0; i < n(); ++i) Send(canopen::EncodeCspCommand(node(i), {cw[i], target[i]}));
    sync_counter = static_cast<std::uint8_t>(sync_counter % 240 + 1);
    Send(canopen::EncodeSync(sync_counter));
    Poll();
    now_ns += kCycleNs;
  }
  DriveState State(int i) const { return canopen::DecodeStatusword(status[node(i)].statusword); }
  std::int32_t Actual(int i) const { return status[node(i)].position_actual; }
  /// The start-up a master runs: NMT reset-communication, the boot-ups, NMT start, then the
  /// controlword walk (0x06, 0x07, 0x0F; from quick stop, disable voltage first) holding the
  /// actual position. Returns the cycles the walk took, or -1.
  int StartUp() {
    Send(canopen::EncodeNmt(canopen::NmtCommand::kResetComm, 0));
    Send(canopen::EncodeNmt(canopen::NmtCommand::kStart, 0));
    // What the master knows of each drive is its last TPDO1 (none: statusword 0).
    for (int k = 0; k < 50; ++k) {
      std::array<std::uint16_t, 8> cw{};
      std::array<std::int32_t, 8> hold{};
      bool all = k > 0;
      for (int i = 0; i < n(); ++i) {
        const DriveState s = State(i);
        cw[i] = canopen::ControlwordTowardEnabled(s);
        all = all && s == DriveState::kOperationEnabled;
        hold[i] = Actual(i);
      }
      if (all) return k;
      Cycle(cw, hold);
    }
    return -1;
  }
  /// Streams IK targets of poses `path(t)` for `seconds`, with enable-operation controlwords.
  template <class Path>
  void Follow(double seconds, const Path& path) {
    const int cycles = static_cast<int>(std::lround(seconds / kCycleS));
    for (int k = 1; k <= cycles; ++k) {
      mca::ActuatorVector q;
      ASSERT_TRUE(drives.mechanism().Inverse(path(k * kCycleS), &q));
      std::array<std::uint16_t, 8> cw{};
      std::array<std::int32_t, 8> target{};
      for (int i = 0; i < n(); ++i) {
        cw[i] = canopen::controlword::kEnableOperation;
        target[i] = static_cast<std::int32_t>(std::lround(q(i) * 1e6));
      }
      Cycle(cw, target);
    }
  }
};

/// A smooth ramp from 0 to 1 over `duration` (cosine), then 1.
double Ramp(double t, double duration) {
  return t >= duration ? 1.0 : 0.5 * (1.0 - std::cos(mca::kPi * t / duration));
}

DofArray PoseOf(double heave, double roll_deg, double pitch_deg, double yaw_deg) {
  DofArray x{};
  x[mca::Index(Dof::kHeave)] = heave;
  x[mca::Index(Dof::kRoll)] = roll_deg * mca::kDegToRad;
  x[mca::Index(Dof::kPitch)] = pitch_deg * mca::kDegToRad;
  x[mca::Index(Dof::kYaw)] = yaw_deg * mca::kDegToRad;
  return x;
}

DofArray Scaled(const DofArray& x, double s) {
  DofArray out{};
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = s * x[k];
  return out;
}

// --- the servo alone -----------------------------------------------------------------------

TEST(ActuatorServo, TheForceLimitLeavesTheAccelerationTheLoadAllows) {
  const mca::ActuatorLimits lim{.min = 0.3, .max = 0.5, .speed = 0.25, .accel = 5.0, .force = 1000.0};
  ActuatorServo s(lim, 20.0);
  EXPECT_DOUBLE_EQ(s.available_accel(), 5.0);  // (1000 − 0)/20 = 50 > 5
  s.SetLoad(-950.0, 25.0);
  EXPECT_DOUBLE_EQ(s.available_accel(), (1000.0 - 950.0) / 25.0);  // 2 m/s²
  s.SetLoad(2000.0, 25.0);
  EXPECT_DOUBLE_EQ(s.available_accel(), 0.05 * 5.0);  // overloaded: the floor
  EXPECT_NEAR(s.kp() * s.velocity_time_constant(), 0.25, 1e-15);  // critically damped cascade
}

TEST(ActuatorServo, FollowsARampWithoutLagAndNeverLeavesItsLimitsWhateverTheTarget) {
  const mca::ActuatorLimits lim{.min = 0.3, .max = 0.5, .speed = 0.25, .accel = 5.0, .force = 1000.0};
  ActuatorServo s(lim, 20.0);
  ServoState start;
  start.q = 0.35;
  s.set_state(start);
  s.ResetTarget(0.35);
  AxisEnvelope env;
  // A ramp at 0.1 m/s (inside the limits): after the transient the error is zero (the header's
  // T_v ë + ė + K_p e = T_v r̈ with r̈ = 0).
  double target = 0.35;
  for (int k = 0; k < 250; ++k) {
    target += 0.1 * kCycleS;
    s.Advance(kCycleS, target, true, &env);
  }
  EXPECT_NEAR(s.state().q, target, 1e-6);
  EXPECT_NEAR(s.state().v, 0.1, 1e-6);
  // Targets far outside the stroke and jumping faster than any limit, back and forth.
  std::uint32_t lcg = 12345;
  for (int k = 0; k < 2000; ++k) {
    lcg = lcg * 1664525U + 1013904223U;
    const double u = static_cast<double>(lcg >> 8) / static_cast<double>(1U << 24);
    if (k % 50 == 0) target = 0.1 + 0.6 * u;  // anywhere in [0.1, 0.7]
    s.Advance(kCycleS, target, true, &env);
  }
  EXPECT_GE(env.q_min, lim.min - 1e-12);
  EXPECT_LE(env.q_max, lim.max + 1e-12);
  EXPECT_LE(env.speed, lim.speed * (1 + 1e-12));
  EXPECT_LE(env.accel, lim.accel * (1 + 1e-12));
  EXPECT_LE(env.effort, lim.force * (1 + 1e-12));
  EXPECT_GT(env.q_max, lim.max - 1e-3);  // it did reach the ends
  EXPECT_LT(env.q_min, lim.min + 1e-3);
  EXPECT_GT(env.speed, 0.99 * lim.speed);
  EXPECT_EQ(env.samples, (250 + 2000) * 8);  // every 0.5 ms substep sampled
}

// --- the mechanism's drives ----------------------------------------------------------------

TEST(SimulatedDrives, FiveNodesBootEnableAndFollowCspToThePoseTheirIkGives) {
  Bench b(Pw4Dof());
  ASSERT_EQ(b.n(), 5);
  EXPECT_FALSE(b.drives.uses_car_plant());
  b.Poll();  // power-on: boot-up from every node
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(b.node(i), 1 + i);
    EXPECT_EQ(b.boot_ups[1 + i], 1) << "node " << 1 + i;
  }
  EXPECT_EQ(b.boot_ups[6], 0);
  const int walk = b.StartUp();
  ASSERT_GE(walk, 0);
  EXPECT_LE(walk, 5);
  EXPECT_TRUE(b.drives.all_enabled());
  for (int i = 0; i < 5; ++i) EXPECT_EQ(b.boot_ups[1 + i], 2);  // NMT reset-comm answered

  const DofArray goal = PoseOf(0.02, 4.0, -3.0, 10.0);
  ASSERT_EQ(b.drives.mechanism().Reachability(goal, 0.05), "");
  b.Follow(2.0, [&](double t) { return Scaled(goal, Ramp(t, 1.5)); });
  // Every leg's reported position is its closed-form length at the goal; the yaw its angle.
  const mca::Mechanism& m = b.drives.mechanism();
  EXPECT_NEAR(b.Actual(0) / 1e6, goal[mca::Index(Dof::kYaw)], 2e-6);
  for (int i = 1; i < 5; ++i) {
    EXPECT_NEAR(b.Actual(i) / 1e6, LegLength(m, i, goal), 2e-6) << m.actuator(i).name;
    EXPECT_EQ(b.State(i), DriveState::kOperationEnabled);
    EXPECT_TRUE(b.emcy[1 + i].empty());
  }
  // The plate pose measured by forward kinematics is the commanded one.
  ASSERT_TRUE(b.drives.fk_status().ok);
  EXPECT_EQ(b.drives.fk_failures(), 0u);
  for (Dof d : mca::kAllDofs)
    EXPECT_NEAR(b.drives.measured_pose()[mca::Index(d)], goal[mca::Index(d)], 2e-6) << mca::DofName(d);
  // Honest measurements: nothing exceeded, the legs used part of their stroke, they carry the
  // payload (pushing: positive), and all of it between them.
  EXPECT_FALSE(b.drives.any_limit_exceeded());
  for (int i = 1; i < 5; ++i) {
    const ActuatorMeasurement meas = b.drives.measurement(i);
    EXPECT_GT(meas.stroke_use, 0.05);
    EXPECT_LT(meas.stroke_use, 1.0);
    EXPECT_GT(meas.peak_speed, 0.0);
    EXPECT_GT(b.drives.load(i), 0.0);
  }
  // Vertical balance (closed form): the legs' vertical components carry m g (the yaw stage
  // turns about z and carries none of it), at the pose the loads were computed for.
  double vertical = 0.0;
  for (int i = 1; i < 5; ++i) {
    const Eigen::Vector3d d = LegVector(m.pivot_height(), m.actuator(i), b.drives.measured_pose());
    vertical += b.drives.load(i) * d.z() / d.norm();
  }
  EXPECT_NEAR(vertical, m.payload().mass * mca::kGravity, 1e-6);
}

TEST(SimulatedDrives, ATargetBeyondALegsStrokeIsNeverReachedAndTripsTheFollowingError) {
  Bench b(Pw4Dof());
  b.Poll();
  ASSERT_GE(b.StartUp(), 0);
  const mca::ActuatorLimits lim = b.drives.mechanism().actuator(2).limits;
  // Node 3 (leg 2) is sent toward 0.1 m beyond its stroke at 80 % of its speed; the rest hold.
  std::array<std::int32_t, 8> target{};
  for (int i = 0; i < 5; ++i) target[i] = b.Actual(i);
  double leg = b.Actual(2) / 1e6;
  std::array<std::uint16_t, 8> cw{};
  cw.fill(canopen::controlword::kEnableOperation);
  for (int k = 0; k < 500 && b.emcy[3].empty(); ++k) {
    leg = std::min(leg + 0.8 * lim.speed * kCycleS, lim.max + 0.1);
    target[2] = static_cast<std::int32_t>(std::lround(leg * 1e6));
    b.Cycle(cw, target);
  }
  ASSERT_EQ(b.emcy[3].size(), 1u);
  EXPECT_EQ(b.emcy[3][0], 0x8611);  // following error
  EXPECT_EQ(b.drives.drive_state(2), DriveState::kFault);
  for (int node : {1, 2, 4, 5}) EXPECT_TRUE(b.emcy[node].empty()) << node;
  for (int k = 0; k < 100; ++k) b.Cycle(cw, target);  // the fault reaction ends at rest
  const ActuatorMeasurement m = b.drives.measurement(2);
  EXPECT_FALSE(m.stroke_exceeded);
  EXPECT_LE(m.q_max, lim.max + 1e-12);
  EXPECT_GT(m.q_max, lim.max - 0.025);  // it went as far as the window let it
  EXPECT_FALSE(m.speed_exceeded);
  EXPECT_FALSE(b.drives.any_limit_exceeded());
  EXPECT_NEAR(b.drives.velocity(2), 0.0, 1e-9);
}

TEST(SimulatedDrives, ATargetFasterThanALegsSpeedIsFollowedAtTheLimitAndTrips) {
  Bench b(Pw4Dof());
  b.Poll();
  ASSERT_GE(b.StartUp(), 0);
  const mca::ActuatorLimits lim = b.drives.mechanism().actuator(4).limits;
  std::array<std::int32_t, 8> target{};
  for (int i = 0; i < 5; ++i) target[i] = b.Actual(i);
  double leg = b.Actual(4) / 1e6;
  std::array<std::uint16_t, 8> cw{};
  cw.fill(canopen::controlword::kEnableOperation);
  int cycles = 0;
  for (; cycles < 500 && b.emcy[5].empty(); ++cycles) {
    ASSERT_GT(leg, lim.min + 0.03);
    leg -= 2.0 * lim.speed * kCycleS;  // twice the speed limit, downwards, inside the stroke
    target[4] = static_cast<std::int32_t>(std::lround(leg * 1e6));
    b.Cycle(cw, target);
  }
  ASSERT_EQ(b.emcy[5].size(), 1u);
  EXPECT_EQ(b.emcy[5][0], 0x8611);
  // Closed form: the target runs at 2v from rest, the leg accelerates at a (the force limit
  // leaves all of it: checked) to v, the gap 2v t − a t²/2 until t_a = v/a (then 1.5 v²/a),
  // growing at v after that, until it passes the window w.
  const double v = lim.speed, a = lim.accel, w = 0.02, t_a = v / a;
  const double load = std::abs(b.drives.load(4));
  ASSERT_LT(load + (b.drives.config().leg_mass_kg + load / mca::kGravity) * a, lim.force);
  const double t_trip = 1.5 * v * v / a > w ? (2.0 * v - std::sqrt(4.0 * v * v - 2.0 * a * w)) / a
                                            : t_a + (w - 1.5 * v * v / a) / v;
  EXPECT_NEAR(cycles * kCycleS, t_trip, 2.0 * kCycleS);
  const ActuatorMeasurement m = b.drives.measurement(4);
  EXPECT_LE(m.peak_speed, lim.speed * (1 + 1e-12));
  EXPECT_GT(m.peak_speed, 0.99 * std::min(lim.speed, lim.accel * t_trip));
  EXPECT_LE(m.peak_accel, lim.accel * (1 + 1e-12));
  EXPECT_FALSE(m.speed_exceeded);
  EXPECT_FALSE(m.stroke_exceeded);
}

TEST(SimulatedDrives, MasterHeartbeatLossQuickStopsEveryNode) {
  Bench b(Pw4Dof());
  b.Poll();
  ASSERT_GE(b.StartUp(), 0);
  // 0.8 Hz, inside every limit: yaw peaks at 6° · 2π · 0.8 Hz = 30 °/s (of 40).
  const DofArray amplitude = PoseOf(0.015, 2.0, 2.0, 6.0);
  b.Follow(0.6, [&](double t) { return Scaled(amplitude, 1.0 - std::cos(2.0 * mca::kPi * 0.8 * t)); });
  double moving = 0.0;
  for (int i = 0; i < 5; ++i) moving = std::max(moving, std::abs(b.drives.velocity(i)));
  ASSERT_GT(moving, 0.05);
  // The master falls silent: the drives run on their own clock.
  for (int k = 0; k < 500; ++k) {
    b.now_ns += kCycleNs;
    b.Poll();
  }
  EXPECT_TRUE(b.drives.master_lost());
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(b.drives.drive_state(i), DriveState::kQuickStopActive) << "node " << 1 + i;
    EXPECT_NEAR(b.drives.velocity(i), 0.0, 1e-9) << "node " << 1 + i;
  }
  EXPECT_FALSE(b.drives.any_limit_exceeded());
}

TEST(SimulatedDrives, AfterALostMasterTheStartUpWorksAgainAndBootUpsAreSeenAgain) {
  Bench b(Pw4Dof());
  b.Poll();
  ASSERT_GE(b.StartUp(), 0);
  ASSERT_EQ(b.drives.mechanism().Reachability(PoseOf(0.02, 3.0, 0.0, 5.0), 0.05), "");
  b.Follow(0.5, [&](double t) { return Scaled(PoseOf(0.02, 3.0, 0.0, 5.0), Ramp(t, 0.5)); });
  for (int k = 0; k < 200; ++k) {  // master gone for 0.8 s
    b.now_ns += kCycleNs;
    b.Poll();
  }
  ASSERT_TRUE(b.drives.master_lost());
  // A (new) master: streaming enable-operation alone moves nothing out of quick stop...
  std::array<std::uint16_t, 8> cw{};
  cw.fill(canopen::controlword::kEnableOperation);
  std::array<std::int32_t, 8> hold{};
  for (int i = 0; i < 5; ++i) hold[i] = b.Actual(i);
  for (int k = 0; k < 10; ++k) b.Cycle(cw, hold);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(b.drives.drive_state(i), DriveState::kQuickStopActive);
  // ...its start-up does: boot-ups again, then every drive enabled, and it follows.
  ASSERT_GE(b.StartUp(), 0);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(b.boot_ups[1 + i], 3) << "node " << 1 + i;  // power-on, 2 resets
  EXPECT_FALSE(b.drives.master_lost());
  EXPECT_TRUE(b.drives.all_enabled());
  const DofArray from = b.drives.measured_pose();
  const DofArray goal = PoseOf(-0.02, -3.0, 2.0, -5.0);
  ASSERT_EQ(b.drives.mechanism().Reachability(goal, 0.05), "");
  b.Follow(1.5, [&](double t) {
    DofArray x{};
    for (std::size_t k = 0; k < x.size(); ++k) x[k] = from[k] + Ramp(t, 1.0) * (goal[k] - from[k]);
    return x;
  });
  for (Dof d : mca::kAllDofs)
    EXPECT_NEAR(b.drives.measured_pose()[mca::Index(d)], goal[mca::Index(d)], 2e-6) << mca::DofName(d);
}

TEST(SimulatedDrives, ARestartedSimulatorBootsAgainAndAcceptsTheStartUp) {
  const mca::Mechanism m = Pw4Dof();
  Bench first(m);
  first.Poll();
  ASSERT_GE(first.StartUp(), 0);
  first.Follow(0.3, [&](double t) { return Scaled(PoseOf(0.02, 0, 0, 0), Ramp(t, 0.3)); });
  // The process is restarted: a new simulator on the same bus, the master still streaming.
  Bench again(m);
  again.now_ns = first.now_ns;
  again.Poll();
  for (int i = 0; i < 5; ++i) EXPECT_EQ(again.boot_ups[1 + i], 1);
  std::array<std::uint16_t, 8> cw{};
  cw.fill(canopen::controlword::kEnableOperation);
  std::array<std::int32_t, 8> stale{};
  for (int i = 0; i < 5; ++i) stale[i] = first.Actual(i);
  for (int k = 0; k < 30; ++k) again.Cycle(cw, stale);  // pre-operational: no PDO taken
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(again.tpdos[1 + i], 0);
    EXPECT_EQ(again.drives.drive_state(i), DriveState::kSwitchOnDisabled);
    EXPECT_EQ(again.heartbeat[1 + i], NmtState::kPreOperational);  // its heartbeat says so
  }
  ASSERT_GE(again.StartUp(), 0);
  EXPECT_TRUE(again.drives.all_enabled());
  again.Follow(0.5, [&](double t) { return Scaled(PoseOf(0.0, 2.0, 2.0, 0.0), Ramp(t, 0.4)); });
  EXPECT_NEAR(again.drives.measured_pose()[mca::Index(Dof::kRoll)], 2.0 * mca::kDegToRad, 2e-6);
}

TEST(SimulatedDrives, ReportsWhatTheActuatorsDidInWordsAndJson) {
  Bench b(Pw4Dof());
  b.Poll();
  ASSERT_GE(b.StartUp(), 0);
  const DofArray goal = PoseOf(0.02, 0.0, 3.0, -8.0);
  b.Follow(1.0, [&](double t) { return Scaled(goal, Ramp(t, 0.8)); });
  const nlohmann::json j = nlohmann::json::parse("{\n" + DrivesReportJsonMembers(b.drives) + "\n}");
  EXPECT_EQ(j["plant"], "actuator-servos");
  for (const char* what : {"stroke", "speed", "acceleration", "force"}) EXPECT_EQ(j["limits_exceeded"][what], false);
  ASSERT_EQ(j["actuators"].size(), 5u);
  for (int i = 0; i < 5; ++i) {
    const auto& a = j["actuators"][i];
    const ActuatorMeasurement m = b.drives.measurement(i);
    EXPECT_EQ(a["node"], 1 + i);
    EXPECT_EQ(a["name"], b.drives.mechanism().actuator(i).name);
    EXPECT_EQ(a["stroke_use"].get<double>(), m.stroke_use);
    EXPECT_EQ(a["peak_speed"].get<double>(), m.peak_speed);
    EXPECT_EQ(a["speed_exceeded"], false);
    EXPECT_EQ(a["state"], "operation enabled");
  }
  EXPECT_NEAR(j["plate_pose"]["pitch_rad"].get<double>(), goal[mca::Index(Dof::kPitch)], 2e-6);
  EXPECT_EQ(j["forward_kinematics"]["ok"], true);
  const std::string text = DrivesSummaryText(b.drives);
  EXPECT_NE(text.find("node 2 leg_front_left (leg): position "), std::string::npos) << text;
  EXPECT_NE(text.find("% of the half-stroke"), std::string::npos) << text;
  EXPECT_NE(text.find("within its limits"), std::string::npos) << text;
  EXPECT_EQ(text.find("EXCEEDED"), std::string::npos) << text;
  EXPECT_NE(text.find("plate pose by forward kinematics: surge 0 m, sway 0 m, heave 0.02 m, roll "),
            std::string::npos) << text;
  EXPECT_NE(text.find(" pitch 3 deg, yaw -8 deg"), std::string::npos) << text;
}

// --- the car keeps its plant ---------------------------------------------------------------

TEST(SimulatedDrives, TheCarsDrivesMoveTheSeed001PlantExactly) {
  EXPECT_TRUE(SimulatedDrives::IsCarRailYaw(SimulatedDrives::CarMechanism()));
  Bench b;  // the default: the car
  ASSERT_EQ(b.n(), 2);
  EXPECT_TRUE(b.drives.uses_car_plant());
  EXPECT_EQ(b.drives.mechanism().actuator(0).dof, Dof::kYaw);
  EXPECT_EQ(b.drives.mechanism().actuator(1).dof, Dof::kSurge);
  b.Poll();
  ASSERT_GE(b.StartUp(), 0);
  // The same CSP targets into the plant directly: the drives' plant must move bit for bit alike.
  PlatformPlant truth;
  truth.ResetTarget({0.0, 0.0});
  std::array<std::uint16_t, 8> cw{};
  cw.fill(canopen::controlword::kEnableOperation);
  for (int k = 1; k <= 500; ++k) {
    const double t = k * kCycleS;
    std::array<std::int32_t, 8> target{};
    target[0] = static_cast<std::int32_t>(std::lround(1e6 * 0.2 * std::sin(1.3 * t)));
    target[1] = static_cast<std::int32_t>(std::lround(1e6 * 0.3 * std::sin(0.9 * t)));
    b.Cycle(cw, target);
    truth.Advance(kCycleS, {target[0] / 1e6, target[1] / 1e6}, true);
    ASSERT_EQ(b.drives.platform(), truth.state()) << "cycle " << k;
  }
  EXPECT_EQ(b.Actual(1), static_cast<std::int32_t>(std::lround(truth.state().q[1] * 1e6)));
  // Measured: the rail's pose by FK is its position; its envelope covers every substep.
  EXPECT_EQ(b.drives.measured_pose()[mca::Index(Dof::kSurge)], truth.state().q[1]);
  EXPECT_EQ(b.drives.measured_pose()[mca::Index(Dof::kYaw)], truth.state().q[0]);
  EXPECT_EQ(b.drives.envelope(1).samples, static_cast<long>(b.drives.syncs()) * 8);
  EXPECT_GE(b.drives.measurement(1).peak_offset, b.drives.peak_abs_position()[1]);
  EXPECT_EQ(b.drives.measurement(0).stroke_use, 0.0);  // the turntable has no stroke
}

TEST(SimulatedDrives, AnExceededLimitIsReportedAsMeasured) {
  // The car's PID may accelerate beyond the rail's 1.224 g (its effort limit allows 1.5 times
  // that): a 0.3 m step on the rail does, and the measurement says so.
  Bench b;
  b.Poll();
  ASSERT_GE(b.StartUp(), 0);
  const double limit = b.drives.mechanism().actuator(1).limits.accel;
  std::array<std::uint16_t, 8> cw{};
  cw.fill(canopen::controlword::kEnableOperation);
  double v_last = 0.0, a_seen = 0.0;  // a lower bound from the cycle-end velocities
  for (int k = 0; k < 100; ++k) {
    b.Cycle(cw, {0, 300'000});
    a_seen = std::max(a_seen, std::abs(b.drives.velocity(1) - v_last) / kCycleS);
    v_last = b.drives.velocity(1);
  }
  ASSERT_GT(a_seen, limit);
  const ActuatorMeasurement m = b.drives.measurement(1);
  EXPECT_GE(m.peak_accel, a_seen);
  EXPECT_TRUE(m.accel_exceeded);
  EXPECT_TRUE(b.drives.any_limit_exceeded());
  EXPECT_FALSE(m.stroke_exceeded);
  const nlohmann::json j = nlohmann::json::parse("{\n" + DrivesReportJsonMembers(b.drives) + "\n}");
  EXPECT_EQ(j["plant"], "lagrange-rail-yaw");
  EXPECT_EQ(j["limits_exceeded"]["acceleration"], true);
  EXPECT_EQ(j["limits_exceeded"]["stroke"], false);
  EXPECT_EQ(j["actuators"][1]["accel_exceeded"], true);
  EXPECT_EQ(j["actuators"][0]["stroke_max"], nullptr);  // the free turntable
  const std::string text = DrivesSummaryText(b.drives);
  const std::size_t rail = text.find("node 2 rail (rail): ");
  ASSERT_NE(rail, std::string::npos) << text;
  const std::string line = text.substr(rail, text.find('\n', rail) - rail);
  EXPECT_NE(line.find("; EXCEEDED "), std::string::npos) << line;
  EXPECT_NE(line.find("acceleration, force;"), std::string::npos) << line;
  EXPECT_NE(text.substr(0, rail).find("within its limits"), std::string::npos) << text;  // the yaw
}

TEST(SimulatedDrives, ShippedPlatformsGetOneNodePerActuator) {
  for (const char* file : {"car2dof.yaml", "pw4dof.yaml", "stewart6dof.yaml"}) {
    const mca::PlatformSpec spec = mca::ReadPlatformFile(kPlatforms / file);
    ASSERT_EQ(spec.mechanism.Validate(), "") << file;
    Bench b(spec.mechanism);
    EXPECT_EQ(b.drives.uses_car_plant(), std::string(file) == "car2dof.yaml") << file;
    b.Poll();
    for (int i = 0; i < b.n(); ++i) EXPECT_EQ(b.boot_ups[1 + i], 1) << file;
    ASSERT_GE(b.StartUp(), 0) << file;
    EXPECT_TRUE(b.drives.all_enabled()) << file;
    // A small pose on every axis the platform moves, reached and measured by FK.
    DofArray goal{};
    for (Dof d : mca::kAllDofs)
      if (spec.mechanism.Moves(d)) goal[mca::Index(d)] = mca::IsRotational(d) ? 0.03 : 0.01;
    b.Follow(1.5, [&](double t) { return Scaled(goal, Ramp(t, 1.0)); });
    const double tolerance = b.drives.uses_car_plant() ? 1e-3 : 2e-6;  // PID vs servo cascade
    for (Dof d : mca::kAllDofs)
      EXPECT_NEAR(b.drives.measured_pose()[mca::Index(d)], goal[mca::Index(d)], tolerance)
          << file << " " << mca::DofName(d);
    EXPECT_EQ(b.drives.fk_failures(), 0u) << file;
  }
}

}  // namespace
}  // namespace pwsim::hw
