#pragma once
// A robust plane-induced homography between matched bearing vectors (unit rays of camera.hpp),
// as a tracker fits its matches: it works for any lens and beyond 90 degrees of incidence, where
// image coordinates of a perspective model do not exist. b ~ H a with a positive factor (a
// plane seen from one side, or a pure rotation): 4-point DLT in RANSAC, refitted on its inliers,
// then refined by Levenberg-Marquardt on their pixel residuals. Deterministic: the same input
// gives the same fit. Used by the evaluation (eval/bearing_fit.hpp adds the essential matrix) and
// by `mdbrief draw` and `match` to tell matches consistent with one such motion.
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief {

// Pixels per radian of ray angle around `pixel` (the mean of both image axes), to turn an angle
// between rays into pixels there. Empty where the camera has no ray for the neighbourhood.
std::optional<double> pixelsPerRadian(const Camera& camera, const cv::Point2d& pixel);

struct RansacOptions {
  double thresholdPx = 2.0;   // inlier: the model's prediction within this many pixels
  double confidence = 0.999;  // stop when a better model is this unlikely
  int maxIterations = 3000;
  std::uint64_t seed = 1;
};

// RANSAC iterations that find an all-inlier sample of `sampleSize` with `confidence` at an inlier
// share `w`, at most `cap`.
int ransacIterationsNeeded(double w, int sampleSize, double confidence, int cap);

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

}  // namespace mdbrief
