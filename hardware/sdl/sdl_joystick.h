#pragma once
// A chair joystick (any SDL2 joystick or gamepad: a USB power-chair joystick, a gamepad's left
// stick) as a JoystickSource (hardware/joystick_source.h).
//
// Axis mapping: raw r in [-32768, 32767] -> u = clamp(r / 32767, -1, 1), negated for an inverted
// axis (SDL reads a stick pushed forward as negative Y, so y is inverted by default), then a
// radial-free dead zone per axis: |u| <= d -> 0, else sign(u) (|u| - d) / (1 - d), so full
// deflection stays 1 and the output is continuous at the dead zone's edge.
//
// Validity: SDL delivers a state, not a stream of frames, so the watchdog here is presence: a
// joystick that is unplugged (SDL_JoystickGetAttached false) reads (0, 0), invalid. Each change
// of the raw axes counts as a new input (JoystickSample::input_seq, input_ns = when Poll saw it).

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hardware/joystick_source.h"

struct _SDL_Joystick;

namespace pwsim::hw {

struct JoystickAxes {
  std::string device;       ///< substring of the SDL joystick name; "" = the first joystick
  int x_axis{0};            ///< SDL axis of the right deflection
  int y_axis{1};            ///< SDL axis of the forward deflection
  bool invert_x{false};
  bool invert_y{true};      ///< SDL: forward is negative
  double dead_zone{0.05};   ///< [0, 0.5] of full deflection, per axis
};

/// Pure: one raw SDL axis value to a deflection in [-1, 1].
double AxisDeflection(int raw, bool invert, double dead_zone);

/// An opened SDL joystick. @throws std::runtime_error when SDL cannot start or no matching
/// joystick is attached, or an axis does not exist.
class SdlJoystick final : public JoystickSource {
 public:
  explicit SdlJoystick(JoystickAxes axes);
  ~SdlJoystick() override;
  SdlJoystick(const SdlJoystick&) = delete;
  SdlJoystick& operator=(const SdlJoystick&) = delete;

  JoystickSample Poll(std::int64_t tick, std::int64_t now_ns) override;
  std::string name() const override { return "SDL joystick '" + name_ + "'"; }

 private:
  JoystickAxes axes_;
  _SDL_Joystick* joystick_{nullptr};
  std::string name_;
  int last_x_raw_{0}, last_y_raw_{0};
  bool seen_{false};
  std::int64_t input_ns_{-1};
  std::uint64_t input_seq_{0};
};

/// A scripted joystick: deflections held from each knot's time (stepwise), read from
///   format: pwsim-joystick-script/1
///   t_s: [0, 1.0, 2.5]      # rising
///   x:   [0, 0, 0.3]        # right, [-1, 1]
///   y:   [0, 0.6, 0.6]      # forward, [-1, 1]
struct JoystickScript {
  std::vector<double> t_s, x, y;
  /// The knot in force at time t (the first before the first knot).
  std::size_t KnotAt(double t) const;
};
/// @throws InputError naming file, line and field.
JoystickScript ReadJoystickScript(const std::filesystem::path& file);

/// The script played on an SDL virtual joystick (SDL_JoystickAttachVirtualEx) and read back
/// through SdlJoystick, so the whole SDL path runs without a device: Poll(tick) sets the virtual
/// axes to the script at tick / rate_hz, then polls the device like any joystick.
class SdlScriptedJoystick final : public JoystickSource {
 public:
  SdlScriptedJoystick(JoystickScript script, int rate_hz, std::string name);
  ~SdlScriptedJoystick() override;
  SdlScriptedJoystick(const SdlScriptedJoystick&) = delete;
  SdlScriptedJoystick& operator=(const SdlScriptedJoystick&) = delete;
  JoystickSample Poll(std::int64_t tick, std::int64_t now_ns) override;
  std::string name() const override { return name_ + " on " + reader_->name(); }

 private:
  JoystickScript script_;
  int rate_hz_;
  std::string name_;
  int device_{-1};
  std::unique_ptr<SdlJoystick> reader_;
  _SDL_Joystick* handle_{nullptr};
};

}  // namespace pwsim::hw
