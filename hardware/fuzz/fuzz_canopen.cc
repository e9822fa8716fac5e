// libFuzzer target: the CANopen decoders and the CSP master's frame handling. The bytes are a
// sequence of 16-byte struct can_frame records fed to Cia402Master::OnFrame between cycles.
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "hardware/canopen.h"
#include "hardware/cia402_master.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pwsim::hw;
  Cia402Master master;
  std::vector<CanFrame> out;
  std::int64_t cycle = 0;
  for (std::size_t at = 0; at + kRawFrameSize <= size; at += kRawFrameSize) {
    CanFrame f;
    if (DecodeRawFrame(std::span<const std::uint8_t>(data + at, kRawFrameSize), &f) != CodecError::kOk) continue;
    std::uint8_t node = 0;
    (void)canopen::Classify(f, &node);
    canopen::NmtCommand cmd{};
    canopen::NmtState st{};
    canopen::Emcy e;
    canopen::CspCommand c;
    canopen::CspStatus s;
    canopen::CspFeedback fb;
    std::uint8_t counter = 0;
    (void)canopen::DecodeNmt(f, &cmd, &node);
    (void)canopen::DecodeSync(f, &counter);
    (void)canopen::DecodeHeartbeat(f, &node, &st);
    (void)canopen::DecodeEmcy(f, &node, &e);
    (void)canopen::DecodeCspCommand(f, &node, &c);
    (void)canopen::DecodeCspFeedback(f, &node, &fb);
    if (canopen::DecodeCspStatus(f, &node, &s)) (void)canopen::DecodeStatusword(s.statusword);
    master.OnFrame(f);
    out.clear();
    master.Cycle(cycle++, AxisValues{}, &out);
    for (const CanFrame& x : out)
      if (!IsValidFrame(x)) std::abort();
  }
  return 0;
}
