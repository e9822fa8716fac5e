#include "hardware/link_auth.h"

#include <sodium.h>
#include <sys/stat.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "engine/input_error.h"

namespace pwsim::hw {

static_assert(crypto_auth_BYTES == kLinkTagBytes, "crypto_auth (HMAC-SHA-512-256) tag size");
static_assert(crypto_auth_KEYBYTES == kLinkKeyBytes, "crypto_auth key size");

namespace {

template <typename T>
void Put(std::uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof(T));  // little-endian host (x86-64, aarch64), as hmd_protocol
}
template <typename T>
T Get(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string Printable(char c) {
  if (c >= 0x20 && c < 0x7F) return std::string("'") + c + "'";
  static const char* kHex = "0123456789abcdef";
  const auto u = static_cast<unsigned char>(c);
  return std::string("byte 0x") + kHex[u >> 4] + kHex[u & 15];
}

}  // namespace

LinkKey ReadLinkKeyFile(const std::string& path, std::string* warning) {
  constexpr const char* kField = "link key";
  constexpr const char* kExpected =
      "64 hexadecimal digits (a 32-byte key) and at most one final newline; make one with "
      "(umask 077; head -c 32 /dev/urandom | od -An -v -tx1 | tr -d ' \\n' > FILE)";
  if (warning != nullptr) warning->clear();
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, 0, kField, "a readable key file", "no such file");
  if (!S_ISREG(st.st_mode)) throw InputError(path, 0, kField, "a regular file", "another kind of file");
  if (st.st_size > 4096)
    throw InputError(path, 0, kField, kExpected, std::to_string(st.st_size) + " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, kField, "a readable key file", "it cannot be opened");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t end = text.size();
  if (end > 0 && text[end - 1] == '\n') --end;
  if (end > 0 && text[end - 1] == '\r') --end;
  for (std::size_t i = 0; i < end; ++i) {
    if (HexValue(text[i]) < 0) {
      const bool newline = text[i] == '\n';
      throw InputError(path, newline ? 2 : 1, kField, kExpected,
                       newline ? std::string("a second line")
                               : Printable(text[i]) + " at column " + std::to_string(i + 1));
    }
  }
  if (end != 2 * kLinkKeyBytes)
    throw InputError(path, 1, kField, kExpected, std::to_string(end) + " hexadecimal digits");
  LinkKey key;
  bool all_zero = true;
  for (std::size_t i = 0; i < kLinkKeyBytes; ++i) {
    key.bytes[i] = static_cast<std::uint8_t>(HexValue(text[2 * i]) * 16 + HexValue(text[2 * i + 1]));
    all_zero = all_zero && key.bytes[i] == 0;
  }
  if (all_zero) throw InputError(path, 1, kField, "a random key", "all zeros");
  if (sodium_init() < 0) throw InputError(path, 0, kField, "libsodium to start", "sodium_init failed");
  if (warning != nullptr && (st.st_mode & (S_IRGRP | S_IROTH)) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof(mode), "%04o", static_cast<unsigned>(st.st_mode & 07777));
    *warning = path + ": the link key is readable by " +
               ((st.st_mode & S_IROTH) != 0 ? std::string("every user") : std::string("its group")) +
               " (mode " + mode + "): anyone who can read it can forge datagrams; chmod 600 " + path;
  }
  return key;
}

std::uint64_t NewLinkEpoch() {
  static std::atomic<std::uint64_t> last{0};
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  std::uint64_t epoch = static_cast<std::uint64_t>(ts.tv_sec) * 1'000'000'000ULL + static_cast<std::uint64_t>(ts.tv_nsec);
  std::uint64_t previous = last.load();
  for (;;) {
    const std::uint64_t next = std::max(epoch, previous + 1);
    if (last.compare_exchange_weak(previous, next)) return next;
  }
}

LinkAuth::LinkAuth(const LinkKey& key, LinkKind kind, LinkRole role, std::uint64_t epoch)
    : key_(key), kind_(kind), role_(role), epoch_(epoch == 0 ? 1 : epoch), ready_(sodium_init() >= 0) {}

std::size_t LinkAuth::SealType(LinkAuthType type, std::span<const std::uint8_t> payload,
                               std::span<std::uint8_t> out) {
  const std::size_t size = kLinkAuthOverhead + payload.size();
  if (!ready_ || payload.size() > kLinkMaxPayload || out.size() < size) return 0;
  std::uint8_t* p = out.data();
  Put(p + 0, kLinkAuthMagic);
  p[4] = kLinkAuthVersion;
  p[5] = static_cast<std::uint8_t>(kind_);
  p[6] = static_cast<std::uint8_t>(role_);
  p[7] = static_cast<std::uint8_t>(type);
  Put(p + 8, epoch_);
  Put(p + 16, peer_epoch_);
  Put(p + 24, ++tx_counter_);
  if (!payload.empty()) std::memmove(p + kLinkAuthHeaderSize, payload.data(), payload.size());
  const std::size_t body = kLinkAuthHeaderSize + payload.size();
  crypto_auth(p + body, p, body, key_.bytes.data());
  ++counters_.sealed;
  return size;
}

