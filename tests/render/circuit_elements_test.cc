// Circuit building blocks (walls, yawed boxes, floor relief) as geometry, and one of each seen
// through the real OSMesa renderer from the eye of a chair that has turned.
#include <gtest/gtest.h>

#include <cmath>

#include "render/camera_rig.h"
#include "render/offscreen_renderer.h"
#include "render/render_scene.h"

namespace pwsim::render {
namespace {

constexpr double kHalfPi = 1.5707963267948966;

Eigen::Vector3d Centre(const Quad& q) {
  return (q.corners[0] + q.corners[1] + q.corners[2] + q.corners[3]) / 4.0;
}

// Tests that every face of a wall and of a yawed box points away from the solid's centre.
TEST(CircuitElementsTest, PrismFacesPointOutwards) {
  std::vector<Quad> quads;
  AddWall(&quads, {1.0, 2.0}, {4.0, 3.0}, 0.2, 0.0, 2.5, Rgb{});
  ASSERT_EQ(quads.size(), 5U);  // 4 sides and the top
  const Eigen::Vector3d wall_centre(2.5, 2.5, 1.25);
  for (const Quad& q : quads) EXPECT_GT(QuadNormal(q).dot(Centre(q) - wall_centre), 0.0);
  quads.clear();
  AddYawedBox(&quads, {-1.0, 0.5}, 0.4, 0.2, 0.7, 0.0, 0.8, Rgb{});
  const Eigen::Vector3d box_centre(-1.0, 0.5, 0.4);
  for (const Quad& q : quads) EXPECT_GT(QuadNormal(q).dot(Centre(q) - box_centre), 0.0);
  // the long axis of the box is turned by the yaw: its x half extent lies along (cos, sin)
  double far = 0.0;
  for (const Quad& q : quads) {
    for (const auto& c : q.corners) {
      far = std::max(far, (c.head<2>() - Eigen::Vector2d(-1.0, 0.5)).dot(Eigen::Vector2d(std::cos(0.7), std::sin(0.7))));
    }
  }
  EXPECT_NEAR(far, 0.4, 1e-12);
}

/// Area of a planar quad (two triangles).
double QuadArea(const Quad& q) {
  return 0.5 * ((q.corners[1] - q.corners[0]).cross(q.corners[2] - q.corners[0]).norm() +
                (q.corners[2] - q.corners[0]).cross(q.corners[3] - q.corners[0]).norm());
}

// Tests the relief of a 5 x 4 vertex grid (0.5 m cells) with a raised inner vertex, a raised
// border corner and a dip at the border: one relief quad per cell with a corner off the floor
// (4 + 1 + 2), the other 5 cells as floor in runs along x (1 + 2 + 1 quads, 1.25 m² in all), and
// skirts on the 4 border edges off the floor, up at the corner, down into the dip.
TEST(CircuitElementsTest, HeightFieldDrawsReliefDipsAndFloorRuns) {
  HeightGrid grid;
  grid.cell = 0.5;
  grid.nx = 5;
  grid.ny = 4;
  grid.z.assign(20, 0.0);
  grid.z[1 * 5 + 2] = 0.04;   // a raised vertex at (1.0, 0.5)
  grid.z[0 * 5 + 4] = 0.02;   // a raised border corner at (2.0, 0.0)
  grid.z[3 * 5 + 1] = -0.03;  // a dip at the border, (0.5, 1.5)
  std::vector<Quad> quads;
  AddHeightField(&quads, grid, Rgb{}, TextureKind::kCushion, 0.0);
  int tops = 0, floors = 0, skirts_up = 0, skirts_down = 0;
  double top_z = 0.0, low_z = 0.0, floor_area = 0.0;
  for (const Quad& q : quads) {
    if (q.texture == TextureKind::kCushion) {
      ++tops;
      EXPECT_GT(QuadNormal(q).z(), 0.9);
      for (const auto& c : q.corners) top_z = std::max(top_z, c.z()), low_z = std::min(low_z, c.z());
    } else if (q.texture == TextureKind::kFloor) {
      ++floors;
      EXPECT_GT(QuadNormal(q).z(), 0.99);
      for (const auto& c : q.corners) EXPECT_EQ(c.z(), 0.0);
      floor_area += QuadArea(q);
    } else {
      double lowest = 0.0;
      for (const auto& c : q.corners) lowest = std::min(lowest, c.z());
      ++(lowest < 0.0 ? skirts_down : skirts_up);
    }
  }
  EXPECT_EQ(tops, 4 + 1 + 2);
  EXPECT_EQ(floors, 1 + 2 + 1);
  EXPECT_NEAR(floor_area, 5 * 0.25, 1e-12);
  EXPECT_EQ(skirts_up, 2);    // the corner's two border edges
  EXPECT_EQ(skirts_down, 2);  // the dip's two border edges
  EXPECT_DOUBLE_EQ(top_z, 0.04);
  EXPECT_DOUBLE_EQ(low_z, -0.03);
}

// Tests the floor around a relief: four quads covering the floor less the hole, exactly.
TEST(CircuitElementsTest, FloorAroundLeavesTheReliefsRectangle) {
  std::vector<Quad> quads;
  AddFloorAround(&quads, Eigen::AlignedBox2d(Eigen::Vector2d(0, 0), Eigen::Vector2d(10, 10)),
                 Eigen::AlignedBox2d(Eigen::Vector2d(2, 3), Eigen::Vector2d(4, 5)), 0.0, Rgb{});
  ASSERT_EQ(quads.size(), 4U);
  double area = 0.0;
  for (const Quad& q : quads) {
    area += QuadArea(q);
    for (const auto& c : q.corners) {  // no corner strictly inside the hole
      EXPECT_FALSE(c.x() > 2 && c.x() < 4 && c.y() > 3 && c.y() < 5);
    }
  }
  EXPECT_NEAR(area, 100.0 - 4.0, 1e-12);
}

// Tests a turned chair's eye: ChairPose3d puts the head at R p_VH from O_V with the yaw applied,
// and a yawed, rolled chair's eye looks along its heading.
TEST(CircuitElementsTest, EyeOfATurnedChair) {
  VisualSample s;
  s.x = 2.0;
  s.y = 1.0;
  s.yaw = kHalfPi;
  const Eigen::Isometry3d X_WC = EyePoseOn(ChairPose3d(s), s, {0.05, 0.0, 1.25}, true);
  EXPECT_NEAR(X_WC.translation().x(), 2.0, 1e-12);
  EXPECT_NEAR(X_WC.translation().y(), 1.05, 1e-12);
  EXPECT_NEAR(X_WC.translation().z(), 1.25, 1e-12);
  EXPECT_NEAR((X_WC.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-12);
  s.yaw = 0.0;
  s.roll = 0.1;  // left side up: the eye's y axis rises
  EXPECT_NEAR((ChairPose3d(s).linear() * Eigen::Vector3d::UnitY()).z(), std::sin(0.1), 1e-12);
}

// Tests walls and a box through the renderer: a red wall 3 m ahead of a chair that has turned
// left by 90° fills the centre of the view; a green box on the floor between them shows below
// the centre; the same chair facing the other way sees neither.
TEST(CircuitElementsTest, TurnedChairSeesTheWallAheadOfIt) {
  RenderScene scene;
  const Rgb grey{0.6F, 0.6F, 0.6F}, red{0.9F, 0.1F, 0.1F}, green{0.1F, 0.8F, 0.2F};
  scene.world.push_back(Quad{{Eigen::Vector3d(-10, -10, 0), Eigen::Vector3d(10, -10, 0),
                              Eigen::Vector3d(10, 10, 0), Eigen::Vector3d(-10, 10, 0)},
                             grey, TextureKind::kNone, 1.0});
  AddWall(&scene.world, {-3.0, 4.0}, {3.0, 4.0}, 0.2, 0.0, 2.5, red, TextureKind::kNone);
  AddYawedBox(&scene.world, {0.0, 2.0}, 0.3, 0.3, 0.4, 0.0, 0.5, green);
  RenderConfig config;
  config.width = 160;
  config.height = 90;
  OffscreenRenderer renderer(scene, config);
  VisualSample s;
  s.y = 0.5;
  s.yaw = kHalfPi;  // facing +y, towards the wall
  auto pixel = [](const ImageView& image, int x, int y) {
    const std::uint8_t* p = image.bgra + 4 * (y * image.width + x);
    return std::array<int, 3>{p[2], p[1], p[0]};
  };
  const std::array<double, 3> head{0.05, 0.0, 1.25};
  ImageView image = renderer.Render(ChairPose3d(s), EyePoseOn(ChairPose3d(s), s, head, true), 0.0);
  const auto centre = pixel(image, 80, 40);
  EXPECT_GT(centre[0], 150);
  EXPECT_LT(centre[1], 60);
  const auto low = pixel(image, 80, 80);
  EXPECT_GT(low[1], 120);
  EXPECT_LT(low[0], 60);
  s.yaw = -kHalfPi;  // facing away
  image = renderer.Render(ChairPose3d(s), EyePoseOn(ChairPose3d(s), s, head, true), 0.0);
  for (int y = 0; y < 90; y += 5) {
    for (int x = 0; x < 160; x += 5) {
      const auto p = pixel(image, x, y);
      ASSERT_FALSE(p[0] > 150 && p[1] < 60) << x << "," << y;
      ASSERT_FALSE(p[1] > 120 && p[0] < 60) << x << "," << y;
    }
  }
}

// Tests that a dip in the floor is seen: a 2 m x 2 m pit 0.3 m deep ahead of the chair (a red
// relief, floor around it from AddFloorAround) shows red pixels below the horizon; no floor is
// drawn over it.
TEST(CircuitElementsTest, ChairSeesADipAheadOfIt) {
  RenderScene scene;
  const Rgb grey{0.6F, 0.6F, 0.6F}, red{0.9F, 0.1F, 0.1F};
  HeightGrid grid;
  grid.x0 = 1.5;
  grid.y0 = -1.0;
  grid.cell = 0.5;
  grid.nx = 5;
  grid.ny = 5;
  grid.z.assign(25, 0.0);
  for (int j = 1; j < 4; ++j) {
    for (int i = 1; i < 4; ++i) grid.z[static_cast<std::size_t>(j * 5 + i)] = -0.3;
  }
  AddHeightField(&scene.world, grid, red, TextureKind::kNone, 0.0, grey);
  AddFloorAround(&scene.world, Eigen::AlignedBox2d(Eigen::Vector2d(-10, -10), Eigen::Vector2d(10, 10)),
                 Eigen::AlignedBox2d(Eigen::Vector2d(1.5, -1.0), Eigen::Vector2d(3.5, 1.0)), 0.0, grey);
  RenderConfig config;
  config.width = 160;
  config.height = 90;
  OffscreenRenderer renderer(scene, config);
  VisualSample s;
  const std::array<double, 3> head{0.05, 0.0, 1.25};
  const ImageView image = renderer.Render(ChairPose3d(s), EyePoseOn(ChairPose3d(s), s, head, true), 0.0);
  int red_pixels = 0, red_above_horizon = 0;
  for (int y = 0; y < 90; ++y) {
    for (int x = 0; x < 160; ++x) {
      const std::uint8_t* p = image.bgra + 4 * (y * image.width + x);
      if (p[2] > 120 && p[1] < 60 && p[0] < 60) ++(y < 45 ? red_above_horizon : red_pixels);
    }
  }
  EXPECT_GT(red_pixels, 200);
  EXPECT_EQ(red_above_horizon, 0);
}

}  // namespace
}  // namespace pwsim::render
