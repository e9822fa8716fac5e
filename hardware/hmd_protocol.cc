#include "hardware/hmd_protocol.h"

#include <sys/random.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

namespace pwsim::hw {
namespace {

class Writer {
 public:
  explicit Writer(std::uint8_t* p) : p_(p) {}
  template <typename T>
  void Put(T v) {
    std::memcpy(p_ + n_, &v, sizeof(T));  // little-endian host (x86-64, aarch64)
    n_ += sizeof(T);
  }
  void PutPose(const Pose& pose) {
    for (double v : pose.p) Put(v);
    for (double v : pose.q) Put(v);
  }
  std::size_t size() const { return n_; }

 private:
  std::uint8_t* p_;
  std::size_t n_{0};
};

class Reader {
 public:
  explicit Reader(const std::uint8_t* p) : p_(p) {}
  template <typename T>
  T Get() {
    T v;
    std::memcpy(&v, p_ + n_, sizeof(T));
    n_ += sizeof(T);
    return v;
  }
  bool GetPose(Pose* pose) {
    bool finite = true;
    for (double& v : pose->p) finite = finite && std::isfinite(v = Get<double>());
    for (double& v : pose->q) finite = finite && std::isfinite(v = Get<double>());
    return finite;
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_{0};
};

std::size_t BodySize(HmdType type) {
  switch (type) {
    case HmdType::kCameraPose: return 88;
    case HmdType::kHeadPose: return 80;
    case HmdType::kPing: return 8;
    case HmdType::kPong: return 24;
    case HmdType::kBye: return 0;
    case HmdType::kHello: return 8;
  }
  return 0;
}

HmdType TypeOf(const HmdBody& body) {
  return static_cast<HmdType>(body.index() + 1);
}

}  // namespace

static_assert(std::numeric_limits<double>::is_iec559, "f64 on the wire is IEEE 754");

std::size_t EncodeHmd(const HmdMessage& m, std::span<std::uint8_t> out) {
  const HmdType type = TypeOf(m.body);
  const std::size_t size = kHmdHeaderSize + BodySize(type);
  if (out.size() < size) return 0;
  Writer w(out.data());
  w.Put(kHmdMagic);
  w.Put(kHmdVersion);
  w.Put(static_cast<std::uint16_t>(type));
  w.Put(m.header.seq);
  w.Put(m.header.session);
  w.Put(m.header.t_send_ns);
  if (const auto* c = std::get_if<CameraPoseMsg>(&m.body)) {
    w.Put(c->tick);
    w.Put(c->frame);
    w.PutPose(c->camera);
    w.Put(c->platform[0]);
    w.Put(c->platform[1]);
  } else if (const auto* h = std::get_if<HeadPoseMsg>(&m.body)) {
    w.Put(h->t_sample_ns);
    w.PutPose(h->head);
    w.Put(h->last_frame);
    w.Put(h->t_frame_rx_ns);
  } else if (const auto* p = std::get_if<PingMsg>(&m.body)) {
    w.Put(p->t0);
  } else if (const auto* q = std::get_if<PongMsg>(&m.body)) {
    w.Put(q->t0);
    w.Put(q->t1);
    w.Put(q->t2);
  } else if (const auto* hello = std::get_if<HelloMsg>(&m.body)) {
    w.Put(hello->stream);
    w.Put(hello->echo);
  }
  return w.size();
}

CodecError DecodeHmd(std::span<const std::uint8_t> in, HmdMessage* message) {
  if (in.size() < kHmdHeaderSize) return CodecError::kTruncated;
  Reader r(in.data());
  if (r.Get<std::uint32_t>() != kHmdMagic) return CodecError::kBadSyntax;
  if (r.Get<std::uint16_t>() != kHmdVersion) return CodecError::kBadVersion;
  const std::uint16_t type = r.Get<std::uint16_t>();
  if (type < 1 || type > 6) return CodecError::kBadOpcode;
  HmdMessage m;
  m.header.type = static_cast<HmdType>(type);
  const std::size_t size = kHmdHeaderSize + BodySize(m.header.type);
  if (in.size() < size) return CodecError::kTruncated;
  if (in.size() > size) return CodecError::kTrailing;
  m.header.seq = r.Get<std::uint32_t>();
  m.header.session = r.Get<std::uint32_t>();
  m.header.t_send_ns = r.Get<std::int64_t>();
  switch (m.header.type) {
    case HmdType::kCameraPose: {
      CameraPoseMsg c;
      c.tick = r.Get<std::int64_t>();
      c.frame = r.Get<std::int64_t>();
      bool ok = r.GetPose(&c.camera);
      c.platform[0] = r.Get<double>();
      c.platform[1] = r.Get<double>();
      ok = ok && std::isfinite(c.platform[0]) && std::isfinite(c.platform[1]);
      if (!ok) return CodecError::kBadSyntax;
      m.body = c;
      break;
    }
    case HmdType::kHeadPose: {
      HeadPoseMsg h;
      h.t_sample_ns = r.Get<std::int64_t>();
      if (!r.GetPose(&h.head)) return CodecError::kBadSyntax;
      h.last_frame = r.Get<std::int64_t>();
      h.t_frame_rx_ns = r.Get<std::int64_t>();
      m.body = h;
      break;
    }
    case HmdType::kPing: m.body = PingMsg{r.Get<std::int64_t>()}; break;
    case HmdType::kPong: {
      PongMsg p;
      p.t0 = r.Get<std::int64_t>();
      p.t1 = r.Get<std::int64_t>();
      p.t2 = r.Get<std::int64_t>();
      m.body = p;
      break;
    }
    case HmdType::kBye: m.body = ByeMsg{}; break;
    case HmdType::kHello: {
      HelloMsg h;
      h.stream = r.Get<std::uint32_t>();
      h.echo = r.Get<std::uint32_t>();
      if (h.stream == 0) return CodecError::kBadSyntax;
      m.body = h;
      break;
    }
  }
  *message = m;
  return CodecError::kOk;
}

std::int64_t SaturatingSub(std::int64_t a, std::int64_t b) {
  std::int64_t r = 0;
  if (!__builtin_sub_overflow(a, b, &r)) return r;
  return b < 0 ? std::numeric_limits<std::int64_t>::max() : std::numeric_limits<std::int64_t>::min();
}

ClockOffsetEstimator::ClockOffsetEstimator(std::size_t window) : ring_(std::max<std::size_t>(window, 1)) {}

void ClockOffsetEstimator::AddSample(std::int64_t t0, std::int64_t t1, std::int64_t t2,
                                     std::int64_t t3) {
  // Reject samples whose spans do not fit comfortably (hostile or corrupt timestamps).
  constexpr std::int64_t kMaxSpan = std::int64_t{1} << 61;
  const std::int64_t up = SaturatingSub(t1, t0);
  const std::int64_t down = SaturatingSub(t2, t3);
  const std::int64_t local = SaturatingSub(t3, t0);
  const std::int64_t remote = SaturatingSub(t2, t1);
  for (std::int64_t v : {up, down, local, remote})
    if (v > kMaxSpan || v < -kMaxSpan) return;
  const std::int64_t rtt = local - remote;
  if (rtt < 0) return;  // inconsistent (clock jump): ignore
  const std::int64_t offset = up / 2 + down / 2 + (up % 2 + down % 2) / 2;
  if (count_ < ring_.size()) {
    ring_[(head_ + count_) % ring_.size()] = {offset, rtt};
    ++count_;
  } else {  // full: the newest replaces the oldest
    ring_[head_] = {offset, rtt};
    head_ = (head_ + 1) % ring_.size();
  }
  ++total_;
}

const ClockOffsetEstimator::Sample* ClockOffsetEstimator::Best() const {
  const Sample* best = nullptr;
  for (std::size_t i = 0; i < count_; ++i) {
    const Sample& s = ring_[(head_ + i) % ring_.size()];
    if (best == nullptr || s.rtt < best->rtt) best = &s;
  }
  return best;
}

std::int64_t ClockOffsetEstimator::offset_ns() const {
  const Sample* best = Best();
  return best == nullptr ? 0 : best->offset;
}

std::int64_t ClockOffsetEstimator::rtt_ns() const {
  const Sample* best = Best();
  return best == nullptr ? 0 : best->rtt;
}

std::uint32_t NewHmdStreamId() {
  std::uint32_t id = 0;
  while (id == 0) {
    if (::getrandom(&id, sizeof(id), 0) != static_cast<ssize_t>(sizeof(id))) {
      id = static_cast<std::uint32_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
           (static_cast<std::uint32_t>(::getpid()) << 16);  // no entropy source: still new per start
    }
  }
  return id;
}

bool HmdReceiveFilter::TakeHelloWanted() {
  const bool wanted = hello_wanted_;
  hello_wanted_ = false;
  return wanted;
}

bool HmdReceiveFilter::Accept(const HmdMessage& m, std::int64_t rx_ns,
                              const ClockOffsetEstimator& offset) {
  const auto t = static_cast<std::size_t>(m.header.type);
  if (t >= last_seq_.size()) {
    ++counters_.malformed;
    return false;
  }
  if (const auto* hello = std::get_if<HelloMsg>(&m.body)) {
    if (own_stream_ == 0 || hello->stream == 0) return false;  // this end runs no streams
    heard_stream_ = hello->stream;
    if (hello->echo != own_stream_) return true;  // it does not know us (yet): tell it
    if (hello->stream == peer_stream_) return false;  // confirmed already: the exchange ends
    if (peer_stream_ != 0) ++counters_.restarts;
    peer_stream_ = hello->stream;
    last_seq_.fill(-1);  // a new stream counts from 0
    last_seq_[t] = m.header.seq;
    hello_wanted_ = false;
    ++counters_.accepted;
    return true;
  }
  if (own_stream_ != 0 && m.header.session != 0) heard_stream_ = m.header.session;
  if (peer_stream_ != 0 && m.header.session != peer_stream_) {
    ++counters_.other_stream;  // a restarted (or another) sender that has not said hello
    if (!wanted_before_ || rx_ns - last_wanted_ns_ >= 100'000'000 || rx_ns < last_wanted_ns_) {
      hello_wanted_ = true;
      wanted_before_ = true;
      last_wanted_ns_ = rx_ns;
    }
    return false;
  }
  if (last_seq_[t] >= 0 && static_cast<std::int64_t>(m.header.seq) <= last_seq_[t]) {
    ++counters_.out_of_order;
    return false;
  }
  if (offset.valid() && m.header.type != HmdType::kPong && m.header.type != HmdType::kPing) {
    const std::int64_t sent_local = SaturatingSub(m.header.t_send_ns, offset.offset_ns());
    if (SaturatingSub(rx_ns, sent_local) > stale_after_ns_) {
      ++counters_.stale;
      last_seq_[t] = m.header.seq;  // newer ones are still welcome
      return false;
    }
  }
  last_seq_[t] = m.header.seq;
  ++counters_.accepted;
  return true;
}

// --- poses ---------------------------------------------------------------------------------
namespace {
std::array<double, 4> QuatMul(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  return {a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
          a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
          a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
          a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}
std::array<double, 3> Rotate(const std::array<double, 4>& q, const std::array<double, 3>& v) {
  const std::array<double, 4> p{v[0], v[1], v[2], 0.0};
  const std::array<double, 4> qc{-q[0], -q[1], -q[2], q[3]};
  const auto r = QuatMul(QuatMul(q, p), qc);
  return {r[0], r[1], r[2]};
}
}  // namespace

Pose ComposePose(const Pose& a, const Pose& b) {
  Pose c;
  const auto rb = Rotate(a.q, b.p);
  for (std::size_t i = 0; i < 3; ++i) c.p[i] = a.p[i] + rb[i];
  c.q = QuatMul(a.q, b.q);
  return c;
}

Pose InversePose(const Pose& a) {
  Pose inv;
  inv.q = {-a.q[0], -a.q[1], -a.q[2], a.q[3]};
  const auto r = Rotate(inv.q, a.p);
  inv.p = {-r[0], -r[1], -r[2]};
  return inv;
}

Pose PlatformPose(double yaw, double rail) {
  Pose p;
  p.q = {0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw)};
  p.p = {rail * std::cos(yaw), rail * std::sin(yaw), 0.0};
  return p;
}

Pose CompensateHeadPose(const Pose& head_in_room, double yaw, double rail) {
  return ComposePose(InversePose(PlatformPose(yaw, rail)), head_in_room);
}

}  // namespace pwsim::hw
