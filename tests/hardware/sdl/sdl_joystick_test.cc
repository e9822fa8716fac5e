// The chair joystick through SDL2 (hardware/sdl/sdl_joystick.h), tested with SDL's virtual
// joystick (SDL_JoystickAttachVirtualEx, SDL >= 2.24; Debian 12 ships 2.26) under the dummy
// video driver: no device, no display.
#include "hardware/sdl/sdl_joystick.h"

#include <SDL.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "engine/input_error.h"
#include <stdexcept>

namespace pwsim::hw {
namespace {

TEST(AxisDeflection, ScaleInversionAndDeadZone) {
  EXPECT_EQ(AxisDeflection(0, false, 0.05), 0.0);
  EXPECT_DOUBLE_EQ(AxisDeflection(32767, false, 0.05), 1.0);
  EXPECT_DOUBLE_EQ(AxisDeflection(-32768, false, 0.05), -1.0);  // clamped
  EXPECT_DOUBLE_EQ(AxisDeflection(-32768, true, 0.05), 1.0);    // SDL forward is negative
  EXPECT_EQ(AxisDeflection(1000, false, 0.05), 0.0);     // 3 % inside the dead zone
  // continuous at the edge, linear beyond: u = 0.525 -> (0.525 - 0.05) / 0.95 = 0.5
  EXPECT_NEAR(AxisDeflection(static_cast<int>(0.525 * 32767), false, 0.05), 0.5, 1.0 / 32767 / 0.95);  // one raw step
  EXPECT_NEAR(AxisDeflection(static_cast<int>(0.0501 * 32767), false, 0.05), 0.0, 1e-4);
}

class VirtualChairJoystick : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("SDL_VIDEODRIVER", "dummy", 1);
    ASSERT_EQ(SDL_InitSubSystem(SDL_INIT_JOYSTICK), 0) << SDL_GetError();
    SDL_VirtualJoystickDesc desc;
    SDL_zero(desc);
    desc.version = SDL_VIRTUAL_JOYSTICK_DESC_VERSION;
    desc.type = SDL_JOYSTICK_TYPE_GAMECONTROLLER;
    desc.naxes = 2;
    desc.nbuttons = 2;
    desc.name = "pwsim virtual chair joystick";
    device_ = SDL_JoystickAttachVirtualEx(&desc);
    ASSERT_GE(device_, 0) << SDL_GetError();
  }
  void TearDown() override {
    if (device_ >= 0) SDL_JoystickDetachVirtual(device_);
    SDL_QuitSubSystem(SDL_INIT_JOYSTICK);
  }
  SDL_Joystick* Handle() const { return SDL_JoystickFromInstanceID(SDL_JoystickGetDeviceInstanceID(device_)); }
  int device_{-1};
};

TEST_F(VirtualChairJoystick, ReadsDeflectionCountsInputsAndStopsWhenUnplugged) {
  JoystickAxes axes;
  axes.device = "virtual chair";
  SdlJoystick joystick(axes);
  EXPECT_NE(joystick.name().find("pwsim virtual chair joystick"), std::string::npos);
  SDL_Joystick* handle = Handle();
  ASSERT_NE(handle, nullptr);
  JoystickSample s = joystick.Poll(0, 100);
  EXPECT_TRUE(s.valid);
  EXPECT_EQ(s.x, 0.0);
  EXPECT_EQ(s.y, 0.0);
  const std::uint64_t first = s.input_seq;
  // pushed fully forward and half right
  SDL_JoystickSetVirtualAxis(handle, 1, -32768);
  SDL_JoystickSetVirtualAxis(handle, 0, 16384);
  s = joystick.Poll(1, 200);
  EXPECT_TRUE(s.valid);
  EXPECT_DOUBLE_EQ(s.y, 1.0);
  EXPECT_NEAR(s.x, (16384.0 / 32767.0 - 0.05) / 0.95, 1e-12);
  EXPECT_EQ(s.input_seq, first + 1);
  EXPECT_EQ(s.input_ns, 200);
  // no change: same input
  s = joystick.Poll(2, 300);
  EXPECT_EQ(s.input_seq, first + 1);
  EXPECT_EQ(s.input_ns, 200);
  // unplugged: (0, 0), invalid
  ASSERT_EQ(SDL_JoystickDetachVirtual(device_), 0);
  device_ = -1;
  s = joystick.Poll(3, 400);
  EXPECT_FALSE(s.valid);
  EXPECT_EQ(s.x, 0.0);
  EXPECT_EQ(s.y, 0.0);
}

TEST_F(VirtualChairJoystick, AMissingDeviceOrAxisIsAClearError) {
  JoystickAxes axes;
  axes.device = "no such joystick";
  EXPECT_THROW(SdlJoystick{axes}, std::runtime_error);
  axes.device = "virtual chair";
  axes.y_axis = 5;
  try {
    SdlJoystick j(axes);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("2 axes"), std::string::npos) << e.what();
  }
}

TEST(SdlScriptedJoystick, PlaysTheShippedScriptThroughTheSdlPath) {
  setenv("SDL_VIDEODRIVER", "dummy", 1);
  const JoystickScript script =
      ReadJoystickScript(std::filesystem::path(PWSIM_SOURCE_DIR) / "assets/joystick/scripted_drive.yaml");
  ASSERT_EQ(script.t_s.size(), 7U);
  SdlScriptedJoystick joystick(script, 1000, "script");
  const double d = JoystickAxes{}.dead_zone;
  auto through = [&](double u) { return AxisDeflection(static_cast<int>(std::lround(u * 32767.0)), false, d); };
  JoystickSample s = joystick.Poll(0, 0);
  EXPECT_TRUE(s.valid);
  EXPECT_EQ(s.y, 0.0);
  s = joystick.Poll(1200, 5);  // the knot of 1.0 s: y = 0.6
  EXPECT_NEAR(s.y, through(0.6), 1e-12);
  EXPECT_EQ(s.input_ns, 5);
  s = joystick.Poll(3000, 6);  // 2.5 s: x = 0.4, y = 0.8
  EXPECT_NEAR(s.x, through(0.4), 1e-12);
  EXPECT_NEAR(s.y, through(0.8), 1e-12);
  s = joystick.Poll(3600, 7);  // 3.5 s: reverse
  EXPECT_LT(s.y, -0.4);
  SDL_QuitSubSystem(SDL_INIT_JOYSTICK);
}

TEST(JoystickScript, BadScriptsNameFileLineAndField) {
  const auto file = std::filesystem::temp_directory_path() / ("bad_script_" + std::to_string(::getpid()) + ".yaml");
  {
    std::ofstream out(file);
    out << "format: pwsim-joystick-script/1\nt_s: [0, 1]\nx: [0, 2]\ny: [0, 0]\n";
  }
  try {
    ReadJoystickScript(file);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "x[1]");
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace pwsim::hw
