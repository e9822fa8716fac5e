#include "render/motion_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace pwsim::render {
namespace {

// Floor (ceiling) points are taken at least this far below (above) the optical axis, as the
// tangent of the angle: clear of the horizon band where the far wall is.
constexpr double kFloorMinSlope = 0.10;
constexpr double kCeilingMinSlope = 0.25;

/// ω of R = exp([ω]×) (the rotation vector; ≈ the skew part of R for small angles).
cv::Vec3d RotationVector(const cv::Matx33d& R) {
  cv::Vec3d omega;
  cv::Rodrigues(R, omega);
  return omega;
}

/// The camera's angles from ω: R = I + [ω]× holds the new camera's axes (rows) in the old one
/// (x right, y down, z ahead): a nose-up pitch δ puts sin δ at R(1,2) = −ω_x; a right-side-down
/// roll φ puts sin φ at R(0,1) = −ω_z; a turn ψ to the left puts the new line of sight's −sin ψ
/// at R(2,0) = −ω_y.
void SetRotation(const cv::Vec3d& omega, FrameMotion& motion) {
  motion.pitch_delta = -omega[0];
  motion.yaw_delta = omega[1];
  motion.roll_delta = -omega[2];
}

/// [px] median flow below which the image is taken not to have moved.
constexpr double kStillFlow_px = 0.02;

/// kRigid (motion_check.h): the rotation between the frames from the tracked points p₀ → p₁.
/// Returns false where the essential matrix finds too few inliers.
bool RigidRotation(const std::vector<cv::Point2f>& p0, const std::vector<cv::Point2f>& p1,
                   const cv::Matx33d& K, cv::Vec3d& omega, int& inliers) {
  constexpr int kMinInliers = 12;
  // An image that did not move (the chair standing still) has no essential matrix: ω = 0.
  std::vector<double> flow(p0.size());
  for (std::size_t i = 0; i < p0.size(); ++i) flow[i] = cv::norm(p1[i] - p0[i]);
  const auto mid = flow.begin() + static_cast<long>(flow.size() / 2);
  std::nth_element(flow.begin(), mid, flow.end());
  if (*mid <= kStillFlow_px) {
    omega = cv::Vec3d(0, 0, 0);
    inliers = static_cast<int>(p0.size());
    return true;
  }
  cv::Mat mask;
  const cv::Mat E = cv::findEssentialMat(p0, p1, cv::Mat(K), cv::USAC_ACCURATE, 0.999, 1.0, mask);
  if (E.rows != 3 || E.cols != 3) return false;  // several solutions stacked: degenerate
  inliers = cv::countNonZero(mask);
  if (inliers < kMinInliers) return false;
  // E = [t]× R has two rotations (the "twisted pair", π apart about the baseline); between
  // consecutive frames the camera turns by a few degrees at most, so the smaller one is R.
  cv::Mat R1, R2, t;
  cv::decomposeEssentialMat(E, R1, R2, t);
  const cv::Vec3d omega1 = RotationVector(cv::Matx33d(R1)), omega2 = RotationVector(cv::Matx33d(R2));
  omega = cv::norm(omega1) <= cv::norm(omega2) ? omega1 : omega2;
  return true;
}

}  // namespace

struct FrameMotionEstimator::Impl {
  SceneModel model{SceneModel::kFloorPlane};
  int scale_shifts{0};  ///< the frame is halved this many times
  cv::Matx33d K;
  cv::Mat previous;  ///< grey, scaled
  cv::Mat grey, small;
};

FrameMotionEstimator::FrameMotionEstimator(int width, int height, double fov_y_deg, int max_width,
                                           SceneModel model)
    : impl_(std::make_unique<Impl>()) {
  impl_->model = model;
  int w = width, h = height;
  while (w > max_width) {
    w /= 2;
    h /= 2;
    ++impl_->scale_shifts;
  }
  const double f = (h / 2.0) / std::tan(fov_y_deg * M_PI / 360.0);
  impl_->K = cv::Matx33d(f, 0, w / 2.0, 0, f, h / 2.0, 0, 0, 1);
}

FrameMotionEstimator::~FrameMotionEstimator() = default;

