// libFuzzer target: the can-utils text parsers (ID#DATA frames and candump log lines).
// A parsed frame must format and parse back to itself.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "hardware/can_frame.h"
#include "hardware/candump_log.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pwsim::hw;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  CanFrame f;
  if (ParseFrameText(text, &f) == CodecError::kOk) {
    if (!IsValidFrame(f)) std::abort();
    CanFrame back;
    if (ParseFrameText(FormatFrameText(f), &back) != CodecError::kOk || !(back == f)) std::abort();
  }
  CandumpRecord r;
  if (ParseCandumpLine(text, &r) == CodecError::kOk) {
    CandumpRecord back;
    if (ParseCandumpLine(FormatCandumpLine(r), &back) != CodecError::kOk || !(back == r)) std::abort();
  }
  std::array<std::uint8_t, kRawFrameSize> raw{};
  if (size >= kRawFrameSize && DecodeRawFrame(std::span<const std::uint8_t>(data, kRawFrameSize), &f) == CodecError::kOk) {
    EncodeRawFrame(f, raw);
    CanFrame back;
    if (DecodeRawFrame(raw, &back) != CodecError::kOk || !(back == f)) std::abort();
  }
  return 0;
}
