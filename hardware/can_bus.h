#pragma once
// One interface for every CAN backend, all non-blocking:
//   SocketCanBus  — AF_CAN/CAN_RAW raw socket (the real bus; EAFNOSUPPORT on kernels without CAN),
//   socket pair   — two AF_UNIX SOCK_SEQPACKET ends carrying struct can_frame (same fd semantics),
//   InProcessBus  — a broadcast hub with fault injection (drops, reordering, error frames, bus-off),
//   UdpCanBus     — cannelloni framing over UDP (udp_can_bus.h), to join two processes.
// Real-time loop rule: nothing here throws after construction; failures are statuses and counts.

#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "hardware/can_frame.h"

namespace pwsim::hw {

enum class BusStatus { kOk, kWouldBlock, kBusOff, kClosed, kError };
const char* BusStatusName(BusStatus status);

struct BusStats {
  std::uint64_t tx{0};            ///< frames sent
  std::uint64_t rx{0};            ///< frames received (error frames included)
  std::uint64_t tx_failed{0};     ///< sends refused (bus-off, full, closed)
  std::uint64_t rx_malformed{0};  ///< datagrams/records that failed to decode
  std::uint64_t error_frames{0};  ///< error frames received
  std::uint64_t rx_lost{0};       ///< gaps in a sequence number (UDP backend)
  std::uint64_t rx_refused{0};    ///< datagrams from a sender other than the peer (UDP backend)
};

class ICanBus {
 public:
  virtual ~ICanBus() = default;
  /// Queues one frame for transmission; never blocks.
  virtual BusStatus Send(const CanFrame& frame) = 0;
  /// Takes one received frame; kWouldBlock when none is waiting.
  virtual BusStatus Receive(CanFrame* frame) = 0;
  /// A file descriptor that polls readable when frames wait, or -1.
  virtual int fd() const { return -1; }
  virtual const BusStats& stats() const = 0;
  virtual std::string name() const = 0;
};

/// A receive-only view of a CAN bus: there is no write path in this type, so code that holds a
/// CanListener cannot transmit (the R-Net joystick reader, rnet_joystick.h). On a real bus the
/// guarantee that nothing leaves the machine is the controller's listen-only mode (no ACK, no
/// error frames, no transmission; docs/hardware.md), which OpenSocketCanListenOnly asks for.
class CanListener {
 public:
  virtual ~CanListener() = default;
  /// Takes one received frame; kWouldBlock when none is waiting.
  virtual BusStatus Receive(CanFrame* frame) = 0;
  virtual int fd() const { return -1; }
  virtual const BusStats& stats() const = 0;
  virtual std::string name() const = 0;
};

/// Wraps `bus` so that only its receive side is reachable (e.g. an InProcessBus endpoint).
std::unique_ptr<CanListener> ListenOnly(std::unique_ptr<ICanBus> bus);

struct ListenerOpenResult {
  std::unique_ptr<CanListener> listener;
  int error{0};
  std::string message;
};

/// A CAN_RAW socket on `iface` behind a CanListener, with a kernel receive filter that admits
/// only identifiers with (id & mask) == (want & mask) (extended-frame bit included), error
/// frames off. The caller never gets a send path. Put the interface in listen-only mode first
/// (`ip link set IFACE type can bitrate 125000 listen-only on`): that is what keeps the
/// controller itself silent.
ListenerOpenResult OpenSocketCanListenOnly(const std::string& iface, std::uint32_t want_id, std::uint32_t mask);

/// Waits until `bus` may have a frame (poll on its fd) or `timeout_ms` passes; buses without
/// an fd return immediately. Returns false on timeout.
bool WaitReadable(const ICanBus& bus, int timeout_ms);

/// Result of opening a backend: a bus, or an errno and a message that says what to do.
struct BusOpenResult {
  std::unique_ptr<ICanBus> bus;
  int error{0};          ///< errno when bus is null
  std::string message;   ///< human-readable reason when bus is null
};

/// Opens a CAN_RAW socket on `iface` (e.g. "can0", "vcan0"), non-blocking, error frames on.
/// On a kernel without CAN the result carries EAFNOSUPPORT and a message naming the stand-ins.
BusOpenResult OpenSocketCan(const std::string& iface);

/// Two connected ends of an AF_UNIX SOCK_SEQPACKET pair; each record is one struct can_frame.
std::pair<std::unique_ptr<ICanBus>, std::unique_ptr<ICanBus>> MakeSocketPairBus();

/// Fault injection knobs of the in-process bus (deterministic: seeded RNG).
struct BusFaults {
  double drop_probability{0.0};     ///< each delivery dropped with this probability
  double reorder_probability{0.0};  ///< a frame is held back and delivered after the next one
  std::uint64_t seed{1};
};

/// A broadcast hub: every frame sent by one endpoint is delivered to every other endpoint
/// (and to the sender when `loopback`). Thread-safe.
class InProcessBus {
 public:
  explicit InProcessBus(BusFaults faults = {});
  ~InProcessBus();
  InProcessBus(const InProcessBus&) = delete;
  InProcessBus& operator=(const InProcessBus&) = delete;

  /// A new node on the bus; the hub must outlive it.
  std::unique_ptr<ICanBus> Connect(const std::string& name, bool loopback = false);

  void SetFaults(const BusFaults& faults);
  /// Drops the next `n` frames sent by anyone.
  void DropNext(int n);
  /// Delivers an error frame of `error_class` to every endpoint.
  void InjectErrorFrame(std::uint32_t error_class, std::uint8_t ctrl_state = 0);
  /// Bus-off: every endpoint gets a bus-off error frame and sends fail until recovered;
  /// recovery sends a "restarted" error frame.
  void SetBusOff(bool bus_off);
  bool bus_off() const;
  std::uint64_t dropped() const;
  std::uint64_t reordered() const;

 private:
  class Endpoint;
  friend class Endpoint;
  BusStatus Broadcast(Endpoint* sender, const CanFrame& frame);
  void DeliverAllLocked(const CanFrame& frame, const Endpoint* except);
  void Detach(Endpoint* endpoint);

  mutable std::mutex mutex_;
  std::vector<Endpoint*> endpoints_;
  BusFaults faults_;
  std::mt19937_64 rng_;
  int drop_next_{0};
  bool bus_off_{false};
  bool have_held_{false};
  CanFrame held_;
  Endpoint* held_sender_{nullptr};
  std::uint64_t dropped_{0};
  std::uint64_t reordered_{0};
};

}  // namespace pwsim::hw
