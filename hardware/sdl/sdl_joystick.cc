#include "hardware/sdl/sdl_joystick.h"

#include "engine/yaml_reader.h"
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

std::size_t JoystickScript::KnotAt(double t) const {
  const auto it = std::upper_bound(t_s.begin(), t_s.end(), t);
  return it == t_s.begin() ? 0 : static_cast<std::size_t>(it - t_s.begin()) - 1;
}

JoystickScript ReadJoystickScript(const std::filesystem::path& file) {
  const YamlDocument doc = LoadYamlFile(file);
  YamlMap root(doc.root, doc.file, "");
  root.RequireFormat("pwsim-joystick-script/1");
  JoystickScript script;
  script.t_s = root.Numbers("t_s", Range::Closed(0.0, 86400.0, "s"), 1, 100000);
  script.x = root.Numbers("x", Range::Closed(-1.0, 1.0), script.t_s.size(), script.t_s.size());
  script.y = root.Numbers("y", Range::Closed(-1.0, 1.0), script.t_s.size(), script.t_s.size());
  for (std::size_t i = 1; i < script.t_s.size(); ++i)
    if (!(script.t_s[i] > script.t_s[i - 1])) root.Fail("t_s", "rising times", std::to_string(script.t_s[i]));
  root.Finish();
  return script;
}

SdlScriptedJoystick::SdlScriptedJoystick(JoystickScript script, int rate_hz, std::string name)
    : script_(std::move(script)), rate_hz_(rate_hz), name_(std::move(name)) {
  if (SDL_WasInit(SDL_INIT_JOYSTICK) == 0 && SDL_InitSubSystem(SDL_INIT_JOYSTICK) != 0)
    throw std::runtime_error(std::string("SDL joystick subsystem: ") + SDL_GetError());
  SDL_VirtualJoystickDesc desc;
  SDL_zero(desc);
  desc.version = SDL_VIRTUAL_JOYSTICK_DESC_VERSION;
  desc.type = SDL_JOYSTICK_TYPE_GAMECONTROLLER;
  desc.naxes = 2;
  desc.name = "pwsim scripted joystick";
  device_ = SDL_JoystickAttachVirtualEx(&desc);
  if (device_ < 0) throw std::runtime_error(std::string("SDL virtual joystick: ") + SDL_GetError());
  JoystickAxes axes;
  axes.device = desc.name;
  reader_ = std::make_unique<SdlJoystick>(axes);
  handle_ = SDL_JoystickFromInstanceID(SDL_JoystickGetDeviceInstanceID(device_));
  if (handle_ == nullptr) throw std::runtime_error(std::string("SDL virtual joystick handle: ") + SDL_GetError());
}

SdlScriptedJoystick::~SdlScriptedJoystick() {
  reader_.reset();
  if (device_ >= 0) SDL_JoystickDetachVirtual(device_);
}

JoystickSample SdlScriptedJoystick::Poll(std::int64_t tick, std::int64_t now_ns) {
  const std::size_t k = script_.KnotAt(static_cast<double>(tick) / rate_hz_);
  // raw SDL values: right positive; forward negative (JoystickAxes::invert_y)
  SDL_JoystickSetVirtualAxis(handle_, 0, static_cast<Sint16>(std::lround(script_.x[k] * 32767.0)));
  SDL_JoystickSetVirtualAxis(handle_, 1, static_cast<Sint16>(std::lround(-script_.y[k] * 32767.0)));
  return reader_->Poll(tick, now_ns);
}

}  // namespace pwsim::hw