FrameMotion FrameMotionEstimator::Push(const ImageView& frame, double eye_height,
                                       double ceiling_clearance) {
  Impl& d = *impl_;
  const cv::Mat bgra(frame.height, frame.width, CV_8UC4, const_cast<std::uint8_t*>(frame.bgra));
  cv::cvtColor(bgra, d.grey, cv::COLOR_BGRA2GRAY);
  for (int i = 0; i < d.scale_shifts; ++i) {
    cv::pyrDown(d.grey, d.small);
    std::swap(d.grey, d.small);
  }
  FrameMotion motion;
  if (d.previous.empty()) {
    d.grey.copyTo(d.previous);
    return motion;
  }

  // 1. Corners in the previous frame, tracked into this one.
  std::vector<cv::Point2f> corners, tracked;
  cv::goodFeaturesToTrack(d.previous, corners, 600, 0.005, 6);
  std::vector<unsigned char> status;
  std::vector<float> error;
  if (corners.size() >= 8) {
    cv::calcOpticalFlowPyrLK(d.previous, d.grey, corners, tracked, status, error, cv::Size(21, 21),
                             3);
  }
  std::vector<cv::Point2f> all0, all1;
  for (std::size_t i = 0; i < status.size(); ++i) {
    if (!status[i]) continue;
    all0.push_back(corners[i]);
    all1.push_back(tracked[i]);
  }
  motion.tracked = static_cast<int>(all0.size());
  d.grey.copyTo(d.previous);
  cv::Vec3d omega(0, 0, 0), t(0, 0, 0);
  if (d.model == SceneModel::kRigid) {
    motion.valid = all0.size() >= 8 && RigidRotation(all0, all1, d.K, omega, motion.inliers);
    SetRotation(omega, motion);
    return motion;
  }

  // 2. The floor nᵀX = h (n down, h the eye height) and, when given, the ceiling (n up, its
  //    clearance above the eye) map x₁ to x₂ ∝ R x₁ + t w with inverse depth w = nᵀx₁ / h. With
  //    R ≈ I + [ω]× this is linear in (ω, t); solved by least squares, re-weighted to drop
  //    points off the planes (walls, cushion, mismatches). Pitch moves floor and ceiling points
  //    the same way, heave moves them apart: using both keeps the two separate.
  const double f = d.K(0, 0), cx = d.K(0, 2), cy = d.K(1, 2);
  struct PlanePoint {
    double u1, v1, u2, v2, w;
  };
  std::vector<PlanePoint> floor;
  for (std::size_t i = 0; i < all0.size(); ++i) {
    const double u1 = (all0[i].x - cx) / f, v1 = (all0[i].y - cy) / f;
    const double u2 = (all1[i].x - cx) / f, v2 = (all1[i].y - cy) / f;
    if (std::abs(u1) > 0.35 * d.grey.cols / f) continue;  // side walls
    if (v1 > kFloorMinSlope) floor.push_back({u1, v1, u2, v2, v1 / eye_height});
    if (ceiling_clearance > 0 && v1 < -kCeilingMinSlope) {
      floor.push_back({u1, v1, u2, v2, -v1 / ceiling_clearance});
    }
  }
  if (floor.size() >= 20) {
    std::vector<double> weight(floor.size(), 1.0);
    for (int iteration = 0; iteration < 4; ++iteration) {
      cv::Matx66d AtA = cv::Matx66d::zeros();
      cv::Vec6d Atb(0, 0, 0, 0, 0, 0);
      for (std::size_t i = 0; i < floor.size(); ++i) {
        if (weight[i] == 0.0) continue;
        const auto [u1, v1, u2, v2, w] = floor[i];
        const cv::Vec6d row_u(u2 * v1, -u2 * u1 - 1.0, v1, -w, 0.0, u2 * w);
        const cv::Vec6d row_v(v2 * v1 + 1.0, -v2 * u1, -u1, 0.0, -w, v2 * w);
        AtA += row_u * row_u.t() + row_v * row_v.t();
        Atb += row_u * (u1 - u2) + row_v * (v1 - v2);
      }
      cv::Vec6d x;
      if (!cv::solve(AtA, Atb, x, cv::DECOMP_CHOLESKY)) break;
      omega = cv::Vec3d(x[0], x[1], x[2]);
      t = cv::Vec3d(x[3], x[4], x[5]);
      // Residuals in pixels; keep points within 3× the median (at least 0.3 px).
      std::vector<double> residual(floor.size());
      for (std::size_t i = 0; i < floor.size(); ++i) {
        const auto [u1, v1, u2, v2, w] = floor[i];
        const cv::Vec3d a(u1 + omega[1] - omega[2] * v1 + t[0] * w,
                          v1 + omega[2] * u1 - omega[0] + t[1] * w,
                          1.0 + omega[0] * v1 - omega[1] * u1 + t[2] * w);
        residual[i] = f * std::hypot(a[0] / a[2] - u2, a[1] / a[2] - v2);
      }
      std::vector<double> sorted = residual;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                       sorted.end());
      const double limit = std::max(0.3, 3.0 * sorted[sorted.size() / 2]);
      motion.inliers = 0;
      for (std::size_t i = 0; i < floor.size(); ++i) {
        weight[i] = residual[i] <= limit ? 1.0 : 0.0;
        motion.inliers += weight[i] > 0 ? 1 : 0;
      }
    }
    motion.valid = motion.inliers >= 12;
  } else if (all0.size() >= 8) {
    // No floor in view: a rotation-only homography of everything tracked.
    cv::Mat inlier_mask;
    const cv::Mat H = cv::findHomography(all0, all1, cv::RANSAC, 1.0, inlier_mask, 2000, 0.999);
    if (!H.empty()) {
      motion.inliers = cv::countNonZero(inlier_mask);
      cv::Matx33d M = d.K.inv() * cv::Matx33d(H) * d.K;
      M *= 1.0 / std::cbrt(cv::determinant(M));
      omega = cv::Vec3d((M(2, 1) - M(1, 2)) / 2, (M(0, 2) - M(2, 0)) / 2, (M(1, 0) - M(0, 1)) / 2);
      motion.valid = true;
    }
  }
  // 3. X₂ = R X₁ + t: the eye moving up by Δz (−y) gives t_y = +Δz.
  SetRotation(omega, motion);
  motion.vertical_delta = t[1];
  return motion;
}

