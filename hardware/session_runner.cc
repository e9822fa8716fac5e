#include "hardware/session_runner.h"

#include <poll.h>
#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <array>
#include <functional>

#include "hardware/candump_log.h"
#include "hardware/canopen.h"

namespace pwsim::hw {
namespace {

void Drain(ICanBus& bus, UdpSocket* hmd, SessionInputs* in, CandumpWriter* dump) {
  CanFrame f;
  while (bus.Receive(&f) == BusStatus::kOk) {
    const std::int64_t now = MonotonicNs();
    in->can.push_back({now, f});
    if (dump != nullptr) dump->Write(now / 1000, f);
  }
  if (hmd == nullptr) return;
  std::array<std::uint8_t, 512> buffer{};
  for (;;) {
    UdpAddress from;
    const long n = hmd->Receive(buffer, &from);
    if (n < 0) break;
    RxDatagram d;
    d.rx_ns = MonotonicNs();
    const auto size = std::min(static_cast<std::size_t>(n), buffer.size());
    d.bytes.assign(buffer.begin(), buffer.begin() + static_cast<long>(size));
    in->hmd.push_back(std::move(d));
  }
}

/// Waits until `deadline_ns`, collecting whatever arrives meanwhile (the source's live input
/// too, for step `tick`); with `until`, returns as soon as it holds.
void WaitUntil(std::int64_t deadline_ns, ICanBus& bus, UdpSocket* hmd, SessionInputs* in,
               CandumpWriter* dump, SessionSource& source, std::int64_t tick,
               const std::function<bool()>& until = nullptr) {
  for (;;) {
    Drain(bus, hmd, in, dump);
    if (source.input_fd() >= 0) source.TakeInput(tick, MonotonicNs());
    const std::int64_t now = MonotonicNs();
    if (now >= deadline_ns || (until && until())) return;
    std::array<pollfd, 3> fds{};
    nfds_t n = 0;
    if (bus.fd() >= 0) fds[n++] = {bus.fd(), POLLIN, 0};
    if (hmd != nullptr && hmd->fd() >= 0) fds[n++] = {hmd->fd(), POLLIN, 0};
    if (source.input_fd() >= 0) fds[n++] = {source.input_fd(), POLLIN, 0};
    const std::int64_t wait = deadline_ns - now;
    timespec ts{static_cast<time_t>(wait / 1'000'000'000), static_cast<long>(wait % 1'000'000'000)};
    ::ppoll(fds.data(), n, &ts, nullptr);
  }
}

/// Which axes answered the last SYNC with a TPDO1 (scans the frames received so far).
class AnswerTracker {
 public:
  explicit AnswerTracker(const MasterConfig& master) : count_(static_cast<std::size_t>(master.axis_count)) {
    for (std::size_t k = 0; k < count_; ++k) nodes_[k] = master.axes[k].node;
  }
  void Scan(const std::vector<RxFrame>& can) {
    for (; cursor_ < can.size(); ++cursor_) {
      std::uint8_t node = 0;
      if (canopen::Classify(can[cursor_].frame, &node) != canopen::FrameKind::kTpdo1) continue;
      for (std::size_t k = 0; k < count_; ++k)
        if (node == nodes_[k]) answered_ |= 1U << k;
    }
  }
  bool all() const { return answered_ == (1U << count_) - 1; }
  void NewSync() { answered_ = 0; }
  void InputsCleared() { cursor_ = 0; }

