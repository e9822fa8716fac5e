// Floor textures through the real OSMesa renderer: a floor made of many quads (a circuit's
// relief grid and the floor around it) shows one continuous pattern, and the minified far floor
// is filtered (mip-mapping) rather than aliased: no moiré.
//
// The measure of aliasing is the high-frequency energy of a band of the far floor, the mean
// |discrete Laplacian| of the luminance. The truth it is held against is not the renderer's
// filtering: the same view drawn at 4× the resolution and averaged over 4×4 pixel blocks (a box
// filter of the scene, supersampling).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "render/camera_rig.h"
#include "render/image_io.h"
#include "render/offscreen_renderer.h"
#include "render/render_scene.h"

namespace pwsim::render {
namespace {

constexpr int kWidth = 320, kHeight = 180;  // fov_y 60°: focal length 155.9 px
constexpr double kEyeHeight = 1.25;         // [m], looking level: the horizon is row 90
// rows of the floor between 10 m and 4 m ahead: 90 + 155.9 · 1.25 / d
constexpr int kFarRow0 = 110, kFarRow1 = 138;

const Rgb kFloorColor{0.85F, 0.80F, 0.72F};

/// Luminance of an image (row major, 0..255).
std::vector<double> Luminance(const ImageView& image) {
  std::vector<double> y(static_cast<std::size_t>(image.width) * image.height);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const std::uint8_t* p = image.bgra + 4 * i;
    y[i] = 0.114 * p[0] + 0.587 * p[1] + 0.299 * p[2];
  }
  return y;
}

/// Mean |4 p − (left + right + up + down)| over rows [row0, row1), columns 8..width−8.
double HighFrequencyEnergy(const std::vector<double>& y, int width, int row0, int row1) {
  double sum = 0.0;
  int count = 0;
  for (int r = row0; r < row1; ++r) {
    for (int c = 8; c < width - 8; ++c) {
      const auto at = [&](int rr, int cc) { return y[static_cast<std::size_t>(rr * width + cc)]; };
      sum += std::abs(4 * at(r, c) - at(r, c - 1) - at(r, c + 1) - at(r - 1, c) - at(r + 1, c));
      ++count;
    }
  }
  return sum / count;
}

/// Mean |a − b| over the same band.
double MeanDifference(const std::vector<double>& a, const std::vector<double>& b, int width, int row0,
                      int row1) {
  double sum = 0.0;
  int count = 0;
  for (int r = row0; r < row1; ++r) {
    for (int c = 8; c < width - 8; ++c, ++count) {
      sum += std::abs(a[static_cast<std::size_t>(r * width + c)] - b[static_cast<std::size_t>(r * width + c)]);
    }
  }
  return sum / count;
}

/// The level view from (0, 0, kEyeHeight) along +x, luminance at width × height.
std::vector<double> RenderLevelView(const RenderScene& scene, int width, int height, int anisotropy = 1,
                                    double* anisotropy_in_effect = nullptr) {
  RenderConfig config;
  config.width = width;
  config.height = height;
  config.anisotropy = anisotropy;
  OffscreenRenderer renderer(scene, config);
  if (anisotropy_in_effect != nullptr) *anisotropy_in_effect = renderer.texture_anisotropy();
  VisualSample s;
  const Eigen::Isometry3d X_WV = ChairPose3d(s);
  const ImageView image = renderer.Render(X_WV, EyePoseOn(X_WV, s, {0.0, 0.0, kEyeHeight}, true), 0.0);
  if (const char* dir = std::getenv("PWSIM_FLOOR_TEXTURE_PNG")) {  // to look at the views
    static int n = 0;
    WritePng(std::string(dir) + "/floor_" + std::to_string(n++) + ".png", image);
  }
  return Luminance(image);
}

/// A 60 m × 60 m floor in one quad.
RenderScene OneQuadFloor() {
  RenderScene scene;
  scene.world.push_back(Quad{{Eigen::Vector3d(-30, -30, 0), Eigen::Vector3d(30, -30, 0),
                              Eigen::Vector3d(30, 30, 0), Eigen::Vector3d(-30, 30, 0)},
                             kFloorColor, TextureKind::kFloor, 1.0, true});
  return scene;
}

/// The same floor as a circuit draws it under a (flat) relief grid of 5 cm cells 1..13 m ahead:
/// the grid's floor in 5 cm strips (runs along x), the floor around it in four quads.
RenderScene StripFloor(bool world_uv) {
  RenderScene scene;
  HeightGrid grid;
  grid.x0 = 1.0;
  grid.y0 = -6.0;
  grid.cell = 0.05;
  grid.nx = 241;
  grid.ny = 241;
  grid.z.assign(static_cast<std::size_t>(grid.nx * grid.ny), 0.0);
  AddHeightField(&scene.world, grid, Rgb{}, TextureKind::kCushion, 0.0, kFloorColor);
  AddFloorAround(&scene.world, Eigen::AlignedBox2d(Eigen::Vector2d(-30, -30), Eigen::Vector2d(30, 30)),
                 Eigen::AlignedBox2d(Eigen::Vector2d(1, -6), Eigen::Vector2d(13, 6)), 0.0, kFloorColor);
  for (Quad& q : scene.world) q.world_uv = world_uv;  // false: texture restarted per quad
  return scene;
}

// Tests that the floor of a relief grid (240 strips 5 cm wide) looks like one floor: the pixels
// of the far band equal those of a single quad (mean difference under 1 level of 255), with the
// same high-frequency energy (±10 %); per-quad texture coordinates, the drawing before world
// coordinates, restart the texture every 5 cm and raise that energy by half at least (moiré).
TEST(FloorTextureTest, ReliefGridFloorShowsOneContinuousPattern) {
  const std::vector<double> one = RenderLevelView(OneQuadFloor(), kWidth, kHeight);
  const std::vector<double> strips = RenderLevelView(StripFloor(true), kWidth, kHeight);
  const std::vector<double> restarted = RenderLevelView(StripFloor(false), kWidth, kHeight);
  const double e_one = HighFrequencyEnergy(one, kWidth, kFarRow0, kFarRow1);
  const double e_strips = HighFrequencyEnergy(strips, kWidth, kFarRow0, kFarRow1);
  const double e_restarted = HighFrequencyEnergy(restarted, kWidth, kFarRow0, kFarRow1);
  RecordProperty("hf_one_quad", std::to_string(e_one));
  RecordProperty("hf_strips", std::to_string(e_strips));
  RecordProperty("hf_restarted", std::to_string(e_restarted));
  const double d_strips = MeanDifference(one, strips, kWidth, kFarRow0, kHeight - 1);
  const double d_restarted = MeanDifference(one, restarted, kWidth, kFarRow0, kHeight - 1);
  std::printf("floor band: hf one quad %.2f, strips %.2f, restarted %.2f; mean |strips - one| %.3f, "
              "|restarted - one| %.2f\n", e_one, e_strips, e_restarted, d_strips, d_restarted);
  EXPECT_LT(d_strips, 1.0);
  EXPECT_NEAR(e_strips / e_one, 1.0, 0.10);
  EXPECT_GT(d_restarted, 5.0) << "the measure no longer sees a texture restarted per quad";
}

// Tests that the far floor is filtered, not aliased: at 320×180 its band differs from the
// supersampled view (1280×720, 4×4 blocks averaged) by less than its own texture contrast
// would give if aliased, and holds no more high-frequency energy than 1.5× the supersampled
// view's. Anisotropic filtering (where the context has it) keeps the band as close.
TEST(FloorTextureTest, FarFloorMatchesSupersampledView) {
  const RenderScene scene = OneQuadFloor();
  const std::vector<double> fine = RenderLevelView(scene, 4 * kWidth, 4 * kHeight);
  std::vector<double> truth(static_cast<std::size_t>(kWidth) * kHeight, 0.0);
  for (int r = 0; r < 4 * kHeight; ++r) {
    for (int c = 0; c < 4 * kWidth; ++c) {
      truth[static_cast<std::size_t>((r / 4) * kWidth + c / 4)] +=
          fine[static_cast<std::size_t>(r * 4 * kWidth + c)] / 16.0;
    }
  }
  const double e_truth = HighFrequencyEnergy(truth, kWidth, kFarRow0, kFarRow1);
  for (const int anisotropy : {1, 16}) {
    double in_effect = 0.0;
    const std::vector<double> view = RenderLevelView(scene, kWidth, kHeight, anisotropy, &in_effect);
    EXPECT_GE(in_effect, 1.0);
    EXPECT_LE(in_effect, anisotropy);
    const double e_view = HighFrequencyEnergy(view, kWidth, kFarRow0, kFarRow1);
    const double difference = MeanDifference(view, truth, kWidth, kFarRow0, kFarRow1);
    RecordProperty("hf_truth", std::to_string(e_truth));
    RecordProperty("hf_view_aniso" + std::to_string(anisotropy), std::to_string(e_view));
    RecordProperty("diff_aniso" + std::to_string(anisotropy), std::to_string(difference));
    std::printf("anisotropy %d (in effect %g): hf %.2f (supersampled %.2f), mean |view - truth| %.2f\n",
                anisotropy, in_effect, e_view, e_truth, difference);
    EXPECT_LT(e_view, 1.5 * e_truth) << "anisotropy " << anisotropy;
    EXPECT_LT(difference, 8.0) << "anisotropy " << anisotropy;
  }
}

}  // namespace
}  // namespace pwsim::render
