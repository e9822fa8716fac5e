#include "render/camera_rig.h"

#include <algorithm>
#include <cmath>

#include "render/road_scene.h"

namespace pwsim::render {

Eigen::Matrix3d PitchRollRotation(double pitch, double roll) {
  return (Eigen::AngleAxisd(-pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

std::array<double, 2> PitchRollOf(const Eigen::Matrix3d& R) {
  // R = Ry(-θ) Rx(φ): R(2,0) = sin θ, R(2,1) = cos θ sin φ, R(2,2) = cos θ cos φ.
  return {std::asin(std::clamp(R(2, 0), -1.0, 1.0)), std::atan2(R(2, 1), R(2, 2))};
}

Eigen::Isometry3d ChairPose(const VisualSample& sample) {
  Eigen::Isometry3d X_WV = Eigen::Isometry3d::Identity();
  X_WV.linear() = PitchRollRotation(sample.pitch, 0.0);
  X_WV.translation() = Eigen::Vector3d(sample.x, 0.0, sample.z);
  return X_WV;
}

Eigen::Isometry3d ChairPose3d(const VisualSample& sample) {
  return CarPose(sample.x, sample.y, sample.z, sample.yaw, sample.roll, sample.pitch);
}

Eigen::Isometry3d EyePose(const VisualSample& sample, const std::array<double, 3>& head_offset,
                          bool remove_tilt, Eye eye, double ipd) {
  return EyePoseOn(ChairPose(sample), sample, head_offset, remove_tilt, eye, ipd);
}

Eigen::Isometry3d EyePoseOn(const Eigen::Isometry3d& X_WV, const VisualSample& sample,
                            const std::array<double, 3>& head_offset, bool remove_tilt, Eye eye,
                            double ipd) {
  // X_VH: the head on the chair; the tracked platform tilt stays in the view unless removed.
  Eigen::Isometry3d X_VH = Eigen::Isometry3d::Identity();
  X_VH.translation() = Eigen::Vector3d(head_offset[0], head_offset[1], head_offset[2]);
  if (!remove_tilt) X_VH.linear() = PitchRollRotation(sample.tilt_pitch, sample.tilt_roll);
  // X_HC: the eye, half the IPD to the left (+y) or right (-y) of the head centre.
  Eigen::Isometry3d X_HC = Eigen::Isometry3d::Identity();
  const double side = eye == Eye::kLeft ? 0.5 : (eye == Eye::kRight ? -0.5 : 0.0);
  X_HC.translation() = Eigen::Vector3d(0.0, side * ipd, 0.0);
  return X_WV * X_VH * X_HC;
}

}  // namespace pwsim::render
