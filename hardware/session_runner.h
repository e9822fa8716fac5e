#pragma once
// The real-time loop around SessionCore: maps CLOCK_MONOTONIC to engine ticks, sleeps until
// each tick that has platform or visual work, timestamps every CAN frame and HMD datagram as
// it arrives (ppoll between ticks), steps the core, sends its outputs and writes the log.
// A step woken more than half a drive cycle late shifts the schedule by its lateness (counted
// in the report as schedule_slips) instead of stepping the missed ticks back to back.
// Optionally (RunnerIo::drive_answer_wait_ns) each SYNC waits for the drives' answer to the
// previous one: a handshake for hosts where the simulated drives share busy cores.

#include <atomic>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "hardware/can_bus.h"
#include "hardware/input_latency.h"
#include "hardware/session.h"
#include "hardware/udp_socket.h"

namespace pwsim::hw {

struct SessionStreams {
  /// The MCA's pose command per drive tick (index tick / drive_cycle_ticks); held at the last
  /// value after the end. The core turns it into actuator setpoints (inverse kinematics).
  std::vector<mca::DofArray> setpoints;
  /// Camera pose per frame tick (index tick / frame_ticks); held after the end.
  std::vector<Pose> cameras;
  /// The cueing that made the setpoints ("washout", "mpc"; mca::McaAlgorithmName), for the record.
  std::string mca_algorithm;
};

/// Where each step's setpoint and camera pose come from: precomputed streams (a scene, a
/// measured trial), or a live drive (a joystick through a vehicle model, stepped up to the
/// tick when the step runs: car_drive_source.h). Whatever it is, the core logs the setpoint
/// and the camera pose as inputs, so a live session replays bit for bit like any other.
class SessionSource {
 public:
  virtual ~SessionSource() = default;
  /// Sets in->setpoint on drive ticks and in->camera on frame ticks for `tick`, at `now_ns`.
  virtual void Fill(std::int64_t tick, bool drive, bool frame, std::int64_t now_ns, SessionInputs* in) = 0;
  /// The live input reading the last Fill used (seq 0: none, e.g. precomputed streams). The
  /// runner measures input -> platform command and input -> HMD frame latency from it.
  virtual InputStamp input() const { return {}; }
  /// True when the source has a live input (the report then carries the latencies).
  virtual bool has_live_input() const { return false; }
  /// A live input that arrives as a stream (a bus) may expose a file descriptor: the runner
  /// then waits on it between steps too and calls TakeInput as it becomes readable, so each
  /// reading is stamped when it arrived rather than at the next step (`next_tick`: the step
  /// the runner is waiting for). Default: none.
  virtual int input_fd() const { return -1; }
  virtual void TakeInput(std::int64_t /*next_tick*/, std::int64_t /*now_ns*/) {}
};

/// Precomputed streams as a source.
class StreamsSource final : public SessionSource {
 public:
  StreamsSource(const SessionConfig& config, const SessionStreams& streams) : config_(config), streams_(streams) {}
  void Fill(std::int64_t tick, bool drive, bool frame, std::int64_t now_ns, SessionInputs* in) override;

 private:
  const SessionConfig& config_;
  const SessionStreams& streams_;
};

struct RunnerIo {
  ICanBus* bus{nullptr};
  UdpSocket* hmd{nullptr};      ///< may be null when the HMD is not required; set
                                ///< AcceptOnlyFrom(hmd_peer) so that no one else reaches the log
  UdpAddress hmd_peer;
  std::ostream* log{nullptr};   ///< session log (replayable); may be null
  std::ostream* candump{nullptr};  ///< candump -l style log of all bus traffic; may be null
  /// Each event line of the core (E lines: supervisor and master states, drive events) as it
  /// happens, after `events_prefix` (other processes can wait for them); may be null.
  std::ostream* events{nullptr};
  std::string events_prefix;
  const std::atomic<bool>* stop{nullptr};  ///< set by a signal handler: graceful soft stop
  int rt_priority{0};           ///< > 0: try SCHED_FIFO at this priority and lock memory
  /// > 0: lockstep with the drives for hosts without real-time scheduling: once every axis
  /// answered a SYNC, each drive step first waits (up to this long after the last SYNC) for
  /// their TPDO1 answering it. A late answer then slips the schedule instead of tripping the
  /// TPDO watchdog; a drive that does not answer within the bound ends the waiting (until
  /// it answers again) and the watchdog reacts as in strict real time (0, the default).
  std::int64_t drive_answer_wait_ns{0};
};

/// Tries SCHED_FIFO at `priority` and mlockall; returns "" or why it was refused.
std::string EnterRealtime(int priority);

/// Runs until the core is done. Returns the report.
SessionReport RunSession(const SessionConfig& config, const SessionStreams& streams,
                         const RunnerIo& io);
/// The same with any source; with a live input the report carries joystick -> platform and
/// joystick -> HMD latencies (input_latency.h).
SessionReport RunSession(const SessionConfig& config, SessionSource& source, const RunnerIo& io);

}  // namespace pwsim::hw
