#include "hardware/input_latency.h"

namespace pwsim::hw {

InputLatency::InputLatency(std::size_t capacity) : capacity_(capacity) { ms_.reserve(capacity); }

void InputLatency::OnOutput(const InputStamp& input, std::int64_t sent_ns) {
  if (input.seq == 0 || input.seq == last_seq_ || input.input_ns < 0) return;
  last_seq_ = input.seq;
  if (ms_.size() >= capacity_) {
    ++overflow_;
    return;
  }
  ms_.push_back(static_cast<double>(sent_ns - input.input_ns) / 1e6);
}

Percentiles InputLatency::Summary() const { return ComputePercentiles(ms_); }

}  // namespace pwsim::hw