 private:
  std::size_t count_{0};
  std::array<std::uint8_t, kMaxDriveAxes> nodes_{};
  unsigned answered_{0};
  std::size_t cursor_{0};
};

}  // namespace

std::string EnterRealtime(int priority) {
  sched_param p{};
  p.sched_priority = priority;
  if (::sched_setscheduler(0, SCHED_FIFO, &p) != 0)
    return std::string("SCHED_FIFO refused: ") + std::strerror(errno);
  if (::mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
    return std::string("mlockall refused: ") + std::strerror(errno);
  return "";
}

void StreamsSource::Fill(std::int64_t tick, bool drive, bool frame, std::int64_t /*now_ns*/, SessionInputs* in) {
  if (drive && !streams_.setpoints.empty()) {
    const auto i = static_cast<std::size_t>(tick / config_.drive_cycle_ticks);
    in->setpoint = streams_.setpoints[std::min(i, streams_.setpoints.size() - 1)];
  }
  if (frame && !streams_.cameras.empty()) {
    const auto i = static_cast<std::size_t>(tick / config_.frame_ticks);
    in->camera = streams_.cameras[std::min(i, streams_.cameras.size() - 1)];
  }
}

SessionReport RunSession(const SessionConfig& config, const SessionStreams& streams,
                         const RunnerIo& io) {
  StreamsSource source(config, streams);
  return RunSession(config, source, io);
}

SessionReport RunSession(const SessionConfig& config, SessionSource& source, const RunnerIo& io) {
  SessionCore core(config);
  // At most one latency sample per output step (the last steps park and disable the drives:
  // margin): reserved up front, nothing allocated later; beyond it, InputLatency counts overflow.
  const std::int64_t last_tick = config.run_ticks + config.max_stop_ticks;
  InputLatency to_platform(static_cast<std::size_t>(last_tick / config.drive_cycle_ticks + 1000));
  InputLatency to_hmd(static_cast<std::size_t>(last_tick / config.frame_ticks + 1000));
  std::optional<CandumpWriter> dump;
  if (io.candump != nullptr) dump.emplace(*io.candump, "can0");
  if (io.log != nullptr) *io.log << kSessionLogMagic << " " << config.ToHeader() << "\n";
  const std::int64_t ns_per_tick = 1'000'000'000LL / config.clock_rate_hz;
  const std::int64_t start = MonotonicNs() + 2'000'000;  // first tick 2 ms from now
  // A step that wakes more than half a drive cycle late (the process was not scheduled) does
  // not catch up by stepping the missed ticks back to back: each SYNC would then go out before
  // the drives could answer the one before, and the TPDO watchdog (counted in cycles) would
  // trip on the session's own delay. The schedule slips by the lateness instead, so the next
  // cycle is again a full period away; motion and visuals slip together (they share the tick).
  const std::int64_t slip_after_ns = ns_per_tick * config.drive_cycle_ticks / 2;
  std::int64_t slip_ns = 0;
  std::int64_t slips = 0;
  AnswerTracker answers(config.master);
  bool drives_answering = false;  // every axis answered a SYNC: lockstep waits from then on
  std::int64_t last_sync_ns = start;
  SessionInputs in;
  in.can.reserve(256);
  in.hmd.reserve(64);
  SessionOutputs out;
  LogLines lines;
  for (std::int64_t tick = 0; !core.done(); ++tick) {
    const bool drive = core.is_drive_tick(tick);
    const bool frame = core.is_frame_tick(tick);
    if (!drive && !frame) continue;
    in.scheduled_ns = start + slip_ns + tick * ns_per_tick;
    WaitUntil(in.scheduled_ns, *io.bus, io.hmd, &in, dump ? &*dump : nullptr, source, tick);
    answers.Scan(in.can);
    if (drive && io.drive_answer_wait_ns > 0 && drives_answering && !answers.all()) {
      // Lockstep: the next SYNC goes out once the drives answered the last one (an event),
      // or, when they do not within the bound, as usual (then the TPDO watchdog sees it).
      WaitUntil(last_sync_ns + io.drive_answer_wait_ns, *io.bus, io.hmd, &in, dump ? &*dump : nullptr, source, tick,
                [&] {
                  answers.Scan(in.can);
                  return answers.all();
                });
      if (!answers.all()) drives_answering = false;
    }
    in.now_ns = MonotonicNs();
    if (in.now_ns - in.scheduled_ns > slip_after_ns) {
      slip_ns += in.now_ns - in.scheduled_ns;
      ++slips;
    }
    source.Fill(tick, drive, frame, in.now_ns, &in);
    in.stop_request = io.stop != nullptr && io.stop->load();
    out.Clear();
    core.Step(tick, in, &out);
    for (const CanFrame& f : out.can) {
      if (io.bus->Send(f) == BusStatus::kOk && dump) dump->Write(MonotonicNs() / 1000, f);
    }
    if (drive && !out.can.empty()) to_platform.OnOutput(source.input(), MonotonicNs());
    if (drive) {
      if (answers.all()) drives_answering = true;
      answers.NewSync();
      last_sync_ns = MonotonicNs();
    }
    if (io.hmd != nullptr) {
      // A refused datagram is a lost frame: the headset's staleness rules cover it.
      for (const HmdDatagram& d : out.hmd) (void)io.hmd->SendTo(io.hmd_peer, d.bytes());
      if (frame && !out.hmd.empty()) to_hmd.OnOutput(source.input(), MonotonicNs());
    }
    if (io.log != nullptr) {
      lines.clear();
      AppendInputLines(tick, in, &lines);
      for (std::string_view l : lines) *io.log << l << '\n';
      for (std::string_view l : out.log) *io.log << l << '\n';
    }
    if (io.events != nullptr) {
      for (std::string_view l : out.log)
        if (!l.empty() && l[0] == 'E') *io.events << io.events_prefix << l.substr(2) << '\n' << std::flush;
    }
    // Reset for the next step, keeping the vectors' capacity.
    in.can.clear();
    answers.InputsCleared();
    in.hmd.clear();
    in.setpoint.reset();
    in.camera.reset();
    in.stop_request = false;
  }
  if (io.log != nullptr) io.log->flush();
  SessionReport report = core.Report();
  report.schedule_slips = slips;
  report.schedule_slip_ms = static_cast<double>(slip_ns) / 1e6;
  report.can_rx_refused = io.bus->stats().rx_refused;
  if (source.has_live_input()) {
    report.has_live_input = true;
    report.input_to_platform_ms = to_platform.Summary();
    report.input_to_hmd_ms = to_hmd.Summary();
  }
  report.hmd_rx_refused = io.hmd != nullptr ? io.hmd->refused() : 0;
  return report;
}

}  // namespace pwsim::hw
