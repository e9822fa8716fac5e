#include "hardware/sdl/sdl_joystick.h"

#include "hardware/sdl/sdl_input.h"

#include <SDL.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pwsim::hw {

double AxisDeflection(int raw, bool invert, double dead_zone) {
  double u = std::clamp(static_cast<double>(raw) / 32767.0, -1.0, 1.0);
  if (invert) u = -u;
  const double a = std::abs(u);
  if (a <= dead_zone) return 0.0;
  return std::copysign((a - dead_zone) / (1.0 - dead_zone), u);
}

SdlJoystick::SdlJoystick(JoystickAxes axes) : axes_(std::move(axes)) {
  if (!(axes_.dead_zone >= 0.0 && axes_.dead_zone <= 0.5))
    throw std::runtime_error("joystick dead zone: expected 0..0.5, got " + std::to_string(axes_.dead_zone));
  joystick_ = OpenSdlJoystick(axes_.device, &name_);
  const int n_axes = SDL_JoystickNumAxes(joystick_);
  if (axes_.x_axis < 0 || axes_.x_axis >= n_axes || axes_.y_axis < 0 || axes_.y_axis >= n_axes) {
    SDL_JoystickClose(joystick_);
    joystick_ = nullptr;
    throw std::runtime_error("joystick '" + name_ + "' has " + std::to_string(n_axes) + " axes; x axis " +
                             std::to_string(axes_.x_axis) + " and y axis " + std::to_string(axes_.y_axis) + " asked for");
  }
}

SdlJoystick::~SdlJoystick() {
  if (joystick_ != nullptr) SDL_JoystickClose(joystick_);
}

JoystickSample SdlJoystick::Poll(std::int64_t /*tick*/, std::int64_t now_ns) {
  SDL_JoystickUpdate();
  JoystickSample s;
  if (SDL_JoystickGetAttached(joystick_) != SDL_TRUE) {  // unplugged: stop
    s.input_ns = input_ns_;
    s.input_seq = input_seq_;
    return s;
  }
  const int x_raw = SDL_JoystickGetAxis(joystick_, axes_.x_axis);
  const int y_raw = SDL_JoystickGetAxis(joystick_, axes_.y_axis);
  if (!seen_ || x_raw != last_x_raw_ || y_raw != last_y_raw_) {
    seen_ = true;
    last_x_raw_ = x_raw;
    last_y_raw_ = y_raw;
    input_ns_ = now_ns;
    ++input_seq_;
  }
  s.valid = true;
  s.x = AxisDeflection(x_raw, axes_.invert_x, axes_.dead_zone);
  s.y = AxisDeflection(y_raw, axes_.invert_y, axes_.dead_zone);
  s.input_ns = input_ns_;
  s.input_seq = input_seq_;
  return s;
}

}  // namespace pwsim::hw
