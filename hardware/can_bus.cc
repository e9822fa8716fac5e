#include "hardware/can_bus.h"

#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

namespace pwsim::hw {

static_assert(sizeof(struct can_frame) == kRawFrameSize, "struct can_frame layout");
static_assert(CAN_EFF_FLAG == kCanEffFlag && CAN_RTR_FLAG == kCanRtrFlag &&
              CAN_ERR_FLAG == kCanErrFlag);

const char* BusStatusName(BusStatus status) {
  switch (status) {
    case BusStatus::kOk: return "ok";
    case BusStatus::kWouldBlock: return "would block";
    case BusStatus::kBusOff: return "bus-off";
    case BusStatus::kClosed: return "closed";
    case BusStatus::kError: return "error";
  }
  return "?";
}

bool WaitReadable(const ICanBus& bus, int timeout_ms) {
  if (bus.fd() < 0) return true;
  pollfd p{bus.fd(), POLLIN, 0};
  return ::poll(&p, 1, timeout_ms) > 0;
}

namespace {

/// A bus over a datagram-like fd whose records are struct can_frame (CAN_RAW or SEQPACKET).
class FdFrameBus final : public ICanBus {
 public:
  FdFrameBus(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}
  ~FdFrameBus() override {
    if (fd_ >= 0) ::close(fd_);
  }
  FdFrameBus(const FdFrameBus&) = delete;
  FdFrameBus& operator=(const FdFrameBus&) = delete;

  BusStatus Send(const CanFrame& frame) override {
    std::array<std::uint8_t, kRawFrameSize> raw{};
    EncodeRawFrame(frame, raw);
    const ssize_t n = ::send(fd_, raw.data(), raw.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n == static_cast<ssize_t>(raw.size())) {
      ++stats_.tx;
      return BusStatus::kOk;
    }
    ++stats_.tx_failed;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS))
      return BusStatus::kWouldBlock;
    if (n < 0 && errno == ENETDOWN) return BusStatus::kBusOff;
    if (n < 0 && (errno == EPIPE || errno == ECONNRESET)) return BusStatus::kClosed;
    return BusStatus::kError;
  }

  BusStatus Receive(CanFrame* frame) override {
    for (;;) {
      std::array<std::uint8_t, 80> raw{};
      const ssize_t n = ::recv(fd_, raw.data(), raw.size(), MSG_DONTWAIT);
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK) return BusStatus::kWouldBlock;
        if (errno == EINTR) continue;
        return BusStatus::kError;
      }
      if (n == 0) return BusStatus::kClosed;
      CanFrame f;
      if (DecodeRawFrame(std::span<const std::uint8_t>(raw.data(), static_cast<std::size_t>(n)),
                         &f) != CodecError::kOk) {
        ++stats_.rx_malformed;
        continue;
      }
      ++stats_.rx;
      if (f.error()) ++stats_.error_frames;
      *frame = f;
      return BusStatus::kOk;
    }
  }

  int fd() const override { return fd_; }
  const BusStats& stats() const override { return stats_; }
  std::string name() const override { return name_; }

 private:
  int fd_;
  std::string name_;
  BusStats stats_;
};

}  // namespace

BusOpenResult OpenSocketCan(const std::string& iface) {
  BusOpenResult result;
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) {
    result.error = errno;
    if (result.error == EAFNOSUPPORT) {
      result.message =
          "SocketCAN is not available: socket(PF_CAN, SOCK_RAW, CAN_RAW) failed with "
          "EAFNOSUPPORT (errno " + std::to_string(result.error) +
          "): this kernel has no CAN protocol family (no 'can'/'can_raw' module). Use "
          "--can udp:HOST:PORT with `pwsim platform-sim`, or run on a machine with SocketCAN.";
    } else {
      result.message = std::string("socket(PF_CAN) failed: ") + std::strerror(result.error);
    }
    return result;
  }
  if (iface.empty() || iface.size() >= IFNAMSIZ) {
    ::close(fd);
    result.error = EINVAL;
    result.message = "SocketCAN interface name '" + iface + "' is empty or too long";
    return result;
  }
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, iface.c_str(), iface.size());
  if (::ioctl(fd, SIOCGIFINDEX, &ifr) < 0) {
    result.error = errno;
    result.message = "SocketCAN interface '" + iface + "' not found: " + std::strerror(errno);
    ::close(fd);
    return result;
  }
  const can_err_mask_t err_mask = CAN_ERR_MASK;
  ::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof(err_mask));
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) < 0) {
    result.error = errno;
    result.message = "bind to SocketCAN interface '" + iface + "' failed: " + std::strerror(errno);
    ::close(fd);
    return result;
  }
  result.bus = std::make_unique<FdFrameBus>(fd, "socketcan:" + iface);
  return result;
}

namespace {

class ListenOnlyBus final : public CanListener {
 public:
  explicit ListenOnlyBus(std::unique_ptr<ICanBus> bus) : bus_(std::move(bus)) {}
  BusStatus Receive(CanFrame* frame) override { return bus_->Receive(frame); }
  int fd() const override { return bus_->fd(); }
  const BusStats& stats() const override { return bus_->stats(); }
  std::string name() const override { return bus_->name() + " (listen-only)"; }

 private:
  std::unique_ptr<ICanBus> bus_;  // held, never sent on
};

}  // namespace

std::unique_ptr<CanListener> ListenOnly(std::unique_ptr<ICanBus> bus) {
  return std::make_unique<ListenOnlyBus>(std::move(bus));
}

