#include "hardware/sdl/sdl_input.h"

#include <SDL.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pwsim::hw {
namespace {

double Pedal(const AxisMap& map, const std::vector<int>& axes) {
  if (map.axis < 0 || map.axis >= static_cast<int>(axes.size())) return 0.0;
  const double raw = axes[static_cast<std::size_t>(map.axis)];
  return std::clamp((raw - map.raw_at_zero) / (map.raw_at_full - map.raw_at_zero), 0.0, 1.0);
}

bool Pressed(int button, const std::vector<bool>& buttons) {
  return button >= 0 && button < static_cast<int>(buttons.size()) && buttons[static_cast<std::size_t>(button)];
}

AxisMap ParseAxis(YamlMap& map, const std::string& key, AxisMap fallback) {
  if (!map.Has(key)) return fallback;
  YamlMap axis = map.Map(key);
  AxisMap out;
  out.axis = axis.Integer("axis", -1, 255);
  out.raw_at_zero = axis.NumberOr("raw_at_zero", fallback.raw_at_zero, Range::Closed(-32768.0, 32767.0));
  out.raw_at_full = axis.NumberOr("raw_at_full", fallback.raw_at_full, Range::Closed(-32768.0, 32767.0));
  axis.Finish();
  if (out.raw_at_zero == out.raw_at_full) axis.Fail("raw_at_full", "a value different from raw_at_zero", "the same");
  return out;
}

void StartSdl() {
  if (SDL_WasInit(SDL_INIT_JOYSTICK) != 0) return;
  if (SDL_InitSubSystem(SDL_INIT_JOYSTICK) != 0) {
    throw std::runtime_error(std::string("SDL joystick subsystem: ") + SDL_GetError());
  }
}

}  // namespace

ControlMapping ParseControlMapping(YamlMap& map) {
  ControlMapping m;
  m.device = map.StringOr("device", m.device);
  m.steer_axis = map.IntegerOr("steer_axis", m.steer_axis, 0, 255);
  m.steer_inverted = map.BoolOr("steer_inverted", m.steer_inverted);
  m.steer_lock = map.NumberOr("steer_lock_deg", m.steer_lock * 180.0 / vehicle::kPi, Range::Positive(1800.0, "deg")) *
                 vehicle::kPi / 180.0;
  m.throttle = ParseAxis(map, "throttle", m.throttle);
  m.brake = ParseAxis(map, "brake", m.brake);
  m.clutch = ParseAxis(map, "clutch", m.clutch);
  if (map.Has("gear_buttons")) {
    m.gear_buttons.clear();
    for (double b : map.Numbers("gear_buttons", Range::Closed(0.0, 255.0), 1, 10)) {
      if (b != std::round(b)) map.Fail("gear_buttons", "integer button numbers", std::to_string(b));
      m.gear_buttons.push_back(static_cast<int>(b));
    }
  }
  m.reverse_button = map.IntegerOr("reverse_button", m.reverse_button, -1, 255);
  m.starter_button = map.IntegerOr("starter_button", m.starter_button, -1, 255);
  return m;
}

vehicle::DriverInput MapControls(const ControlMapping& mapping, const std::vector<int>& axes,
                                 const std::vector<bool>& buttons) {
  vehicle::DriverInput in;
  if (mapping.steer_axis < static_cast<int>(axes.size())) {
    // SDL wheels read negative to the left; pwsim steers left positive
    double raw = axes[static_cast<std::size_t>(mapping.steer_axis)];
    raw = std::clamp(raw / 32767.0, -1.0, 1.0);
    in.steer = (mapping.steer_inverted ? raw : -raw) * mapping.steer_lock;
  }
  in.throttle = Pedal(mapping.throttle, axes);
  in.brake = Pedal(mapping.brake, axes);
  in.clutch = Pedal(mapping.clutch, axes);
  in.gear = 0;
  for (std::size_t i = 0; i < mapping.gear_buttons.size(); ++i) {
    if (Pressed(mapping.gear_buttons[i], buttons)) in.gear = static_cast<int>(i) + 1;
  }
  if (Pressed(mapping.reverse_button, buttons)) in.gear = -1;
  in.starter = Pressed(mapping.starter_button, buttons);
  return in;
}

std::vector<std::string> ListJoysticks() {
  StartSdl();
  std::vector<std::string> names;
  for (int i = 0; i < SDL_NumJoysticks(); ++i) {
    const char* name = SDL_JoystickNameForIndex(i);
    names.emplace_back(name != nullptr ? name : "");
  }
  return names;
}

SDL_Joystick* OpenSdlJoystick(const std::string& device, std::string* name) {
  StartSdl();
  for (int i = 0; i < SDL_NumJoysticks(); ++i) {
    const char* c_name = SDL_JoystickNameForIndex(i);
    const std::string n = c_name != nullptr ? c_name : "";
    if (device.empty() || n.find(device) != std::string::npos) {
      SDL_Joystick* joystick = SDL_JoystickOpen(i);
      if (joystick == nullptr) throw std::runtime_error("SDL_JoystickOpen(" + n + "): " + SDL_GetError());
      *name = n;
      return joystick;
    }
  }
  throw std::runtime_error("no joystick" + (device.empty() ? std::string() : " named like '" + device + "'") +
                           " attached (" + std::to_string(SDL_NumJoysticks()) + " seen)");
}

SdlWheel::SdlWheel(ControlMapping mapping) : mapping_(std::move(mapping)) {
  joystick_ = OpenSdlJoystick(mapping_.device, &name_);
  axes_.assign(static_cast<std::size_t>(std::max(0, SDL_JoystickNumAxes(joystick_))), 0);
  buttons_.assign(static_cast<std::size_t>(std::max(0, SDL_JoystickNumButtons(joystick_))), false);
}

SdlWheel::~SdlWheel() {
  if (joystick_ != nullptr) SDL_JoystickClose(joystick_);
}

vehicle::DriverInput SdlWheel::Poll() {
  SDL_JoystickUpdate();
  for (std::size_t i = 0; i < axes_.size(); ++i) axes_[i] = SDL_JoystickGetAxis(joystick_, static_cast<int>(i));
  for (std::size_t i = 0; i < buttons_.size(); ++i) {
    buttons_[i] = SDL_JoystickGetButton(joystick_, static_cast<int>(i)) != 0;
  }
  return MapControls(mapping_, axes_, buttons_);
}

}  // namespace pwsim::hw
