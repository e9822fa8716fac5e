#pragma once
// Live driver controls from a real steering wheel and pedals through SDL2's joystick API (any
// device SDL sees: USB wheels such as the Logitech G29/G920 or Thrustmaster T300 present their
// wheel, pedals and H-shifter as one joystick with axes and buttons).
//
// The mapping (which axis is what, which way round, which buttons are the gears) is data, so a
// new wheel is a file edit. `MapControls` is the pure part (tested without SDL); `SdlWheel` opens
// the device and polls it once per tick; it never blocks.
//
//   SdlWheel wheel(mapping);            // SDL_Init(SDL_INIT_JOYSTICK), opens the device
//   DriverInput in = wheel.Poll();      // SDL_JoystickUpdate + MapControls
//
// Headless use (CI, the session machine without a display): SDL's joystick subsystem needs no
// video; set SDL_VIDEODRIVER=dummy if a library initialises video anyway. Tests attach a virtual
// joystick (SDL_JoystickAttachVirtual), which needs no device at all.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "engine/vehicle/vehicle_model.h"
#include "engine/yaml_reader.h"

struct _SDL_Joystick;

namespace pwsim::hw {

/// One analogue axis: raw SDL value in [-32768, 32767] to a control value.
struct AxisMap {
  int axis{-1};            ///< SDL axis index; -1 = not connected (control stays 0)
  double raw_at_zero{32767.0};   ///< raw value where the control reads 0 (pedal released)
  double raw_at_full{-32768.0};  ///< raw value where the control reads 1 (pedal floored)
};

struct ControlMapping {
  std::string device;      ///< substring of the SDL joystick name; "" = the first joystick
  int steer_axis{0};       ///< SDL axis of the steering wheel (centre 0)
  bool steer_inverted{false};   ///< true for a wheel whose raw axis grows to the left (SDL: right)
  double steer_lock{7.854};     ///< [rad] steering-wheel angle at full axis (G29: ±450 deg)
  AxisMap throttle{2, 32767.0, -32768.0};
  AxisMap brake{3, 32767.0, -32768.0};
  AxisMap clutch{1, 32767.0, -32768.0};
  /// Buttons of an H-shifter: gear_buttons[i] engages gear i + 1; none pressed = neutral.
  std::vector<int> gear_buttons{12, 13, 14, 15, 16, 17};
  int reverse_button{18};
  int starter_button{-1};  ///< restarts a stalled engine (-1: none)
};

/// Parses a `controls:` mapping (all fields optional, defaults above: a Logitech G29 with its
/// shifter). Axis entries are {axis, raw_at_zero, raw_at_full}; steer_lock is in degrees.
ControlMapping ParseControlMapping(YamlMap& map);

/// Pure mapping of raw axes and buttons to the car's controls (values clamped to range).
vehicle::DriverInput MapControls(const ControlMapping& mapping, const std::vector<int>& axes,
                                 const std::vector<bool>& buttons);

/// An opened SDL joystick. Not copyable. @throws std::runtime_error when SDL cannot start or no
/// matching joystick is attached.
class SdlWheel {
 public:
  explicit SdlWheel(ControlMapping mapping);
  ~SdlWheel();
  SdlWheel(const SdlWheel&) = delete;
  SdlWheel& operator=(const SdlWheel&) = delete;

  /// Reads the device's current state (non-blocking).
  vehicle::DriverInput Poll();
  const std::string& name() const { return name_; }

 private:
  ControlMapping mapping_;
  _SDL_Joystick* joystick_{nullptr};
  std::string name_;
  std::vector<int> axes_;
  std::vector<bool> buttons_;
};

/// Names of the joysticks SDL sees now (initialises the joystick subsystem).
std::vector<std::string> ListJoysticks();

/// Starts SDL's joystick subsystem if needed and opens the first joystick whose name contains
/// `device` ("" = the first); its name goes to `name`. @throws std::runtime_error when none
/// matches or it cannot be opened.
_SDL_Joystick* OpenSdlJoystick(const std::string& device, std::string* name);

}  // namespace pwsim::hw
