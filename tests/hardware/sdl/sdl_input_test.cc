// The live-input path tested end to end with SDL's virtual joystick: SDL is started headless
// (dummy video driver, joystick subsystem only), a virtual wheel with 4 axes and 20 buttons is
// attached, its axes and buttons are set, and SdlWheel::Poll must read them as car controls.
#include "hardware/sdl/sdl_input.h"

#include <SDL.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "engine/input_error.h"

namespace pwsim::hw {
namespace {

TEST(MapControls, PedalsSteeringAndShifter) {
  const ControlMapping m;  // G29 defaults
  std::vector<int> axes{0, 32767, 32767, 32767};
  std::vector<bool> buttons(20, false);
  vehicle::DriverInput in = MapControls(m, axes, buttons);
  EXPECT_EQ(in.throttle, 0.0);
  EXPECT_EQ(in.brake, 0.0);
  EXPECT_EQ(in.clutch, 0.0);
  EXPECT_EQ(in.gear, 0);
  EXPECT_EQ(in.steer, 0.0);
  axes = {-32767, -32768, 0, -32768};
  buttons[14] = true;  // third gear on the G29 shifter
  in = MapControls(m, axes, buttons);
  EXPECT_NEAR(in.steer, m.steer_lock, 1e-12);  // wheel turned fully left
  EXPECT_DOUBLE_EQ(in.clutch, 1.0);
  EXPECT_NEAR(in.throttle, 32767.0 / 65535.0, 1e-12);
  EXPECT_DOUBLE_EQ(in.brake, 1.0);
  EXPECT_EQ(in.gear, 3);
  buttons[18] = true;
  EXPECT_EQ(MapControls(m, axes, buttons).gear, -1);
  // an unplugged axis reads 0
  ControlMapping none = m;
  none.clutch.axis = 9;
  EXPECT_EQ(MapControls(none, axes, buttons).clutch, 0.0);
}

TEST(MapControls, MappingFromYaml) {
  const YamlDocument doc = LoadYamlString(
      "controls: {device: T300, steer_axis: 0, steer_lock_deg: 540, throttle: {axis: 1, raw_at_zero: -32768, "
      "raw_at_full: 32767}, gear_buttons: [1, 2, 3, 4, 5], reverse_button: 6}\n",
      "controls.yaml");
  YamlMap root(doc.root, doc.file, "");
  YamlMap controls = root.Map("controls");
  const ControlMapping m = ParseControlMapping(controls);
  controls.Finish();
  EXPECT_EQ(m.device, "T300");
  EXPECT_NEAR(m.steer_lock, 3.0 * vehicle::kPi, 1e-12);
  EXPECT_EQ(m.gear_buttons.size(), 5u);
  EXPECT_DOUBLE_EQ(MapControls(m, {0, 32767}, {}).throttle, 1.0);

  const YamlDocument bad = LoadYamlString("controls: {throttle: {axis: 1, raw_at_zero: 5, raw_at_full: 5}}\n", "c.yaml");
  YamlMap bad_root(bad.root, bad.file, "");
  YamlMap bad_controls = bad_root.Map("controls");
  EXPECT_THROW(ParseControlMapping(bad_controls), InputError);
}

class VirtualWheel : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("SDL_VIDEODRIVER", "dummy", 1);
    setenv("SDL_AUDIODRIVER", "dummy", 1);
    ASSERT_EQ(SDL_InitSubSystem(SDL_INIT_JOYSTICK), 0) << SDL_GetError();
    device_ = SDL_JoystickAttachVirtual(SDL_JOYSTICK_TYPE_WHEEL, 4, 20, 0);
    ASSERT_GE(device_, 0) << SDL_GetError();
  }
  void TearDown() override {
    if (device_ >= 0) SDL_JoystickDetachVirtual(device_);
    SDL_QuitSubSystem(SDL_INIT_JOYSTICK);
  }
  int device_{-1};
};

TEST_F(VirtualWheel, PollReadsTheDevice) {
  ControlMapping mapping;
  mapping.device = "";  // the first joystick: the virtual one
  SdlWheel wheel(mapping);
  SDL_Joystick* joystick = SDL_JoystickFromInstanceID(SDL_JoystickGetDeviceInstanceID(device_));
  ASSERT_NE(joystick, nullptr);
  // pedals released, wheel centred, neutral
  for (int a = 1; a < 4; ++a) SDL_JoystickSetVirtualAxis(joystick, a, 32767);
  SDL_JoystickSetVirtualAxis(joystick, 0, 0);
  vehicle::DriverInput in = wheel.Poll();
  EXPECT_EQ(in.throttle, 0.0);
  EXPECT_EQ(in.gear, 0);
  EXPECT_EQ(in.steer, 0.0);
  // half throttle, clutch floored, second gear, wheel a quarter to the right
  SDL_JoystickSetVirtualAxis(joystick, 2, 0);
  SDL_JoystickSetVirtualAxis(joystick, 1, -32768);
  SDL_JoystickSetVirtualAxis(joystick, 0, 8192);
  SDL_JoystickSetVirtualButton(joystick, 13, 1);
  in = wheel.Poll();
  EXPECT_NEAR(in.throttle, 32767.0 / 65535.0, 1e-12);
  EXPECT_DOUBLE_EQ(in.clutch, 1.0);
  EXPECT_EQ(in.gear, 2);
  EXPECT_NEAR(in.steer, -8192.0 / 32767.0 * mapping.steer_lock, 1e-12);
  EXPECT_FALSE(wheel.name().empty());
}

TEST_F(VirtualWheel, MissingDeviceIsAClearError) {
  ControlMapping mapping;
  mapping.device = "no such wheel";
  try {
    SdlWheel wheel(mapping);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no such wheel"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pwsim::hw
