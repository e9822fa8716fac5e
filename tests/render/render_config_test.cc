#include "render/render_config.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/input_error.h"
#include "engine/scene.h"

namespace pwsim::render {
namespace {

/// The default scene's text with `render_yaml` appended.
std::string DefaultSceneText() {
  std::ifstream in(PWSIM_SOURCE_DIR "/scenes/speed_cushion.yaml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

Scene SceneWithRender(const std::string& render_yaml) {
  return ParseScene(DefaultSceneText() + render_yaml, PWSIM_SOURCE_DIR "/scenes/inline_test.yaml");
}

int LineCount(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

// Tests that a scene without a render: section gets the defaults.
TEST(RenderConfigTest, DefaultsWithoutSection) {
  const RenderConfig dut = ParseRenderConfig(SceneWithRender(""));
  EXPECT_EQ(dut.width, 1280);
  EXPECT_EQ(dut.height, 720);
  EXPECT_EQ(dut.fps, 50);
  EXPECT_TRUE(dut.remove_tilt);
  EXPECT_EQ(dut.TicksPerFrame(Clock{}), 20);
}

// Tests that the render: section sets size, fps, field of view and the HMD eyes.
TEST(RenderConfigTest, ReadsSection) {
  const RenderConfig dut = ParseRenderConfig(
      SceneWithRender("render: {size: [640, 360], fps: 25, fov_y_deg: 75, stereo: true,\n"
                      "         hmd: {eye_size: [1440, 1600], ipd_m: 0.063, inner_deg: 40}}\n"));
  EXPECT_EQ(dut.width, 640);
  EXPECT_EQ(dut.fps, 25);
  EXPECT_DOUBLE_EQ(dut.fov_y_deg, 75);
  EXPECT_TRUE(dut.stereo);
  EXPECT_EQ(dut.image_width(), 2880);
  EXPECT_DOUBLE_EQ(dut.hmd.ipd, 0.063);
  EXPECT_DOUBLE_EQ(dut.hmd.fov.inner_deg, 40);
}

// Tests that an unknown key fails naming the field and the line.
TEST(RenderConfigTest, UnknownKeyFails) {
  try {
    ParseRenderConfig(SceneWithRender("render: {size: [640, 360], fsp: 25}\n"));
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("render.fsp"), std::string::npos) << error.what();
    EXPECT_EQ(error.line(), LineCount(DefaultSceneText()) + 1);
  }
}

// Tests that anisotropic filtering is off by default, read from the section, and refused
// outside 1..16 naming the field.
TEST(RenderConfigTest, AnisotropyReadAndBounded) {
  EXPECT_EQ(ParseRenderConfig(SceneWithRender("")).anisotropy, 1);
  EXPECT_EQ(ParseRenderConfig(SceneWithRender("render: {anisotropy: 8}\n")).anisotropy, 8);
  try {
    ParseRenderConfig(SceneWithRender("render: {anisotropy: 32}\n"));
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("render.anisotropy"), std::string::npos) << error.what();
  }
}

// Tests that a frame rate which does not divide the clock rate fails (frame k = tick k·N).
TEST(RenderConfigTest, FpsMustDivideClockRate) {
  EXPECT_THROW(ParseRenderConfig(SceneWithRender("render: {fps: 60}\n")), InputError);
  EXPECT_THROW(ParseRenderConfig(SceneWithRender("render: {size: [641, 360]}\n")), InputError);
}

}  // namespace
}  // namespace pwsim::render
