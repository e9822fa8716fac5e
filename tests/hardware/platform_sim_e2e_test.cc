// `pwsim platform-sim --platform scenes/platforms/pw4dof.yaml` as a process on loopback, with
// this test as the CANopen master on a real UdpCanBus: five boot-ups at start, the start-up,
// a CSP trajectory answered SYNC by SYNC; then the process is killed and restarted on the same
// port: five boot-ups again and the start-up works again; at exit it prints what the actuators
// did and writes the JSON report. Every wait is for an event (a line, a frame, an exit); the
// time limits only guard against a hang.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "hardware/canopen.h"
#include "hardware/udp_can_bus.h"
#include "hardware/udp_socket.h"
#include "mca/platform.h"
#include "tests/hardware/child_process.h"

namespace pwsim::hw {
namespace {

namespace fs = std::filesystem;

/// The binary under test: PWSIM_E2E_PWSIM when set (scripts/e2e-under-load.sh runs a copy), else
/// the build's.
const std::string kPwsim = std::getenv("PWSIM_E2E_PWSIM") != nullptr ? std::string(std::getenv("PWSIM_E2E_PWSIM"))
                                                                     : std::string(PWSIM_BINARY_DIR) + "/pwsim";
const fs::path kPw4Dof = fs::path(PWSIM_SOURCE_DIR) / "scenes/platforms/pw4dof.yaml";
constexpr int kGuardMs = 60'000;

/// The child processes (tests/hardware/child_process.h).
using Child = pwsim::test::ChildProcess;

/// The master's end of the link and what it heard.
struct Master {
  std::unique_ptr<ICanBus> bus;
  std::array<int, 128> boot_ups{};
  std::array<canopen::CspStatus, 128> status{};
  int tpdo1{0};
  std::vector<std::uint16_t> emcy;
  std::uint8_t counter{0};

