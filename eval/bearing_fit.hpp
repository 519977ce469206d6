#pragma once
// Robust two-view fits on matched bearing vectors (unit rays of camera.hpp), as a tracker fits
// its matches: they work for any lens and beyond 90 degrees of incidence, where image
// coordinates of a perspective model do not exist.
// - A plane-induced homography between bearings (b ~ H a with a positive factor: a plane seen
//   from one side, or a pure rotation): 4-point DLT in RANSAC, refitted on its inliers, then
//   refined by Levenberg-Marquardt on their pixel residuals.
// - An essential matrix by OpenGV's 5-point solver (Nister) in RANSAC, factored into the
//   relative pose that puts the inliers in front of both cameras and refined on them by
//   OpenGV's non-linear optimisation.
// Both are deterministic: the same input gives the same fit.
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera.hpp"

namespace mdbrief::eval {

// Pixels per radian of ray angle around `pixel` (the mean of both image axes), to turn an angle
// between rays into pixels there. Empty where the camera has no ray for the neighbourhood.
std::optional<double> pixelsPerRadian(const Camera& camera, const cv::Point2d& pixel);

struct RansacOptions {
  double thresholdPx = 2.0;   // inlier: the model's prediction within this many pixels
  double confidence = 0.999;  // stop when a better model is this unlikely
  int maxIterations = 3000;
  std::uint64_t seed = 1;
};

struct HomographyFit {
  cv::Matx33d h;               // b ~ h * a, scaled so that h * a . b > 0 for inliers
  std::vector<char> inliers;   // per correspondence
  int inlierCount = 0;
};

// a[k], b[k]: bearings of correspondence k; scaleB[k]: pixels per radian at b's pixel, which turns
// the angle between b[k] and h a[k] into the pixel residual. Empty when there are fewer than 4
// correspondences or no sample gives a usable model.
std::optional<HomographyFit> fitBearingHomography(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                                                  const std::vector<double>& scaleB, const RansacOptions& options);

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