ListenerOpenResult OpenSocketCanListenOnly(const std::string& iface, std::uint32_t want_id, std::uint32_t mask) {
  ListenerOpenResult result;
  BusOpenResult opened = OpenSocketCan(iface);
  if (!opened.bus) {
    result.error = opened.error;
    result.message = opened.message;
    return result;
  }
  const int fd = opened.bus->fd();
  can_filter filter{};
  filter.can_id = (want_id & mask) | CAN_EFF_FLAG;
  filter.can_mask = mask | CAN_EFF_FLAG;  // remote frames pass: the reader counts them as garbage
  const can_err_mask_t no_errors = 0;
  if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof(filter)) != 0 ||
      ::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &no_errors, sizeof(no_errors)) != 0) {
    result.error = errno;
    result.message = "SocketCAN filter on '" + iface + "' refused: " + std::strerror(errno);
    return result;
  }
  result.listener = ListenOnly(std::move(opened.bus));
  return result;
}

std::pair<std::unique_ptr<ICanBus>, std::unique_ptr<ICanBus>> MakeSocketPairBus() {
  int sv[2] = {-1, -1};
  if (::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, sv) != 0) {
    return {nullptr, nullptr};
  }
  return {std::make_unique<FdFrameBus>(sv[0], "socketpair:a"),
          std::make_unique<FdFrameBus>(sv[1], "socketpair:b")};
}

// ---------------------------------------------------------------------------------------------
class InProcessBus::Endpoint final : public ICanBus {
 public:
  Endpoint(InProcessBus* hub, std::string name, bool loopback)
      : hub_(hub), name_(std::move(name)), loopback_(loopback) {}
  ~Endpoint() override { hub_->Detach(this); }
  Endpoint(const Endpoint&) = delete;
  Endpoint& operator=(const Endpoint&) = delete;

  BusStatus Send(const CanFrame& frame) override {
    const BusStatus status = hub_->Broadcast(this, frame);
    std::lock_guard<std::mutex> lock(hub_->mutex_);
    if (status == BusStatus::kOk) {
      ++stats_.tx;
    } else {
      ++stats_.tx_failed;
    }
    return status;
  }
  BusStatus Receive(CanFrame* frame) override {
    std::lock_guard<std::mutex> lock(hub_->mutex_);
    if (queue_.empty()) return BusStatus::kWouldBlock;
    *frame = queue_.front();
    queue_.pop_front();
    ++stats_.rx;
    if (frame->error()) ++stats_.error_frames;
    return BusStatus::kOk;
  }
  const BusStats& stats() const override { return stats_; }
  std::string name() const override { return "inproc:" + name_; }

  InProcessBus* hub_;
  std::string name_;
  bool loopback_;
  std::deque<CanFrame> queue_;  // guarded by hub_->mutex_
  BusStats stats_;
};

InProcessBus::InProcessBus(BusFaults faults) : faults_(faults), rng_(faults.seed) {}
InProcessBus::~InProcessBus() = default;

std::unique_ptr<ICanBus> InProcessBus::Connect(const std::string& name, bool loopback) {
  auto endpoint = std::make_unique<Endpoint>(this, name, loopback);
  std::lock_guard<std::mutex> lock(mutex_);
  endpoints_.push_back(endpoint.get());
  return endpoint;
}

void InProcessBus::Detach(Endpoint* endpoint) {
  std::lock_guard<std::mutex> lock(mutex_);
  endpoints_.erase(std::remove(endpoints_.begin(), endpoints_.end(), endpoint), endpoints_.end());
  if (held_sender_ == endpoint) held_sender_ = nullptr;
}

void InProcessBus::SetFaults(const BusFaults& faults) {
  std::lock_guard<std::mutex> lock(mutex_);
  faults_ = faults;
  rng_.seed(faults.seed);
}

void InProcessBus::DropNext(int n) {
  std::lock_guard<std::mutex> lock(mutex_);
  drop_next_ += n;
}

void InProcessBus::DeliverAllLocked(const CanFrame& frame, const Endpoint* except) {
  for (Endpoint* e : endpoints_) {
    if (e == except && !e->loopback_) continue;
    e->queue_.push_back(frame);
  }
}

void InProcessBus::InjectErrorFrame(std::uint32_t error_class, std::uint8_t ctrl_state) {
  std::lock_guard<std::mutex> lock(mutex_);
  DeliverAllLocked(MakeErrorFrame(error_class, ctrl_state), nullptr);
}

void InProcessBus::SetBusOff(bool bus_off) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (bus_off == bus_off_) return;
  bus_off_ = bus_off;
  DeliverAllLocked(MakeErrorFrame(bus_off ? kCanErrBusOff : kCanErrRestarted), nullptr);
}

bool InProcessBus::bus_off() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bus_off_;
}
std::uint64_t InProcessBus::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}
std::uint64_t InProcessBus::reordered() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return reordered_;
}

BusStatus InProcessBus::Broadcast(Endpoint* sender, const CanFrame& frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (bus_off_) return BusStatus::kBusOff;
  if (!IsValidFrame(frame)) return BusStatus::kError;
  if (drop_next_ > 0) {
    --drop_next_;
    ++dropped_;
    return BusStatus::kOk;  // lost on the wire: the sender cannot tell
  }
  std::uniform_real_distribution<double> u(0.0, 1.0);
  if (faults_.drop_probability > 0.0 && u(rng_) < faults_.drop_probability) {
    ++dropped_;
    return BusStatus::kOk;
  }
  if (!have_held_ && faults_.reorder_probability > 0.0 && u(rng_) < faults_.reorder_probability) {
    have_held_ = true;
    held_ = frame;
    held_sender_ = sender;
    ++reordered_;
    return BusStatus::kOk;
  }
  DeliverAllLocked(frame, sender);
  if (have_held_) {
    have_held_ = false;
    DeliverAllLocked(held_, held_sender_);
  }
  return BusStatus::kOk;
}

}  // namespace pwsim::hw
