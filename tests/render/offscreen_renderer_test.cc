#include "render/offscreen_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "engine/scene.h"
#include "render/camera_rig.h"
#include "render/image_io.h"
#include "render/motion_check.h"
#include "render/render_scene.h"

namespace pwsim::render {
namespace {

// Golden-image tolerances over B, G, R. The renderer is deterministic on one Mesa build
// (bit-identical frames for any LP_NUM_THREADS); the tolerances absorb a Mesa/LLVM update that
// moves texture filtering or edge coverage a little, while a moved camera or a missing object
// changes many pixels a lot.
constexpr int kMaxPixelDelta = 96;       ///< a few edge pixels may flip between rasterisers
constexpr double kMeanPixelDelta = 1.5;  ///< the image as a whole must stay the same

const std::filesystem::path kTestData = PWSIM_SOURCE_DIR "/tests/render/testdata";

Scene DefaultScene() { return LoadScene(PWSIM_SOURCE_DIR "/scenes/speed_cushion.yaml"); }

RenderConfig Small(bool stereo) {
  RenderConfig config;
  config.width = 160;
  config.height = 90;
  config.stereo = stereo;
  config.hmd.eye_width = 80;
  config.hmd.eye_height = 90;
  return config;
}

/// The chair at the start of the default trial with a little pitch, seen from the head.
VisualSample StartSample() {
  VisualSample sample;
  sample.x = 0.5;
  sample.z = 0.01;
  sample.pitch = 0.01;
  return sample;
}

/// Compares with a golden PNG; PWSIM_UPDATE_GOLDENS=1 rewrites the golden instead.
void ExpectMatchesGolden(const ImageView& image, const std::string& name) {
  const std::filesystem::path golden = kTestData / name;
  if (std::getenv("PWSIM_UPDATE_GOLDENS") != nullptr) {
    WritePng(golden, image);
    GTEST_SKIP() << "golden rewritten: " << golden;
  }
  const Image expected = ReadPng(golden);
  const PixelDelta delta = ComparePixels(image, expected.view());
  ASSERT_TRUE(delta.same_size) << name;
  EXPECT_LE(delta.max, kMaxPixelDelta) << name;
  EXPECT_LE(delta.mean, kMeanPixelDelta) << name;
  if (delta.mean > kMeanPixelDelta) {  // kept for a look, in the build tree (not a shared /tmp name)
    const std::filesystem::path seen = std::filesystem::path(PWSIM_BINARY_DIR) / "test_out" / "render" / name;
    std::filesystem::create_directories(seen.parent_path());
    WritePng(seen, image);
    ADD_FAILURE() << "the image rendered is in " << seen;
  }
}

// Tests that the OSMesa context reports a real renderer (llvmpipe on CI, no GPU, no X).
TEST(OffscreenRendererTest, ReportsRealRenderer) {
  const RenderConfig config = Small(false);
  OffscreenRenderer dut(BuildRenderScene(DefaultScene(), config), config);
  EXPECT_FALSE(dut.gl_renderer().empty());
  EXPECT_NE(dut.gl_version().find("Compatibility Profile"), std::string::npos) << dut.gl_version();
  EXPECT_EQ(dut.width(), 160);
  EXPECT_EQ(dut.height(), 90);
}

// Tests the mono view of the default trial's start against its golden image.
TEST(OffscreenRendererTest, MonoMatchesGolden) {
  const Scene scene = DefaultScene();
  const RenderConfig config = Small(false);
  OffscreenRenderer dut(BuildRenderScene(scene, config), config);
  const VisualSample sample = StartSample();
  ExpectMatchesGolden(
      dut.Render(ChairPose(sample), EyePose(sample, scene.occupant.head_offset, true), 0),
      "default_mono_160x90.png");
}

// Tests the side-by-side stereo view (two 80×90 eyes, IPD, asymmetric FOV) against its golden.
TEST(OffscreenRendererTest, StereoMatchesGolden) {
  const Scene scene = DefaultScene();
  const RenderConfig config = Small(true);
  OffscreenRenderer dut(BuildRenderScene(scene, config), config);
  EXPECT_EQ(dut.width(), 160);
  const VisualSample sample = StartSample();
  ExpectMatchesGolden(
      dut.Render(ChairPose(sample), EyePose(sample, scene.occupant.head_offset, true), 0),
      "default_stereo_2x80x90.png");
}

// Tests that the golden tolerances are tight enough to see a half-degree change of pitch.
TEST(OffscreenRendererTest, GoldenToleranceSeesHalfDegreePitch) {
  const Scene scene = DefaultScene();
  const RenderConfig config = Small(false);
  OffscreenRenderer dut(BuildRenderScene(scene, config), config);
  VisualSample sample = StartSample();
  const Image reference = CopyImage(
      dut.Render(ChairPose(sample), EyePose(sample, scene.occupant.head_offset, true), 0));
  sample.pitch += 0.5 * M_PI / 180.0;
  const PixelDelta delta = ComparePixels(
      dut.Render(ChairPose(sample), EyePose(sample, scene.occupant.head_offset, true), 0),
      reference.view());
  EXPECT_GT(delta.mean, kMeanPixelDelta);
}

// Tests that the tilt-coordination angle is removed from the view: with removal the frame is
// the untilted one, pixel for pixel; without it the horizon moves by the platform tilt, which
// the pixel check measures (a wrong tilt compensation is caught).
TEST(OffscreenRendererTest, WrongTiltCompensationIsCaught) {
  const Scene scene = DefaultScene();
  RenderConfig config = Small(false);
  config.width = 480;
  config.height = 270;
  OffscreenRenderer dut(BuildRenderScene(scene, config), config);
  VisualSample level = StartSample();
  VisualSample tilted = level;
  tilted.tilt_pitch = 2.0 * M_PI / 180.0;  // the platform pitched nose-up by tilt coordination
  const auto& head = scene.occupant.head_offset;
  const auto render = [&](const VisualSample& s, bool remove_tilt) {
    return CopyImage(dut.Render(ChairPose(s), EyePose(s, head, remove_tilt), 0));
  };
  const Image reference = render(level, true);
  const Image removed = render(tilted, true);
  const Image kept = render(tilted, false);
  EXPECT_EQ(ComparePixels(removed.view(), reference.view()).max, 0);

  const double eye_height = EyePose(level, head, true).translation().z();
  const auto horizon_shift = [&](const Image& image) {
    FrameMotionEstimator estimator(config.width, config.height, config.fov_y_deg);
    estimator.Push(reference.view(), eye_height, scene.room.height - eye_height);
    return estimator.Push(image.view(), eye_height, scene.room.height - eye_height);
  };
  const FrameMotion with_removal = horizon_shift(removed);
  const FrameMotion without_removal = horizon_shift(kept);
  ASSERT_TRUE(with_removal.valid && without_removal.valid);
  EXPECT_NEAR(with_removal.pitch_delta, 0.0, 1e-4);
  EXPECT_NEAR(without_removal.pitch_delta, tilted.tilt_pitch, 0.05 * tilted.tilt_pitch);
}

// Tests that skipping the colour clear (head inside the room) leaves no stale pixel: a frame
// drawn after a very different one equals, pixel for pixel, the same view from a fresh renderer
// (whose first frame clears colour too), in mono and in stereo.
TEST(OffscreenRendererTest, DepthOnlyClearLeavesNoStalePixels) {
  const Scene scene = DefaultScene();
  const auto& head = scene.occupant.head_offset;
  VisualSample before = StartSample();
  before.pitch = 0.35;  // looking at the ceiling
  VisualSample after = StartSample();
  after.x = 3.0;
  after.pitch = -0.30;  // on the cushion, looking at the floor
  for (const bool stereo : {false, true}) {
    RenderConfig config = Small(stereo);
    const RenderScene render_scene = BuildRenderScene(scene, config);
    OffscreenRenderer reused(render_scene, config);
    reused.Render(ChairPose(before), EyePose(before, head, true), 0);
    reused.Render(ChairPose(before), EyePose(before, head, true), 0);
    const Image second = CopyImage(reused.Render(ChairPose(after), EyePose(after, head, true), 0));
    OffscreenRenderer fresh(render_scene, config);
    const Image first = CopyImage(fresh.Render(ChairPose(after), EyePose(after, head, true), 0));
    EXPECT_EQ(ComparePixels(second.view(), first.view()).max, 0) << (stereo ? "stereo" : "mono");
  }
}

}  // namespace
}  // namespace pwsim::render
