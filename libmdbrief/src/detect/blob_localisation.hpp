#pragma once
// Where a blob lies, measured again on the input image at the blob's own scale.
//
// A level above the input is a bilinear reduction of the level before it, as cv::ORB builds its
// pyramid: the reduction's sampling phase changes from pixel to pixel, so each level pixel is
// blurred a little differently, and a blob's response peak moves by a fraction of a level pixel
// that depends on where the blob falls on the level's grid. Measured on a rendered plane, exact
// truth: keypoints of levels 5 and up lie 0.47 px (median) from the true point at their levels'
// positions, 0.25 px located on the input (docs/RESULTS.md "Keypoints located on the input").
#include <optional>

#include <opencv2/core.hpp>

namespace mdbrief::detail {

// The widest smoothing a blob is located at, input pixels.
constexpr double kMaxSigma = 16.0;
// Blobs wider than this are located on the input's halving (cv::pyrDown: a binomial 5-tap kernel
// of variance 1 pixel^2, then every second pixel, the same phase everywhere), where their kernel
// is half as wide: the cost of a blob grows with the square of its width, and the coarsest levels
// would cost as much as all the others. Narrower ones on the input itself, where the 3x3 fit has
// its full resolution (halving them too lost poster-dev fits within 1 px).
constexpr double kHalvedFromSigma = 5.5;

// The maximum of det(Hessian) of the input smoothed by a Gaussian of `sigma` input pixels (in
// (0, kMaxSigma]; 3 sigma wide, borders reflected as BORDER_REFLECT_101) nearest to `start`
// (input pixels): a quadratic fit to the response at the 3x3 pixels around the nearest pixel,
// stepping one pixel towards the vertex while the vertex lies outside that pixel, at most a few
// steps. On `input8u` (CV_8UC1), or above kHalvedFromSigma on `half8u`, cv::pyrDown(input8u).
// nullopt when the response there has no cap (not a maximum), or when the vertex lies further
// than maxDistance (input pixels) from start. Plain float arithmetic in a fixed order: the same
// bits at every SIMD level. Safe to call from several threads.
std::optional<cv::Point2d> relocaliseBlob(const cv::Mat& input8u, const cv::Mat& half8u, const cv::Point2d& start,
                                          double sigma, double maxDistance);

}  // namespace mdbrief::detail
