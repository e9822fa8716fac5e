// The HMD link with the real `pwsim hmd-peer` processes on loopback. This test plays the
// session's end with the session core's own HMD rules (a HmdReceiveFilter with a stream of its
// own, answering the HELLOs that ask for it: hardware/session_core.cc HandleHmd), so that:
//  - a headset killed and started again on the same port (a new process, a new stream, seq
//    from 0) is re-admitted through its HELLO, plain and authenticated (a new epoch);
//  - with --adopt-first-peer, a stranger's camera pose sent first adopts no one (it gets a
//    HELLO back, not a head pose) and the session that answers the HELLO is adopted; the
//    stranger is refused from then on; in authenticated mode a stranger without the key gets
//    nothing back at all.
// Synchronised on events only: lines the headset prints, datagrams arriving, exits.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <string>

#include "hardware/canopen.h"
#include "hardware/hmd_protocol.h"
#include "hardware/link_auth.h"
#include "hardware/udp_socket.h"
#include "tests/hardware/child_process.h"
#include "tests/hardware/forged_udp.h"

namespace pwsim::hw {
namespace {

namespace fs = std::filesystem;
using test::ChildProcess;

/// The binary under test: PWSIM_E2E_PWSIM when set (a copy that a rebuild cannot swap mid-run,
/// as scripts/e2e-under-load.sh does), else the build's.
const std::string kPwsim = std::getenv("PWSIM_E2E_PWSIM") != nullptr ? std::string(std::getenv("PWSIM_E2E_PWSIM"))
                                                                     : std::string(PWSIM_BINARY_DIR) + "/pwsim";

/// The address and stream of a headset, from its lines "stream N" (printed first) and
/// "listening on HOST:PORT".
struct Listening {
  UdpAddress address;
  std::uint32_t stream{0};
};
std::optional<Listening> WaitListening(ChildProcess& headset) {
  const auto address_line = headset.WaitForLine("pwsim hmd-peer: listening on ");
  const std::string out = headset.Output();
  const std::size_t at = out.find("stream ");
  if (!address_line || at == std::string::npos) return std::nullopt;
  const auto address = ParseUdpAddress(*address_line);
  if (!address) return std::nullopt;
  return Listening{*address, static_cast<std::uint32_t>(std::stoul(out.substr(at + 7)))};
}

/// The session's end of the HMD link, with the core's rules.
class SessionEnd {
 public:
  explicit SessionEnd(const std::optional<LinkKey>& key) : filter_(1'000'000'000, NewHmdStreamId()) {
    EXPECT_EQ(socket.Bind(*ParseUdpAddress("127.0.0.1:0")), "");
    if (key) socket.EnableAuth(*key, LinkKind::kHmd, LinkRole::kSession);
  }
  UdpSocket socket;
  std::string address() const { return "127.0.0.1:" + std::to_string(socket.local_port()); }
  const HmdReceiveFilter& filter() const { return filter_; }
  /// Head poses taken, by the stream the headset named in them.
  std::map<std::uint32_t, int> heads;

  void Send(const UdpAddress& to, HmdBody body) {
    HmdMessage m;
    m.header.seq = seq_++;
    m.header.session = filter_.own_stream();
    m.header.t_send_ns = MonotonicNs();
    m.header.type = static_cast<HmdType>(body.index() + 1);
    m.body = std::move(body);
    std::array<std::uint8_t, kHmdMaxSize> out{};
    socket.SendTo(to, std::span<const std::uint8_t>(out.data(), EncodeHmd(m, out)));
  }
  /// One frame to `to`, then what arrived, until `done()` (false after the guard).
  bool RunUntil(const UdpAddress& to, const std::function<bool()>& done) {
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
      Send(to, CameraPoseMsg{frame_ * 10, frame_, Pose{}, {0.0, 0.0}});
      ++frame_;
      socket.WaitReadable(10);  // the frame period; the headset answers within it or later
      Drain();
      if (done()) return true;
    }
    return false;
  }
  void Drain() {
    std::array<std::uint8_t, 512> buffer{};
    UdpAddress from;
    long n = 0;
    while ((n = socket.Receive(buffer, &from)) >= 0) {
      HmdMessage m;
      if (DecodeHmd(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)), &m) != CodecError::kOk) {
        filter_.CountMalformed();
        continue;
      }
      if (!filter_.Accept(m, MonotonicNs(), offset_)) {
        if (filter_.TakeHelloWanted()) Send(from, filter_.HelloAnswer());
        continue;
      }
      if (std::holds_alternative<HelloMsg>(m.body)) Send(from, filter_.HelloAnswer());
      if (std::holds_alternative<HeadPoseMsg>(m.body)) ++heads[m.header.session];
    }
  }

 private:
  HmdReceiveFilter filter_;
  ClockOffsetEstimator offset_;
  std::uint32_t seq_{0};
  std::int64_t frame_{0};
};

