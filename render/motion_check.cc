#include "render/motion_check.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <cmath>
#include <limits>

namespace pwsim::render {

struct FrameMotionEstimator::Impl {
  int scale_shifts{0};  ///< the frame is halved this many times
  cv::Matx33d K;
  cv::Mat previous;     ///< grey, scaled
  cv::Mat grey, small;
};

FrameMotionEstimator::FrameMotionEstimator(int width, int height, double fov_y_deg,
                                           int max_width)
    : impl_(std::make_unique<Impl>()) {
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

FrameMotion FrameMotionEstimator::Push(const ImageView& frame, double eye_height) {
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
    cv::calcOpticalFlowPyrLK(d.previous, d.grey, corners, tracked, status, error,
                             cv::Size(21, 21), 3);
  }
  std::vector<cv::Point2f> all0, all1, floor0, floor1;
  const double horizon_margin = 0.12 * d.grey.rows;
  for (std::size_t i = 0; i < status.size(); ++i) {
    if (!status[i]) continue;
    all0.push_back(corners[i]);
    all1.push_back(tracked[i]);
    // The floor: well below the image centre (the horizon when the view is level).
    if (corners[i].y > d.K(1, 2) + horizon_margin) {
      floor0.push_back(corners[i]);
      floor1.push_back(tracked[i]);
    }
  }
  motion.tracked = static_cast<int>(all0.size());
  d.grey.copyTo(d.previous);

  // 2. The floor homography H = K (R + t nᵀ/d) K⁻¹, decomposed; the solution whose plane normal
  //    points up (−y in OpenCV's camera axes: x right, y down, z ahead) is the floor.
  cv::Matx33d R = cv::Matx33d::eye();
  cv::Vec3d t_over_d(0, 0, 0);
  if (floor0.size() >= 12) {
    cv::Mat inlier_mask;
    const cv::Mat H = cv::findHomography(floor0, floor1, cv::RANSAC, 1.0, inlier_mask, 2000, 0.999);
    if (!H.empty()) {
      motion.inliers = cv::countNonZero(inlier_mask);
      std::vector<cv::Mat> rotations, translations, normals;
      cv::decomposeHomographyMat(H, cv::Mat(d.K), rotations, translations, normals);
      double best = -2.0;
      for (std::size_t s = 0; s < normals.size(); ++s) {
        const double up = -normals[s].at<double>(1);
        if (up > best) {
          best = up;
          R = cv::Matx33d(rotations[s]);
          t_over_d = cv::Vec3d(translations[s]);
        }
      }
      motion.valid = best > 0.7;
    }
  } else if (all0.size() >= 8) {
    // No floor in view: a rotation-only homography of everything tracked.
    cv::Mat inlier_mask;
    const cv::Mat H = cv::findHomography(all0, all1, cv::RANSAC, 1.0, inlier_mask, 2000, 0.999);
    if (!H.empty()) {
      motion.inliers = cv::countNonZero(inlier_mask);
      cv::Matx33d M = d.K.inv() * cv::Matx33d(H) * d.K;
      M *= 1.0 / std::cbrt(cv::determinant(M));
      R = M;
      motion.valid = true;
    }
  }
  // 3. Rows of R are the new camera's axes in the old one: a nose-up pitch δ puts sin δ at
  //    R(1,2) (y down, z ahead); a right-side-down roll φ puts sin φ at R(0,1).
  motion.pitch_delta = std::atan2(R(1, 2), R(2, 2));
  motion.roll_delta = std::atan2(R(0, 1), R(1, 1));
  // x2 = R x1 + t: the camera moving up by Δz (−y) gives t_y = +Δz / d.
  motion.vertical_delta = t_over_d[1] * eye_height;
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
    const double e = estimate[static_cast<std::size_t>(k)], r = reference[static_cast<std::size_t>(k)];
    if (std::isfinite(e) && std::isfinite(r)) sum += (e - r) * (e - r), ++m;
  }
  out.rms_error = m > 0 ? std::sqrt(sum / m) : 0.0;
  return out;
}

}  // namespace pwsim::render
