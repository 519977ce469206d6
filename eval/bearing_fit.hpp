#pragma once
// Robust two-view fits on matched bearing vectors (unit rays of camera.hpp), as a tracker fits
// its matches: they work for any lens and beyond 90 degrees of incidence, where image
// coordinates of a perspective model do not exist.
// - A plane-induced homography between bearings: toolkit/bearing_homography.hpp.
// - An essential matrix by OpenGV's 5-point solver (Nister) in RANSAC, factored into the
//   relative pose that puts the inliers in front of both cameras and refined on them by
//   OpenGV's non-linear optimisation. Deterministic: the same input gives the same fit.
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "toolkit/bearing_homography.hpp"

namespace mdbrief::eval {

struct EssentialFit {
  // a . (E b) = 0 for matching bearings; E = [t]x R with camera b in the frame of camera a (a
  // point X_b of b's frame is R X_b + t in a's frame), |t| = 1.
  cv::Matx33d essential;
  std::vector<char> inliers;
  int inlierCount = 0;
};

// Inlier: b within the threshold of the epipolar plane of a; the pixel threshold becomes an
// angle through `pixelsPerRadian` (one value for the camera). Empty with fewer than 5
// correspondences or no model.
std::optional<EssentialFit> fitEssential(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                                         double pixelsPerRadian, const RansacOptions& options);

// Angle (radians) between bearing `a` and the epipolar plane of `b` under the fit.
double epipolarAngle(const EssentialFit& fit, const cv::Vec3d& a, const cv::Vec3d& b);

}  // namespace mdbrief::eval
