// libFuzzer target: the HMD bridge datagram parser. Decoded messages re-encode to the same bytes.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "hardware/hmd_protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pwsim::hw;
  HmdMessage m;
  if (DecodeHmd(std::span<const std::uint8_t>(data, size), &m) != CodecError::kOk) return 0;
  std::array<std::uint8_t, kHmdMaxSize> out{};
  const std::size_t n = EncodeHmd(m, out);
  if (n != size || std::memcmp(out.data(), data, n) != 0) std::abort();
  HmdReceiveFilter filter(100'000'000, 5);  // runs the stream start-up (HELLO)
  ClockOffsetEstimator offset;
  if (filter.Accept(m, 0, offset) && std::holds_alternative<HelloMsg>(m.body) && filter.HelloAnswer().stream != 5)
    std::abort();
  (void)filter.Accept(m, 1, offset);  // the same again: a duplicate, or the HELLO that ends the exchange
  if (const auto* p = std::get_if<PongMsg>(&m.body)) offset.AddSample(p->t0, p->t1, p->t2, p->t2);
  return 0;
}