SeriesComparison CompareSeries(const std::vector<double>& estimate,
                               const std::vector<double>& reference, double dt, int max_lag) {
  SeriesComparison out;
  const int n = static_cast<int>(std::min(estimate.size(), reference.size()));
  // Pearson correlation of estimate[k] with reference[k - lag] over the valid overlap.
  auto correlate = [&](int lag, double* slope, int* count) {
    double se = 0, sr = 0, see = 0, srr = 0, ser = 0;
    int m = 0;
    for (int k = std::max(0, lag); k < std::min(n, n + lag); ++k) {
      const double e = estimate[static_cast<std::size_t>(k)];
      const double r = reference[static_cast<std::size_t>(k - lag)];
      if (!std::isfinite(e) || !std::isfinite(r)) continue;
      se += e, sr += r, see += e * e, srr += r * r, ser += e * r;
      ++m;
    }
    if (slope != nullptr) *slope = srr > 0 ? ser / srr : 0.0;
    if (count != nullptr) *count = m;
    if (m < 3) return 0.0;
    const double cov = ser - se * sr / m;
    const double ve = see - se * se / m, vr = srr - sr * sr / m;
    return (ve > 0 && vr > 0) ? cov / std::sqrt(ve * vr) : 0.0;
  };
  int best_lag = 0;
  double best = -std::numeric_limits<double>::infinity();
  for (int lag = -max_lag; lag <= max_lag; ++lag) {
    const double c = correlate(lag, nullptr, nullptr);
    if (c > best) best = c, best_lag = lag;
  }
  out.correlation = correlate(best_lag, &out.gain, &out.samples);
  // Sub-sample lag from a parabola through the correlation around its peak.
  double lag = best_lag;
  if (best_lag > -max_lag && best_lag < max_lag) {
    const double cm = correlate(best_lag - 1, nullptr, nullptr);
    const double cp = correlate(best_lag + 1, nullptr, nullptr);
    const double curvature = cm - 2 * out.correlation + cp;
    if (curvature < 0) lag += 0.5 * (cm - cp) / curvature;
  }
  out.lag = lag * dt;
  double sum = 0;
  int m = 0;
  for (int k = 0; k < n; ++k) {
    const double e = estimate[static_cast<std::size_t>(k)],
                 r = reference[static_cast<std::size_t>(k)];
    if (std::isfinite(e) && std::isfinite(r)) sum += (e - r) * (e - r), ++m;
  }
  out.rms_error = m > 0 ? std::sqrt(sum / m) : 0.0;
  return out;
}

}  // namespace pwsim::render
