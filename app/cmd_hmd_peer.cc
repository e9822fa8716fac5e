// pwsim hmd-peer: plays a headset on the HMD bridge for tests and demos. Receives camera
// poses, answers each frame with a tracked head pose (the head riding the platform, plus a
// gentle scripted head motion), answers pings, and can run on an offset clock or vanish.
// It takes datagrams from one peer only: the session's HMD address given with --peer, or, with
// --adopt-first-peer, the sender that completes the HELLO handshake (it echoes this headset's
// random stream id, which only a sender that receives our datagrams can know); others are
// counted and dropped (hardware/udp_socket.h). Each start is a new stream: HELLOs re-admit a
// restarted headset or session (hardware/hmd_protocol.h). --link-key: authenticated mode.

#include <csignal>
#include <cmath>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "app/commands.h"
#include "app/link_key_option.h"
#include "app/stop_signal.h"
#include "engine/atomic_file.h"
#include "hardware/hmd_protocol.h"
#include "hardware/udp_socket.h"

namespace pwsim::app {
const CommandSpec& HmdPeerSpec() {
  static const CommandSpec spec{
      "hmd-peer",
      "pwsim hmd-peer [options]",
      "Play a headset on the HMD bridge (UDP): camera poses in, head poses out.",
      {
          {"listen", "HOST:PORT", "-", "127.0.0.1:29537", "UDP address the session sends frames to (port 0: any free port; the line 'listening on HOST:PORT' names it)"},
          {"peer", "udp:HOST:PORT", "-", "", "the session's HMD address (pwsim session --hmd-local): the only sender whose messages are taken"},
          {"adopt-first-peer", "", "-", "", "instead of --peer: the sender that completes the HELLO handshake becomes the only peer (tests and demos on one machine); a first datagram alone adopts no one"},
          {"clock-offset-ms", "MS", "ms", "0", "run the headset clock this far ahead of ours"},
          {"head-yaw-deg", "DEG", "deg", "5", "amplitude of the scripted head yaw (0.5 Hz)"},
          {"duration", "S", "s", "0", "exit after this long (0 = until the session says bye)"},
          {"exit-after", "S", "s", "0", "vanish abruptly this long after the first camera pose (fault injection; 0 = never)"},
          {"report", "FILE", "-", "", "write a JSON summary"},
          LinkKeyOptionSpec(),
      },
      ""};
  return spec;
}

int HmdPeerCommand(const ParsedArgs& args) {
  if (!args.positional().empty()) throw UsageError("takes no positional arguments");
  const auto listen = hw::ParseUdpAddress(args.Get("listen"));
  if (!listen) throw UsageError("option --listen: expected HOST:PORT");
  const auto offset_ns = static_cast<std::int64_t>(args.GetDouble("clock-offset-ms", -1e6, 1e6) * 1e6);
  const double head_yaw = args.GetDouble("head-yaw-deg", 0.0, 90.0) * M_PI / 180.0;
  const double duration = args.GetDouble("duration", 0.0, 86400.0);
  const double exit_after = args.GetDouble("exit-after", 0.0, 86400.0);
  const bool adopt = args.Flag("adopt-first-peer");
  const std::string peer_spec = args.Get("peer");
  if (adopt == !peer_spec.empty())
    throw UsageError("give the session's HMD address with --peer udp:HOST:PORT, or --adopt-first-peer (not both)");
  hw::UdpSocket socket;
  if (!peer_spec.empty()) {
    if (peer_spec.rfind("udp:", 0) != 0 || !hw::ParseUdpAddress(peer_spec.substr(4)))
      throw UsageError("option --peer: expected udp:HOST:PORT, got '" + peer_spec + "'");
  }
  const std::optional<hw::LinkKey> key = LinkKeyOption(args, "hmd-peer");
  const std::string error = socket.Bind(*listen);
  if (!error.empty()) {
    std::cerr << "pwsim hmd-peer: " << error << "\n";
    return 1;
  }
  if (key) socket.EnableAuth(*key, hw::LinkKind::kHmd, hw::LinkRole::kPeer);
  InstallStopSignalHandlers();
  hw::UdpAddress bound = *listen;
  bound.port = socket.local_port();
  const std::uint32_t stream = hw::NewHmdStreamId();
  std::cout << "pwsim hmd-peer: " << (key ? "authenticated link (--link-key), " : "") << "stream " << stream << "\n"
            << "pwsim hmd-peer: listening on " << bound.ToString() << "\n" << std::flush;

  std::array<std::uint8_t, hw::kHmdMaxSize> reply{};
  std::uint32_t seq = 0;
  auto send = [&](const hw::UdpAddress& to, hw::HmdBody body, std::int64_t t_send) {
    hw::HmdMessage r;
    r.header.seq = seq++;
    r.header.session = stream;  // this headset's stream (hmd_protocol.h)
    r.header.t_send_ns = t_send;
    r.header.type = static_cast<hw::HmdType>(body.index() + 1);
    r.body = std::move(body);
    const std::size_t size = hw::EncodeHmd(r, reply);
    socket.SendTo(to, std::span<const std::uint8_t>(reply.data(), size));
  };
  // HELLOs this end starts (to a candidate, or while the session has not confirmed): at most
  // one per 20 ms to the same address.
  std::int64_t last_hello_ns = 0;
  std::optional<hw::UdpAddress> last_hello_to;
  auto hello = [&](const hw::UdpAddress& to, std::uint32_t echo, std::int64_t t_send) {
    const std::int64_t now = hw::MonotonicNs();
    if (last_hello_to == to && now - last_hello_ns < 20'000'000) return;
    last_hello_to = to;
    last_hello_ns = now;
    send(to, hw::HelloMsg{stream, echo}, t_send);
  };
  if (!peer_spec.empty()) {
    const hw::UdpAddress peer = *hw::ParseUdpAddress(peer_spec.substr(4));
    socket.AcceptOnlyFrom(peer);
    if (key) socket.SendHello(peer);        // our epoch first, so that what follows is fresh
    hello(peer, 0, offset_ns + hw::MonotonicNs());  // a session already running re-admits us
  }

  auto peer_now = [&] { return hw::MonotonicNs() + offset_ns; };
  const std::int64_t start = hw::MonotonicNs();
  std::int64_t first_frame_ns = -1;  // --exit-after counts from the session's first camera pose
  hw::ClockOffsetEstimator no_offset;  // the peer checks order only
  hw::HmdReceiveFilter filter(1'000'000'000, stream);
  std::uint64_t frames = 0;
  std::uint64_t refused_said = 0;
  std::uint64_t unconfirmed = 0;  // well-formed messages from senders not (yet) adopted
  std::uint32_t confirmed_said = 0;
  std::string why = "signal";
  std::array<std::uint8_t, 512> buffer{};
  for (;;) {
    if (StopRequested()) break;
    const double t = static_cast<double>(hw::MonotonicNs() - start) / 1e9;
    if (duration > 0 && t >= duration) {
      why = "duration reached";
      break;
    }
    const double t_frames =
        first_frame_ns < 0 ? -1.0 : static_cast<double>(hw::MonotonicNs() - first_frame_ns) / 1e9;
    if (exit_after > 0 && t_frames >= exit_after) {
      std::cout << "pwsim hmd-peer: vanishing " << t_frames << " s after the first camera pose (--exit-after)\n"
                << std::flush;
      return 0;
    }
    socket.WaitReadable(5);
    hw::UdpAddress from;
    long n = 0;
    bool bye = false;
    while ((n = socket.Receive(buffer, &from)) >= 0) {
      const std::int64_t rx = peer_now();
      hw::HmdMessage m;
      if (hw::DecodeHmd(std::span<const std::uint8_t>(buffer.data(),
                                                      std::min(static_cast<std::size_t>(n), buffer.size())),
                        &m) != hw::CodecError::kOk) {
        filter.CountMalformed();
        continue;
      }
      const auto* hi = std::get_if<hw::HelloMsg>(&m.body);
      if (!socket.peer()) {  // --adopt-first-peer: only a sender that echoes our stream
        if (hi == nullptr || hi->echo != stream) {
          ++unconfirmed;
          hello(from, hi != nullptr ? hi->stream : m.header.session, rx);
          continue;
        }
        socket.AcceptOnlyFrom(from);
        std::cout << "pwsim hmd-peer: adopted " << from.ToString() << " (it answered the hello)\n" << std::flush;
      }
      if (!filter.Accept(m, rx, no_offset)) {
        if (filter.TakeHelloWanted()) hello(from, filter.HelloAnswer().echo, rx);
        continue;
      }
      if (hi != nullptr) {
        send(from, filter.HelloAnswer(), peer_now());
        continue;
      }
      if (filter.peer_stream() == 0) hello(from, m.header.session, rx);  // not confirmed yet: start up
      hw::HmdBody body;
      if (const auto* cam = std::get_if<hw::CameraPoseMsg>(&m.body)) {
        ++frames;
        if (first_frame_ns < 0) {
          first_frame_ns = hw::MonotonicNs();
          std::cout << "pwsim hmd-peer: first camera pose from " << from.ToString() << "\n" << std::flush;
        }
        if (frames % 100 == 0) std::cout << "pwsim hmd-peer: " << frames << " frames\n" << std::flush;
        // Head in the rig: seated 1.2 m up, looking around gently; the tracker sees it in the
        // room, i.e. carried by the platform.
        const double ts = static_cast<double>(rx) / 1e9;
        hw::Pose head_in_rig;
        head_in_rig.p = {0.0, 0.0, 1.2};
        const double yaw = head_yaw * std::sin(2.0 * M_PI * 0.5 * ts);
        head_in_rig.q = {0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw)};
        const hw::Pose in_room =
            hw::ComposePose(hw::PlatformPose(cam->platform[0], cam->platform[1]), head_in_rig);
        body = hw::HeadPoseMsg{rx, in_room, cam->frame, rx};
      } else if (const auto* ping = std::get_if<hw::PingMsg>(&m.body)) {
        body = hw::PongMsg{ping->t0, rx, 0};
      } else if (std::holds_alternative<hw::ByeMsg>(m.body)) {
        bye = true;
        continue;
      } else {
        continue;
      }
      if (auto* pong = std::get_if<hw::PongMsg>(&body)) pong->t2 = peer_now();
      send(from, std::move(body), peer_now());
    }
    if (filter.peer_stream() != confirmed_said) {  // an event other processes can wait for
      confirmed_said = filter.peer_stream();
      std::cout << "pwsim hmd-peer: session stream " << confirmed_said << " confirmed"
                << (filter.counters().restarts > 0 ? " (restart " + std::to_string(filter.counters().restarts) + ")" : "")
                << "\n" << std::flush;
    }
    if (socket.refused() != refused_said) {  // an event other processes can wait for
      refused_said = socket.refused();
      std::cout << "pwsim hmd-peer: refused " << refused_said << " datagrams from senders other than "
                << (socket.peer() ? socket.peer()->ToString() : "the peer") << "\n" << std::flush;
    }
    if (bye) {
      why = "session said bye";
      break;
    }
  }
  const auto& c = filter.counters();
  std::cout << "pwsim hmd-peer: stopped (" << why << "), " << frames << " frames, dropped "
            << c.out_of_order << " out-of-order, " << c.malformed << " malformed, " << c.other_stream
            << " of another stream, " << unconfirmed << " from senders not adopted, refused "
            << socket.refused() << " from other senders\n";
  if (!args.Get("report").empty()) {
    std::ostringstream r;
    r << "{\n  \"format\": \"pwsim-hmd-peer-report/1\",\n  \"frames\": " << frames
      << ",\n  \"peer\": \"" << (socket.peer() ? socket.peer()->ToString() : "") << "\""
      << ",\n  \"refused_datagrams\": " << socket.refused()
      << ",\n  \"out_of_order\": " << c.out_of_order << ",\n  \"malformed\": " << c.malformed
      << ",\n  \"stream\": " << stream << ",\n  \"session_stream\": " << filter.peer_stream()
      << ",\n  \"other_stream\": " << c.other_stream << ",\n  \"session_restarts\": " << c.restarts
      << ",\n  \"unconfirmed_messages\": " << unconfirmed;
    if (const hw::LinkAuthCounters* a = socket.auth_counters())
      r << ",\n  \"auth\": {\"accepted\": " << a->accepted << ", \"bad_tag\": " << a->bad_tag
        << ", \"replayed\": " << a->replayed << ", \"unconfirmed\": " << a->unconfirmed
        << ", \"malformed\": " << a->malformed << ", \"peer_restarts\": " << a->peer_restarts << "}";
    r
      << ",\n  \"stop\": \"" << why << "\"\n}\n";
    WriteFileAtomically(args.Get("report"), r.str());
  }
  return 0;
}

}  // namespace pwsim::app
