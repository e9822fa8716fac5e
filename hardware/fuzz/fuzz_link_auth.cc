// libFuzzer target: the authenticated links' datagram check (link_auth.h). Arbitrary bytes are
// never taken (no valid tag can be guessed); the same bytes sealed as a payload open to
// themselves exactly once, and a copy with any byte changed is refused.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "hardware/link_auth.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pwsim::hw;
  LinkKey key;
  for (std::size_t i = 0; i < key.bytes.size(); ++i) key.bytes[i] = static_cast<std::uint8_t>(3 * i + 1);
  LinkAuth session(key, LinkKind::kHmd, LinkRole::kSession, 1000);
  LinkAuth peer(key, LinkKind::kHmd, LinkRole::kPeer, 2000);
  std::span<const std::uint8_t> payload;
  bool answer = false;
  if (peer.Open(std::span<const std::uint8_t>(data, size), 0, &payload, &answer) == LinkAuth::Verdict::kData) std::abort();
  // Both ends hear each other's epoch, then the input travels as a payload.
  std::vector<std::uint8_t> buffer(kLinkAuthOverhead + kLinkMaxPayload);
  std::size_t n = session.SealHello(buffer);
  (void)peer.Open(std::span<const std::uint8_t>(buffer.data(), n), 0, &payload, &answer);
  n = peer.SealHello(buffer);
  (void)session.Open(std::span<const std::uint8_t>(buffer.data(), n), 0, &payload, &answer);
  const std::size_t len = size < kLinkMaxPayload ? size : kLinkMaxPayload;
  n = session.Seal(std::span<const std::uint8_t>(data, len), buffer);
  if (n != kLinkAuthOverhead + len) std::abort();
  std::vector<std::uint8_t> altered(buffer.begin(), buffer.begin() + static_cast<long>(n));
  altered[(size > 0 ? data[0] : 0) % n] ^= 0x01;
  if (peer.Open(altered, 0, &payload, &answer) == LinkAuth::Verdict::kData) std::abort();
  const std::span<const std::uint8_t> sealed(buffer.data(), n);
  if (peer.Open(sealed, 0, &payload, &answer) != LinkAuth::Verdict::kData) std::abort();
  if (payload.size() != len || (len > 0 && std::memcmp(payload.data(), data, len) != 0)) std::abort();
  if (peer.Open(sealed, 0, &payload, &answer) == LinkAuth::Verdict::kData) std::abort();  // a replay
  return 0;
}
