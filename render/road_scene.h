#pragma once
// The car simulator's world as render data (no OSG): a ground plane to the horizon, a road of
// lanes along a centre line with edge lines and dashed lane lines, traffic cones, and the car's
// cabin (bonnet, dashboard, pillars) in the vehicle frame V. The dashboard instruments (engine
// speed, vehicle speed, gear) are drawn on each frame by dashboard.h, like the indicators of
// seed 001's cabin.
//
//   RenderScene rs = BuildRoadScene(road, cabin);
//   renderer.Render(CarPose(x, y, yaw, roll, pitch), EyePoseInCar(...), t);

#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "render/render_scene.h"

namespace pwsim::render {

struct RoadGeometry {
  std::vector<std::array<double, 2>> centre;  ///< [m] in W: centre of the rightmost lane
  double lane_width{3.5};                     ///< [m]
  int lanes{2};                               ///< lanes; the others lie to the left
  std::vector<std::array<double, 2>> cones;   ///< [m] cone positions in W
  double ground_half_size{3000.0};            ///< [m] ground plane around the road
};

struct CabinGeometry {
  double cg_height{0.55};    ///< [m] V's origin (CoG) above the road
  double front{2.0};         ///< [m] front bumper ahead of the CoG
  double half_width{0.9};    ///< [m]
  double windscreen_x{0.8};  ///< [m] base of the windscreen ahead of the CoG
};

/// World (ground, road, markings, cones) and cabin quads.
RenderScene BuildRoadScene(const RoadGeometry& road, const CabinGeometry& cabin, std::uint32_t texture_seed);

/// X_WV of the car: position of its CoG (x, y, cg_height), yaw ψ, roll φ (left side up) and
/// pitch θ (nose up): R = Rz(ψ) Ry(-θ) Rx(φ).
Eigen::Isometry3d CarPose(double x, double y, double cg_height, double yaw, double roll, double pitch);

/// X_WC for an eye at p_VH (head_offset) in the car: looks along the car's x.
Eigen::Isometry3d EyePoseInCar(const Eigen::Isometry3d& X_WV, const std::array<double, 3>& head_offset);

}  // namespace pwsim::render
