#include "hardware/rnet_joystick.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <utility>

#include "engine/input_error.h"

namespace pwsim::hw {

RnetFrameKind ClassifyRnetFrame(const CanFrame& frame, RnetJoystickFrame* out) {
  if (frame.error()) return RnetFrameKind::kOther;
  const std::uint32_t id = frame.arbitration_id();
  const bool joystick_id = (id & kRnetJoystickMask) == kRnetJoystickId;
  if (!joystick_id) return RnetFrameKind::kOther;
  // The joystick identifier, in any form: from here on the frame must follow the layout.
  if (!frame.extended() || frame.remote() || frame.len != 2) return RnetFrameKind::kGarbage;
  const int x = static_cast<std::int8_t>(frame.data[0]);
  const int y = static_cast<std::int8_t>(frame.data[1]);
  if (x < -100 || x > 100 || y < -100 || y > 100) return RnetFrameKind::kGarbage;
  out->device = static_cast<int>((id >> 8) & 0xF);
  out->x_percent = x;
  out->y_percent = y;
  return RnetFrameKind::kJoystick;
}

CanFrame EncodeRnetJoystick(int device, int x_percent, int y_percent) {
  CanFrame f;
  f.id = (kRnetJoystickId | (static_cast<std::uint32_t>(device & 0xF) << 8)) | kCanEffFlag;
  f.len = 2;
  f.data[0] = static_cast<std::uint8_t>(static_cast<std::int8_t>(std::clamp(x_percent, -100, 100)));
  f.data[1] = static_cast<std::uint8_t>(static_cast<std::int8_t>(std::clamp(y_percent, -100, 100)));
  return f;
}

void RnetOnFrame(const RnetJoystickParams& params, RnetJoystickState* state, const CanFrame& frame,
                 std::int64_t tick, std::int64_t rx_ns) {
  RnetJoystickFrame j;
  switch (ClassifyRnetFrame(frame, &j)) {
    case RnetFrameKind::kOther:
      ++state->counters.other;
      return;
    case RnetFrameKind::kGarbage:
      ++state->counters.garbage;
      return;
    case RnetFrameKind::kJoystick:
      break;
  }
  const int want = params.device >= 0 ? params.device : state->device;
  if (want >= 0 && j.device != want) {
    ++state->counters.other_device;
    return;
  }
  state->device = j.device;
  ++state->counters.valid;
  state->x_percent = j.x_percent;
  state->y_percent = j.y_percent;
  state->last_valid_tick = tick;
  state->input_ns = rx_ns;
  ++state->input_seq;
}

JoystickSample RnetSample(const RnetJoystickParams& params, RnetJoystickState* state, std::int64_t tick) {
  JoystickSample s;
  s.valid = state->last_valid_tick >= 0 && tick - state->last_valid_tick < params.timeout_ticks;
  if (state->was_valid && !s.valid) ++state->counters.timeouts;
  state->was_valid = s.valid;
  if (s.valid) {
    s.x = state->x_percent / 100.0;
    s.y = state->y_percent / 100.0;
  }
  s.input_ns = state->input_ns;
  s.input_seq = state->input_seq;
  return s;
}

RnetJoystick::RnetJoystick(std::unique_ptr<CanListener> listener, RnetJoystickParams params)
    : listener_(std::move(listener)), params_(params) {}

void RnetJoystick::Take(std::int64_t tick, std::int64_t now_ns) {
  CanFrame f;
  while (listener_->Receive(&f) == BusStatus::kOk) RnetOnFrame(params_, &state_, f, tick, now_ns);
}

JoystickSample RnetJoystick::Poll(std::int64_t tick, std::int64_t now_ns) {
  Take(tick, now_ns);
  return RnetSample(params_, &state_, tick);
}

std::string RnetJoystick::name() const { return "R-Net joystick on " + listener_->name(); }

RnetLogJoystick::RnetLogJoystick(std::vector<CandumpRecord> records, int rate_hz, RnetJoystickParams params,
                                 std::string name)
    : records_(std::move(records)), rate_hz_(rate_hz), params_(params), name_(std::move(name)) {
  record_tick_.reserve(records_.size());
  record_us_.reserve(records_.size());
  const std::int64_t t0 = records_.empty() ? 0 : records_.front().time_us;
  for (const CandumpRecord& r : records_) {
    // ceil((t - t0) * rate / 1e6): the first tick at or after the record's time (never before
    // it arrived); a log that runs backwards holds its records at tick 0+
    const std::int64_t dt = std::max<std::int64_t>(0, r.time_us - t0);
    record_tick_.push_back((dt * rate_hz + 999'999) / 1'000'000);
    record_us_.push_back(dt);
  }
}

JoystickSample RnetLogJoystick::Poll(std::int64_t tick, std::int64_t now_ns) {
  const std::int64_t tick_us = tick * 1'000'000 / rate_hz_;
  for (; next_ < records_.size() && record_tick_[next_] <= tick; ++next_) {
    const std::int64_t arrived_ns = now_ns - std::max<std::int64_t>(0, tick_us - record_us_[next_]) * 1000;
    RnetOnFrame(params_, &state_, records_[next_].frame, record_tick_[next_], arrived_ns);  // its own tick
  }
  return RnetSample(params_, &state_, tick);
}

std::int64_t RnetLogJoystick::last_record_tick() const { return record_tick_.empty() ? 0 : record_tick_.back(); }

std::vector<CandumpRecord> ReadCandumpFile(const std::filesystem::path& file) {
  RequireReadableFile(file, "a candump log (candump -l)");
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), 0, "(file)", "a readable candump log (candump -l)", "cannot open");
  std::vector<CandumpRecord> records;
  std::string line;
  int number = 0;
  int previous_line = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line == "\r") continue;
    CandumpRecord record;
    if (const CodecError error = ParseCandumpLine(line, &record); error != CodecError::kOk) {
      throw InputError(file.string(), number, "frame",
                       "a candump -l line '(SECONDS.MICROSECONDS) IFACE ID#DATA'", CodecErrorName(error));
    }
    if (!records.empty() && record.time_us < records.back().time_us) {
      const auto stamp = [](std::int64_t us) {
        const std::string text = FormatCandumpLine({us, "", CanFrame{}});
        return text.substr(0, text.find(')') + 1);
      };
      throw InputError(file.string(), number, "timestamp",
                       "time that never goes back (line " + std::to_string(previous_line) + " is at " +
                           stamp(records.back().time_us) + ")",
                       stamp(record.time_us));
    }
    records.push_back(std::move(record));
    previous_line = number;
  }
  if (records.empty()) {
    throw InputError(file.string(), 0, "frame", "at least one frame line '(SECONDS.MICROSECONDS) IFACE ID#DATA'",
                     number == 0 ? "an empty file" : "only blank lines");
  }
  return records;
}

std::int64_t WatchdogTicks(double timeout_ms, int rate_hz) {
  const double ticks = timeout_ms * rate_hz / 1000.0;
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(ticks - 1e-9)));
}

}  // namespace pwsim::hw
