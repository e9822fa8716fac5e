// libFuzzer target: the cannelloni CAN-over-UDP datagram parser (hardware/can_frame.h).
// Whatever decodes must re-encode to the same bytes.
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "hardware/can_frame.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pwsim::hw;
  std::vector<CanFrame> frames;
  std::uint8_t seq = 0;
  if (DecodeCannelloni(std::span<const std::uint8_t>(data, size), &seq, &frames) != CodecError::kOk)
    return 0;
  std::vector<std::uint8_t> out(size + 16);
  const std::size_t n = EncodeCannelloni(seq, frames, out);
  if (n != size) std::abort();
  for (std::size_t i = 0; i < n; ++i) {
    // RTR frames carry no data on the wire; everything else must match exactly.
    if (out[i] != data[i]) std::abort();
  }
  for (const CanFrame& f : frames)
    if (!IsValidFrame(f)) std::abort();
  return 0;
}
