#include "render/motion_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/scene.h"
#include "render/camera_rig.h"
#include "render/offscreen_renderer.h"
#include "render/render_scene.h"

namespace pwsim::render {
namespace {

// Small frames keep the suite fast; the estimate is sub-pixel, so 480×270 is plenty.
constexpr int kWidth = 480;
constexpr int kHeight = 270;
constexpr int kFps = 50;
// Acceptance from the issue: rate within 5 %, phase within one frame.
constexpr double kRateTolerance = 0.05;
constexpr double kLagTolerance = 1.0 / kFps;

RenderConfig SmallConfig() {
  RenderConfig config;
  config.width = kWidth;
  config.height = kHeight;
  config.fps = kFps;
  return config;
}

// Tests that a known lag and gain are recovered from synthetic series.
TEST(CompareSeriesTest, FindsGainAndLag) {
  const double dt = 0.02;
  std::vector<double> reference, estimate;
  for (int k = 0; k < 200; ++k) {
    reference.push_back(std::sin(2 * M_PI * 0.7 * k * dt));
    estimate.push_back(0.9 * std::sin(2 * M_PI * 0.7 * (k - 3) * dt));
  }
  const SeriesComparison dut = CompareSeries(estimate, reference, dt, 10);
  EXPECT_NEAR(dut.gain, 0.9, 0.01);
  EXPECT_NEAR(dut.lag, 3 * dt, 0.2 * dt);
  EXPECT_GT(dut.correlation, 0.999);
}

// Tests that a rendered pitch oscillation (2 deg, 1 Hz) is recovered from the pixels: the
// pitch rate within 5 % and the phase within one frame.
TEST(FrameMotionEstimatorTest, RecoversRenderedPitchOscillation) {
  const Scene scene = LoadScene(PWSIM_SOURCE_DIR "/scenes/speed_cushion.yaml");
  const RenderConfig config = SmallConfig();
  OffscreenRenderer renderer(BuildRenderScene(scene, config), config);
  FrameMotionEstimator dut(kWidth, kHeight, config.fov_y_deg);
  const double amplitude = 2.0 * M_PI / 180.0, omega = 2.0 * M_PI * 1.0, dt = 1.0 / kFps;
  std::vector<double> estimated, truth;
  double previous_pitch = 0.0;
  for (int k = 0; k <= 100; ++k) {
    VisualSample sample;
    sample.x = 0.5;
    sample.pitch = amplitude * std::sin(omega * k * dt);
    const auto X_WC = EyePose(sample, scene.occupant.head_offset, true);
    const FrameMotion motion =
        dut.Push(renderer.Render(ChairPose(sample), X_WC, k * dt), X_WC.translation().z(),
                 scene.room.height - X_WC.translation().z());
    if (k > 0) {
      ASSERT_TRUE(motion.valid) << "frame " << k;
      estimated.push_back(motion.pitch_delta / dt);
      truth.push_back((sample.pitch - previous_pitch) / dt);
    }
    previous_pitch = sample.pitch;
  }
  const SeriesComparison result = CompareSeries(estimated, truth, dt, 5);
  EXPECT_NEAR(result.gain, 1.0, kRateTolerance);
  EXPECT_LT(std::abs(result.lag), kLagTolerance);
  EXPECT_GT(result.correlation, 0.99);
}

// Tests that a rendered vertical motion of the eye (5 mm per frame up, level view) is
// recovered in sign and size from the floor homography.
TEST(FrameMotionEstimatorTest, RecoversVerticalMotion) {
  const Scene scene = LoadScene(PWSIM_SOURCE_DIR "/scenes/speed_cushion.yaml");
  const RenderConfig config = SmallConfig();
  OffscreenRenderer renderer(BuildRenderScene(scene, config), config);
  FrameMotionEstimator dut(kWidth, kHeight, config.fov_y_deg);
  for (int k = 0; k < 4; ++k) {
    VisualSample sample;
    sample.x = 0.5;
    sample.z = 0.005 * k;
    const auto X_WC = EyePose(sample, scene.occupant.head_offset, true);
    const FrameMotion motion =
        dut.Push(renderer.Render(ChairPose(sample), X_WC, k * 0.02), X_WC.translation().z() - 0.005,
                 scene.room.height - X_WC.translation().z() + 0.005);
    if (k == 0) continue;
    ASSERT_TRUE(motion.valid);
    EXPECT_NEAR(motion.vertical_delta, 0.005, 0.001) << "frame " << k;
    EXPECT_NEAR(motion.pitch_delta, 0.0, 5e-4);  // heave-to-pitch crosstalk, 0.03 deg
  }
}

// Tests that driving forward (2.4 cm per frame, 1.2 m/s at 50 fps) shows as neither pitch nor
// vertical motion: parallax must not leak into the estimates.
TEST(FrameMotionEstimatorTest, ForwardMotionIsNotPitchOrHeave) {
  const Scene scene = LoadScene(PWSIM_SOURCE_DIR "/scenes/speed_cushion.yaml");
  const RenderConfig config = SmallConfig();
  OffscreenRenderer renderer(BuildRenderScene(scene, config), config);
  FrameMotionEstimator dut(kWidth, kHeight, config.fov_y_deg);
  for (int k = 0; k < 4; ++k) {
    VisualSample sample;
    sample.x = 4.5 + 0.024 * k;
    const auto X_WC = EyePose(sample, scene.occupant.head_offset, true);
    const FrameMotion motion =
        dut.Push(renderer.Render(ChairPose(sample), X_WC, k * 0.02), X_WC.translation().z(),
                 scene.room.height - X_WC.translation().z());
    if (k == 0) continue;
    ASSERT_TRUE(motion.valid);
    EXPECT_NEAR(motion.vertical_delta, 0.0, 0.001) << "frame " << k;
    EXPECT_NEAR(motion.pitch_delta, 0.0, 5e-4) << "frame " << k;
  }
}

}  // namespace
}  // namespace pwsim::render