  /// Receives until `done` holds; false when nothing came for the guard's length.
  template <class Done>
  bool ReceiveUntil(const Done& done) {
    while (!done()) {
      CanFrame f;
      if (bus->Receive(&f) != BusStatus::kOk) {
        if (!WaitReadable(*bus, kGuardMs)) return false;
        continue;
      }
      std::uint8_t node = 0;
      switch (canopen::Classify(f, &node)) {
        case canopen::FrameKind::kHeartbeat: {
          canopen::NmtState s{};
          if (canopen::DecodeHeartbeat(f, &node, &s) && s == canopen::NmtState::kBootUp) ++boot_ups[node];
          break;
        }
        case canopen::FrameKind::kTpdo1:
          if (canopen::DecodeCspStatus(f, &node, &status[node])) ++tpdo1;
          break;
        case canopen::FrameKind::kEmcy: {
          canopen::Emcy e;
          if (canopen::DecodeEmcy(f, &node, &e)) emcy.push_back(e.code);
          break;
        }
        default:
          break;
      }
    }
    return true;
  }
  bool BootUpsFromAll(int n, int count) {
    return ReceiveUntil([&] {
      for (int i = 1; i <= n; ++i)
        if (boot_ups[i] < count) return false;
      return true;
    });
  }
  /// One cycle: RPDO1 to every node, SYNC, then wait for every node's TPDO1.
  bool Cycle(int n, const std::array<std::uint16_t, 8>& cw, const std::array<std::int32_t, 8>& target) {
    for (int i = 0; i < n; ++i) bus->Send(canopen::EncodeCspCommand(static_cast<std::uint8_t>(1 + i), {cw[i], target[i]}));
    counter = static_cast<std::uint8_t>(counter % 240 + 1);
    bus->Send(canopen::EncodeSync(counter));
    const int want = tpdo1 + n;
    return ReceiveUntil([&] { return tpdo1 >= want; });
  }
  canopen::DriveState State(int i) const { return canopen::DecodeStatusword(status[1 + i].statusword); }
  /// NMT reset-communication (and its boot-ups), NMT start, the controlword walk.
  bool StartUp(int n) {
    const std::array<int, 128> before = boot_ups;
    bus->Send(canopen::EncodeNmt(canopen::NmtCommand::kResetComm, 0));
    if (!ReceiveUntil([&] {
          for (int i = 1; i <= n; ++i)
            if (boot_ups[i] <= before[i]) return false;
          return true;
        }))
      return false;
    bus->Send(canopen::EncodeNmt(canopen::NmtCommand::kStart, 0));
    for (int k = 0; k < 20; ++k) {
      std::array<std::uint16_t, 8> cw{};
      std::array<std::int32_t, 8> hold{};
      bool all = k > 0;
      for (int i = 0; i < n; ++i) {
        cw[i] = canopen::ControlwordTowardEnabled(State(i));
        hold[i] = status[1 + i].position_actual;
        all = all && State(i) == canopen::DriveState::kOperationEnabled;
      }
      if (all) return true;
      if (!Cycle(n, cw, hold)) return false;
    }
    return false;
  }
};

/// A port that was free a moment ago (bound and released), for the simulator's --listen.
std::uint16_t FreePort() {
  UdpSocket probe;
  if (!probe.Bind(*ParseUdpAddress("127.0.0.1:0")).empty()) return 0;
  return probe.local_port();
}

TEST(PlatformSimProcess, Pw4DofBootsFiveDrivesFollowsAndIsReadmittedAfterARestart) {
  const fs::path dir = fs::temp_directory_path() / ("pwsim_platform_sim_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::uint16_t port = FreePort();
  ASSERT_NE(port, 0);
  const std::string drives_at = "127.0.0.1:" + std::to_string(port);
  Master m;
  BusOpenResult opened = UdpCanBus::Open("127.0.0.1:0", drives_at);
  ASSERT_TRUE(opened.bus) << opened.message;
  const std::string master_at = "127.0.0.1:" + std::to_string(static_cast<UdpCanBus&>(*opened.bus).local_port());
  m.bus = std::move(opened.bus);
  const mca::Mechanism mech = mca::ReadPlatformFile(kPw4Dof).mechanism;
  const int n = mech.actuator_count();
  ASSERT_EQ(n, 5);
  auto spawn = [&](const std::string& report) {
    return std::make_unique<Child>(std::vector<std::string>{
        kPwsim, "platform-sim", "--platform", kPw4Dof.string(), "--listen", drives_at, "--peer",
        "udp:" + master_at, "--idle-exit", "1", "--report", (dir / report).string()});
  };

  // First run: boot-ups at power-on, the start-up, a short motion.
  auto first = spawn("first.json");
  const auto banner = first->WaitForLine("pwsim platform-sim: pw4dof, drives ");
  ASSERT_TRUE(banner) << first->Output();
  EXPECT_NE(banner->find("1 (yaw), 2 (leg_front_left)"), std::string::npos) << *banner;
  ASSERT_TRUE(m.BootUpsFromAll(n, 1)) << first->Output();
  ASSERT_TRUE(m.StartUp(n)) << first->Output();
  std::array<std::uint16_t, 8> enable{};
  enable.fill(canopen::controlword::kEnableOperation);
  auto follow = [&](const mca::DofArray& goal, int cycles) {
    for (int k = 1; k <= cycles; ++k) {
      const double s = k >= cycles / 2 ? 1.0 : 0.5 * (1.0 - std::cos(mca::kPi * k / (cycles / 2)));
      mca::DofArray x{};
      for (std::size_t a = 0; a < x.size(); ++a) x[a] = s * goal[a];
      mca::ActuatorVector q;
      if (!mech.Inverse(x, &q)) return false;
      std::array<std::int32_t, 8> target{};
      for (int i = 0; i < n; ++i) target[i] = static_cast<std::int32_t>(std::lround(q(i) * 1e6));
      if (!m.Cycle(n, enable, target)) return false;
    }
    return true;
  };
  mca::DofArray goal{};
  goal[mca::Index(mca::Dof::kHeave)] = 0.02;
  goal[mca::Index(mca::Dof::kPitch)] = 3.0 * mca::kDegToRad;
  ASSERT_TRUE(follow(goal, 100));

  // Killed mid-session and restarted on the same port: boot-ups again, the start-up again.
  first->Kill();
  auto second = spawn("second.json");
  ASSERT_TRUE(second->WaitForLine("pwsim platform-sim: listening on ")) << second->Output();
  ASSERT_TRUE(m.BootUpsFromAll(n, 3)) << second->Output();  // power-on, reset-comm, power-on
  ASSERT_TRUE(m.StartUp(n)) << second->Output();
  ASSERT_TRUE(second->WaitForLine("pwsim platform-sim: operation enabled")) << second->Output();
  goal[mca::Index(mca::Dof::kRoll)] = -2.0 * mca::kDegToRad;
  goal[mca::Index(mca::Dof::kYaw)] = 5.0 * mca::kDegToRad;
  ASSERT_TRUE(follow(goal, 200));
  EXPECT_TRUE(m.emcy.empty());

  // The master stops: the drives quick-stop (300 ms without it), the simulator exits on idle
  // (1 s), says what the actuators did and writes its JSON report.
  EXPECT_EQ(second->Wait(), 0) << second->Output();
  const std::string& out = second->Output();
  EXPECT_NE(out.find("pwsim platform-sim: node 2 leg_front_left (leg): position "), std::string::npos) << out;
  EXPECT_NE(out.find("pwsim platform-sim: plate pose by forward kinematics: surge 0 m"), std::string::npos) << out;
  EXPECT_EQ(out.find("EXCEEDED"), std::string::npos) << out;
  std::ifstream in(dir / "second.json");
  const nlohmann::json r = nlohmann::json::parse(in, nullptr, false);
  ASSERT_TRUE(r.is_object()) << out;
  EXPECT_EQ(r["platform"], "pw4dof");
  EXPECT_EQ(r["plant"], "actuator-servos");
  ASSERT_EQ(r["actuators"].size(), 5u);
  ASSERT_EQ(r["final_position"].size(), 5u);
  for (const char* what : {"stroke", "speed", "acceleration", "force"}) EXPECT_EQ(r["limits_exceeded"][what], false);
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(r["actuators"][i]["node"], 1 + i);
    EXPECT_EQ(r["actuators"][i]["state"], "quick stop active");  // the master fell silent first
    EXPECT_GT(r["actuators"][i]["peak_speed"].get<double>(), 0.0);
  }
  EXPECT_NEAR(r["plate_pose"]["heave_m"].get<double>(), 0.02, 1e-5);
  EXPECT_NEAR(r["plate_pose"]["pitch_rad"].get<double>(), 3.0 * mca::kDegToRad, 1e-5);
  EXPECT_NEAR(r["plate_pose"]["roll_rad"].get<double>(), -2.0 * mca::kDegToRad, 1e-5);
  EXPECT_NEAR(r["plate_pose"]["yaw_rad"].get<double>(), 5.0 * mca::kDegToRad, 1e-5);
  EXPECT_EQ(r["forward_kinematics"]["ok"], true);
  EXPECT_EQ(r["master_lost"], true);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pwsim::hw