std::size_t LinkAuth::Seal(std::span<const std::uint8_t> payload, std::span<std::uint8_t> out) {
  return SealType(LinkAuthType::kData, payload, out);
}

std::size_t LinkAuth::SealHello(std::span<std::uint8_t> out) {
  const std::size_t n = SealType(LinkAuthType::kHello, {}, out);
  if (n > 0) ++counters_.hellos_sent;
  return n;
}

bool LinkAuth::TakeCounter(std::uint64_t c) {
  if (c == 0) return false;
  if (c > rx_max_) {
    const std::uint64_t shift = c - rx_max_;
    rx_window_ = shift >= kReplayWindow ? 0 : rx_window_ << shift;
    rx_window_ |= 1;
    rx_max_ = c;
    return true;
  }
  const std::uint64_t back = rx_max_ - c;
  if (back >= kReplayWindow) return false;  // too old to tell: refused
  const std::uint64_t bit = std::uint64_t{1} << back;
  if ((rx_window_ & bit) != 0) return false;
  rx_window_ |= bit;
  return true;
}

LinkAuth::Verdict LinkAuth::Open(std::span<const std::uint8_t> in, std::int64_t now_ns,
                                 std::span<const std::uint8_t>* payload, bool* answer_hello) {
  *answer_hello = false;
  if (!ready_ || in.size() < kLinkAuthOverhead || in.size() > kLinkAuthOverhead + kLinkMaxPayload) {
    ++counters_.malformed;
    return Verdict::kDropped;
  }
  const std::uint8_t* p = in.data();
  const auto type = static_cast<LinkAuthType>(p[7]);
  if (Get<std::uint32_t>(p) != kLinkAuthMagic || p[4] != kLinkAuthVersion ||
      p[5] != static_cast<std::uint8_t>(kind_) ||
      (p[6] != static_cast<std::uint8_t>(LinkRole::kSession) && p[6] != static_cast<std::uint8_t>(LinkRole::kPeer)) ||
      p[6] == static_cast<std::uint8_t>(role_) ||
      (type != LinkAuthType::kData && type != LinkAuthType::kHello) ||
      (type == LinkAuthType::kHello && in.size() != kLinkAuthOverhead)) {
    ++counters_.malformed;
    return Verdict::kDropped;
  }
  const std::size_t body = in.size() - kLinkTagBytes;
  if (crypto_auth_verify(p + body, p, body, key_.bytes.data()) != 0) {
    ++counters_.bad_tag;
    return Verdict::kDropped;
  }
  // Authentic from here on (a key holder sent it), but maybe old.
  const auto epoch = Get<std::uint64_t>(p + 8);
  const auto echo = Get<std::uint64_t>(p + 16);
  const auto counter = Get<std::uint64_t>(p + 24);
  peer_epoch_ = std::max(peer_epoch_, epoch);
  const bool fresh = echo == epoch_;
  if (!fresh && (!hello_sent_ || now_ns - last_hello_ns_ >= kHelloIntervalNs || now_ns < last_hello_ns_)) {
    *answer_hello = true;  // the sender does not know this end's epoch (yet)
    hello_sent_ = true;
    last_hello_ns_ = now_ns;
  }
  if (type == LinkAuthType::kHello) {
    ++counters_.hellos;
    return Verdict::kHello;
  }
  if (!fresh) {
    ++counters_.unconfirmed;
    return Verdict::kDropped;
  }
  if (epoch < rx_epoch_) {
    ++counters_.replayed;  // an earlier life of the peer
    return Verdict::kDropped;
  }
  if (epoch > rx_epoch_) {  // the peer (re)started: its counters start over
    if (counter == 0) {
      ++counters_.replayed;
      return Verdict::kDropped;
    }
    if (rx_epoch_ != 0) ++counters_.peer_restarts;
    rx_epoch_ = epoch;
    rx_max_ = 0;
    rx_window_ = 0;
  }
  if (!TakeCounter(counter)) {
    ++counters_.replayed;
    return Verdict::kDropped;
  }
  ++counters_.accepted;
  *payload = in.subspan(kLinkAuthHeaderSize, body - kLinkAuthHeaderSize);
  return Verdict::kData;
}

}  // namespace pwsim::hw
