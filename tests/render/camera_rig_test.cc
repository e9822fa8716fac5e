#include "render/camera_rig.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pwsim::render {
namespace {

const std::array<double, 3> kHead{0.05, 0.0, 1.25};

// Tests that a nose-up pitch tilts the line of sight (C's x) upwards and round-trips.
TEST(CameraRigTest, NoseUpPitchLooksUp) {
  const Eigen::Matrix3d R = PitchRollRotation(0.1, 0.0);
  EXPECT_GT((R * Eigen::Vector3d::UnitX()).z(), 0.0);
  const auto pitch_roll = PitchRollOf(PitchRollRotation(0.1, -0.03));
  EXPECT_NEAR(pitch_roll[0], 0.1, 1e-12);
  EXPECT_NEAR(pitch_roll[1], -0.03, 1e-12);
}

// Tests that a right-side-down roll raises the left side (C's y axis gains height).
TEST(CameraRigTest, RightSideDownRollRaisesLeft) {
  EXPECT_GT((PitchRollRotation(0.0, 0.1) * Eigen::Vector3d::UnitY()).z(), 0.0);
}

// Tests the frame algebra X_WC = X_WV X_VH X_HC: the eye sits at the head offset on the chair.
TEST(CameraRigTest, EyeAtHeadOnChair) {
  VisualSample s;
  s.x = 2.0;
  s.z = 0.05;
  s.pitch = 0.2;
  const Eigen::Isometry3d X_WC = EyePose(s, kHead, true);
  const Eigen::Vector3d expected = Eigen::Vector3d(2.0, 0.0, 0.05) +
                                   PitchRollRotation(0.2, 0.0) * Eigen::Vector3d(0.05, 0, 1.25);
  EXPECT_TRUE(X_WC.translation().isApprox(expected, 1e-12));
  EXPECT_NEAR(PitchRollOf(X_WC.linear())[0], 0.2, 1e-12);
}

// Tests that the eyes are one IPD apart along the head's y, left eye on the left (+y).
TEST(CameraRigTest, StereoEyesAreOneIpdApart) {
  VisualSample s;
  s.pitch = 0.1;
  const Eigen::Isometry3d left = EyePose(s, kHead, true, Eye::kLeft, 0.064);
  const Eigen::Isometry3d right = EyePose(s, kHead, true, Eye::kRight, 0.064);
  const Eigen::Vector3d d = left.linear().transpose() * (left.translation() - right.translation());
  EXPECT_TRUE(d.isApprox(Eigen::Vector3d(0, 0.064, 0), 1e-12));
}

// Tests that the tilt-coordination angle is removed from the view, or kept when asked to.
TEST(CameraRigTest, TiltRemovedOrKept) {
  VisualSample s;
  s.pitch = 0.02;
  s.tilt_pitch = 0.05;
  s.tilt_roll = 0.01;
  const auto removed = PitchRollOf(EyePose(s, kHead, true).linear());
  const auto kept = PitchRollOf(EyePose(s, kHead, false).linear());
  EXPECT_NEAR(removed[0], 0.02, 1e-12);
  EXPECT_NEAR(removed[1], 0.0, 1e-12);
  EXPECT_NEAR(kept[0], 0.07, 1e-3);
  EXPECT_NEAR(kept[1], 0.01, 1e-3);
}

}  // namespace
}  // namespace pwsim::render
