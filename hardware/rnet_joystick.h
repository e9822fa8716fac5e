#pragma once
// The chair's own joystick on its R-Net bus, read and never written.
//
// R-Net (PG Drives Technology, now Curtiss-Wright) is the CAN bus of many commercial power
// chairs: 125 kbit/s, 29-bit identifiers. Its joystick module (JSM) broadcasts the stick
// position about every 10 ms. The layout below is not from a manufacturer's specification; it
// is the one published by the can2RNET reverse-engineering project (Chavez & Specter, DEF CON 24,
// 2016; github.com/redragonx/can2RNET, file RNETdictionary_catagorized.txt, "PERIODIC frames"):
//
//   identifier  0x02000M00, extended (29-bit); M = the joystick module's device slot, 0..F
//   data        2 bytes: X, Y as signed 8-bit percentages, -100..100
//               X > 0 right, Y > 0 forward (e.g. 02000100#0064 = full forward)
//   period      10 ms
//
// Reading: x = X / 100, y = Y / 100. Frames on the joystick identifier that break the layout
// (standard id, remote frame, length != 2, |X| or |Y| > 100) are garbage: counted, ignored.
// Every other R-Net frame is counted as `other` and ignored. The first joystick slot seen is
// locked (a second joystick module, e.g. an attendant's, is counted and ignored) unless a slot
// is configured.
//
// Watchdog, deterministic on ticks: with the last valid frame taken at tick k0, the sample of
// tick k is valid iff k - k0 < timeout_ticks; from tick k0 + timeout_ticks on, (x, y) = (0, 0)
// and valid = false until the next valid frame. With the default 100 ms at 1 kHz, a chair whose
// joystick frames stop is commanded to zero deflection 100 ms after the last frame (10 frame
// periods: scheduling hiccups of the reader do not stop the chair, a pulled cable does).
//
// Sources: a CanListener (can_bus.h: SocketCAN opened listen-only, an in-process bus endpoint)
// or a candump log (`candump -l can0`), replayed on ticks from the log's own timestamps.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hardware/can_bus.h"
#include "hardware/candump_log.h"
#include "hardware/joystick_source.h"

namespace pwsim::hw {

inline constexpr std::uint32_t kRnetJoystickId = 0x02000000;   ///< slot 0; slot M: | M << 8
inline constexpr std::uint32_t kRnetJoystickMask = 0x1FFFF0FF;  ///< the bits that name the frame
inline constexpr int kRnetBitrate = 125000;                     ///< [bit/s]

enum class RnetFrameKind { kJoystick, kOther, kGarbage };

struct RnetJoystickFrame {
  int device{0};      ///< slot M of 0x02000M00
  int x_percent{0};   ///< -100..100, right +
  int y_percent{0};   ///< -100..100, forward +
};

/// What `frame` is on an R-Net bus; fills `out` for kJoystick.
RnetFrameKind ClassifyRnetFrame(const CanFrame& frame, RnetJoystickFrame* out);
/// The joystick frame of slot `device` (0..15) at (x, y) percent (clamped to -100..100).
CanFrame EncodeRnetJoystick(int device, int x_percent, int y_percent);

struct RnetJoystickParams {
  int device{-1};                 ///< slot to read; -1 = lock onto the first slot seen
  std::int64_t timeout_ticks{100};  ///< watchdog (>= 1): ticks without a valid frame -> (0, 0)
};

struct RnetJoystickCounters {
  std::uint64_t valid{0};         ///< joystick frames taken
  std::uint64_t garbage{0};       ///< frames on the joystick id that break the layout
  std::uint64_t other{0};         ///< other R-Net (or foreign) frames, error frames included
  std::uint64_t other_device{0};  ///< joystick frames of a slot other than the locked one
  std::uint64_t timeouts{0};      ///< valid -> invalid transitions of the watchdog
};

struct RnetJoystickState {
  int device{-1};                  ///< locked slot
  int x_percent{0}, y_percent{0};  ///< last valid reading
  std::int64_t last_valid_tick{-1};
  std::int64_t input_ns{-1};
  std::uint64_t input_seq{0};
  bool was_valid{false};
  RnetJoystickCounters counters;
};

/// Takes one received frame at `tick` (arrived at `rx_ns`).
void RnetOnFrame(const RnetJoystickParams& params, RnetJoystickState* state, const CanFrame& frame,
                 std::int64_t tick, std::int64_t rx_ns);
/// The sample of `tick` (after that tick's frames), watchdog applied.
JoystickSample RnetSample(const RnetJoystickParams& params, RnetJoystickState* state, std::int64_t tick);

/// The R-Net joystick read live from a listener (never a bus: nothing here can transmit).
class RnetJoystick final : public JoystickSource {
 public:
  RnetJoystick(std::unique_ptr<CanListener> listener, RnetJoystickParams params);
  JoystickSample Poll(std::int64_t tick, std::int64_t now_ns) override;
  int fd() const override { return listener_->fd(); }
  /// Takes the frames waiting now (arrival = now_ns), counted at `tick`.
  void Take(std::int64_t tick, std::int64_t now_ns) override;
  std::string name() const override;
  const RnetJoystickCounters& counters() const { return state_.counters; }

 private:
  std::unique_ptr<CanListener> listener_;
  RnetJoystickParams params_;
  RnetJoystickState state_;
};

/// The R-Net joystick replayed from a candump log: a record at log time t (microseconds after
/// the log's first record) is taken at tick ceil(t * rate_hz / 1e6), so a replay is the same
/// on every machine and at any speed. For latency, a record counts as arrived at its log time
/// on the caller's clock: input_ns = now_ns - (tick time - t), as a live bus would deliver it.
class RnetLogJoystick final : public JoystickSource {
 public:
  RnetLogJoystick(std::vector<CandumpRecord> records, int rate_hz, RnetJoystickParams params, std::string name);
  JoystickSample Poll(std::int64_t tick, std::int64_t now_ns) override;
  std::string name() const override { return name_; }
  const RnetJoystickCounters& counters() const { return state_.counters; }
  /// The tick of the log's last record.
  std::int64_t last_record_tick() const;

 private:
  std::vector<CandumpRecord> records_;
  std::vector<std::int64_t> record_tick_;
  std::vector<std::int64_t> record_us_;  ///< log time after the first record [us]
  int rate_hz_;
  std::size_t next_{0};
  RnetJoystickParams params_;
  RnetJoystickState state_;
  std::string name_;
};

/// Reads a candump log (`candump -l`). @throws InputError naming the file, line and form, for a
/// missing file or a directory, a malformed line, a timestamp earlier than the line before it,
/// or a log without frames.
std::vector<CandumpRecord> ReadCandumpFile(const std::filesystem::path& file);

/// Watchdog ticks for `timeout_ms` at `rate_hz` (rounded up, at least 1).
std::int64_t WatchdogTicks(double timeout_ms, int rate_hz);

}  // namespace pwsim::hw