struct TempDir {
  fs::path dir = fs::temp_directory_path() / ("pwsim_hmd_link_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(dir); }
  ~TempDir() { fs::remove_all(dir); }
  /// A key file (mode 0600) and the key it holds.
  std::pair<std::string, LinkKey> Key() {
    const fs::path p = dir / "link.key";
    std::ofstream(p) << "8f1c2e7a9b3d4c5e6f708192a3b4c5d6e7f8091a2b3c4d5e6f708192a3b4c5d6\n";
    ::chmod(p.c_str(), 0600);
    return {p.string(), ReadLinkKeyFile(p.string(), nullptr)};
  }
};

void RestartIsReadmitted(bool authenticated) {
  if (!fs::exists(kPwsim)) GTEST_SKIP() << kPwsim << " not built";
  TempDir tmp;
  std::vector<std::string> key_args;
  std::optional<LinkKey> key;
  if (authenticated) {
    auto [path, k] = tmp.Key();
    key_args = {"--link-key", path};
    key = k;
  }
  SessionEnd session(key);
  auto start = [&](const std::string& listen) {
    std::vector<std::string> args = {kPwsim, "hmd-peer", "--listen", listen, "--peer", "udp:" + session.address()};
    args.insert(args.end(), key_args.begin(), key_args.end());
    return std::make_unique<ChildProcess>(args);
  };
  auto first = start("127.0.0.1:0");
  const auto one = WaitListening(*first);
  ASSERT_TRUE(one) << first->Output();
  session.socket.AcceptOnlyFrom(one->address);
  ASSERT_TRUE(session.RunUntil(one->address, [&] {
    return session.filter().peer_stream() == one->stream && session.heads[one->stream] >= 5;
  })) << first->Output();
  ASSERT_TRUE(first->WaitForLine("pwsim hmd-peer: session stream " + std::to_string(session.filter().own_stream()) +
                                 " confirmed")) << first->Output();
  // Killed mid-session, started again on the same port: a new stream, its seq from 0.
  first->Kill();
  auto second = start(one->address.ToString());
  const auto two = WaitListening(*second);
  ASSERT_TRUE(two) << second->Output();
  ASSERT_NE(two->stream, one->stream);
  ASSERT_TRUE(session.RunUntil(one->address, [&] { return session.heads[two->stream] >= 5; })) << second->Output();
  EXPECT_EQ(session.filter().peer_stream(), two->stream);
  EXPECT_EQ(session.filter().counters().restarts, 1U);
  EXPECT_EQ(session.heads[one->stream] >= 5, true);
  if (authenticated) {
    EXPECT_EQ(session.socket.auth_counters()->peer_restarts, 1U);
    EXPECT_EQ(session.socket.auth_counters()->bad_tag, 0U);
  }
  session.Send(two->address, ByeMsg{});
  EXPECT_EQ(second->Wait(), 0) << second->Output();
  EXPECT_NE(second->Output().find("stopped (session said bye)"), std::string::npos) << second->Output();
}

TEST(HmdPeerLink, ARestartedHeadsetIsReadmittedThroughItsHello) { RestartIsReadmitted(false); }
TEST(HmdPeerLink, ARestartedHeadsetIsReadmittedInAuthenticatedMode) { RestartIsReadmitted(true); }

TEST(HmdPeerLink, AStrangersFirstMessageAdoptsNoOneTheSessionsHelloDoes) {
  if (!fs::exists(kPwsim)) GTEST_SKIP() << kPwsim << " not built";
  TempDir tmp;
  const std::string report = (tmp.dir / "hmd.json").string();
  ChildProcess headset({kPwsim, "hmd-peer", "--listen", "127.0.0.1:0", "--adopt-first-peer", "--report", report});
  const auto at = WaitListening(headset);
  ASSERT_TRUE(at) << headset.Output();
  // The stranger sends a well-formed camera pose first and waits for what comes back.
  SessionEnd stranger(std::nullopt);
  stranger.Send(at->address, CameraPoseMsg{});
  ASSERT_TRUE(stranger.socket.WaitReadable(60'000)) << headset.Output();
  std::array<std::uint8_t, 512> buffer{};
  const long n = stranger.socket.Receive(buffer, nullptr);
  ASSERT_GT(n, 0);
  HmdMessage back;
  ASSERT_EQ(DecodeHmd(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)), &back), CodecError::kOk);
  ASSERT_TRUE(std::holds_alternative<HelloMsg>(back.body));  // a HELLO, not a head pose
  EXPECT_EQ(std::get<HelloMsg>(back.body), (HelloMsg{at->stream, stranger.filter().own_stream()}));
  // The session answers the handshake and is adopted.
  SessionEnd session(std::nullopt);
  ASSERT_TRUE(session.RunUntil(at->address, [&] { return session.heads[at->stream] >= 3; })) << headset.Output();
  ASSERT_TRUE(headset.WaitForLine("pwsim hmd-peer: adopted " + session.address())) << headset.Output();
  // The stranger, even answering the HELLO now, is refused.
  stranger.Send(at->address, HelloMsg{stranger.filter().own_stream(), at->stream});
  ASSERT_TRUE(headset.WaitForLine("pwsim hmd-peer: refused 1 datagrams")) << headset.Output();
  session.Send(at->address, ByeMsg{});
  ASSERT_EQ(headset.Wait(), 0) << headset.Output();
  std::ifstream in(report);
  const auto r = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(r.is_discarded());
  EXPECT_EQ(r["peer"].get<std::string>(), session.address());
  // The stranger's camera pose and the session's before the handshake: held, not answered.
  EXPECT_GE(r["unconfirmed_messages"].get<int>(), 2);
  EXPECT_EQ(r["refused_datagrams"].get<int>(), 1);
  EXPECT_EQ(r["session_stream"].get<std::uint32_t>(), session.filter().own_stream());
}

TEST(HmdPeerLink, InAuthenticatedModeAStrangerWithoutTheKeyGetsNothingBack) {
  if (!fs::exists(kPwsim)) GTEST_SKIP() << kPwsim << " not built";
  TempDir tmp;
  auto [path, key] = tmp.Key();
  ChildProcess headset({kPwsim, "hmd-peer", "--listen", "127.0.0.1:0", "--adopt-first-peer", "--link-key", path});
  const auto at = WaitListening(headset);
  ASSERT_TRUE(at) << headset.Output();
  SessionEnd stranger(std::nullopt);  // plain: no key
  stranger.Send(at->address, CameraPoseMsg{});
  stranger.Send(at->address, HelloMsg{stranger.filter().own_stream(), at->stream});
  ASSERT_TRUE(headset.WaitForLine("pwsim hmd-peer: refused 2 datagrams")) << headset.Output();
  SessionEnd session(key);
  ASSERT_TRUE(session.RunUntil(at->address, [&] { return session.heads[at->stream] >= 3; })) << headset.Output();
  ASSERT_TRUE(headset.WaitForLine("pwsim hmd-peer: adopted " + session.address())) << headset.Output();
  stranger.Drain();
  EXPECT_TRUE(stranger.heads.empty());
  session.Send(at->address, ByeMsg{});
  EXPECT_EQ(headset.Wait(), 0) << headset.Output();
}

/// A free loopback port: bound by the kernel's choice and released for a process to bind.
std::string FreePort() {
  UdpSocket probe;
  if (!probe.Bind(*ParseUdpAddress("127.0.0.1:0")).empty()) return "";
  return "127.0.0.1:" + std::to_string(probe.local_port());
}

// The whole system: `pwsim session` with platform-sim and a headset that is killed mid-session
// and started again on its port. The session core answers the new headset's HELLO (the
// headset prints that it confirmed the session's stream only after a HELLO echoing its own new
// stream), takes its head poses, stops cleanly on SIGINT and its log replays bit for bit.
// Authenticated: the same with --link-key everywhere, and a quick stop for the rail forged
// with the session's own CAN address (a raw socket) is refused by the drives: the session
// parks as if nothing happened (in issue 39 one such datagram quick-stopped the drives).
void SessionReadmitsARestartedHeadset(bool authenticated) {
  if (!fs::exists(kPwsim)) GTEST_SKIP() << kPwsim << " not built";
  TempDir tmp;
  std::vector<std::string> key;
  if (authenticated) key = {"--link-key", tmp.Key().first};
  auto with_key = [&](std::vector<std::string> args) {
    args.insert(args.end(), key.begin(), key.end());
    return args;
  };
  const std::string can_local = FreePort(), hmd_local = FreePort(), hmd_at = FreePort();
  // The car scene on platform-sim's default platform (the car's yaw + rail drives).
  ChildProcess platform(with_key({kPwsim, "platform-sim", "--listen", "127.0.0.1:0", "--peer", "udp:" + can_local,
                                  "--idle-exit", "0"}));
  const auto can_at = platform.WaitForLine("pwsim platform-sim: listening on ");
  ASSERT_TRUE(can_at) << platform.Output();
  auto headset = [&] {
    return std::make_unique<ChildProcess>(with_key({kPwsim, "hmd-peer", "--listen", hmd_at, "--peer", "udp:" + hmd_local}));
  };
  auto first = headset();
  ASSERT_TRUE(first->WaitForLine("pwsim hmd-peer: listening on ")) << first->Output();
  const fs::path out = tmp.dir / "session";
  ChildProcess session(with_key({kPwsim, "session", std::string(PWSIM_SOURCE_DIR) + "/scenes/car_lane_change.yaml",
                                 "--can", "udp:" + *can_at, "--can-local", can_local, "--hmd", "udp:" + hmd_at,
                                 "--hmd-local", hmd_local, "--hmd-timeout-ms", "60000", "--drive-wait-ms", "50",
                                 "--duration", "14", "--out", out.string()}));
  ASSERT_TRUE(first->WaitForLine("pwsim hmd-peer: 100 frames")) << first->Output() << session.Output();
  const auto stream = first->WaitForLine("pwsim hmd-peer: session stream ");
  ASSERT_TRUE(stream) << first->Output();
  first->Kill();
  auto second = headset();
  ASSERT_TRUE(second->WaitForLine("pwsim hmd-peer: session stream " + *stream)) << second->Output() << session.Output();
  ASSERT_TRUE(second->WaitForLine("pwsim hmd-peer: 100 frames")) << second->Output();
  if (authenticated) {
    std::vector<std::uint8_t> quick_stop(kCannelloniHeaderSize + 13);
    const CanFrame frame = canopen::EncodeCspCommand(2, {canopen::controlword::kQuickStop, 0});
    quick_stop.resize(EncodeCannelloni(0, std::span<const CanFrame>(&frame, 1), quick_stop));
    const std::optional<bool> sent = test::SendForgedUdp(*ParseUdpAddress(can_local), *ParseUdpAddress(*can_at), quick_stop);
    if (sent) {
      ASSERT_TRUE(*sent);
      ASSERT_TRUE(platform.WaitForLine("pwsim platform-sim: refused 1 datagrams")) << platform.Output();
    } else {
      std::cout << "no raw socket here (CAP_NET_RAW): the forged quick stop is not sent\n";
    }
  }
  ::kill(session.pid(), SIGINT);
  EXPECT_EQ(session.Wait(), 0) << session.Output();
  EXPECT_EQ(second->Wait(), 0) << second->Output();  // the session said bye
  ChildProcess replay({kPwsim, "replay", (out / "session.log").string()});
  EXPECT_EQ(replay.Wait(), 0) << replay.Output();
  std::ifstream in(out / "report.json");
  const auto r = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(r.is_discarded());
  EXPECT_EQ(r["hmd_rx"]["malformed"].get<int>(), 0);
  EXPECT_GT(r["hmd_rx"]["accepted"].get<int>(), 200);
}

TEST(HmdPeerLink, ASessionReadmitsARestartedHeadset) { SessionReadmitsARestartedHeadset(false); }
TEST(HmdPeerLink, AnAuthenticatedSessionReadmitsARestartedHeadsetAndIgnoresAForgedQuickStop) {
  SessionReadmitsARestartedHeadset(true);
}

}  // namespace
}  // namespace pwsim::hw
