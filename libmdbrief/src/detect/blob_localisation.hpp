#pragma once
// Where a blob lies, measured again on the input image at the blob's own scale.
//
// A level above the input is a bilinear reduction of the level before it, as cv::ORB builds its
// pyramid: the reduction's sampling phase changes from pixel to pixel, so each level pixel is
// blurred a little differently, and a blob's response peak moves by a fraction of a level pixel
// that depends on where the blob falls on the level's grid. Measured on a EuRoC frame and a copy
// shifted by a known sub-pixel amount: a level-5 blob (2.4 input pixels per level pixel) moves by
// 0.31 px (median) more than the shift; its determinant of the Hessian on the input, smoothed to
// the same scale, moves by 0.06 px (docs/RESULTS.md "Keypoints located on the input").
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

namespace mdbrief::detail {

// The input image and its halvings by cv::pyrDown (a binomial 5-tap kernel, variance 1 pixel^2
// of the image it halves, then every second pixel: the same phase everywhere), on which blobs are
// located again: each on the coarsest of them where its smoothing still spans kMinSigma pixels,
// which keeps the cost per blob about the same whatever its scale.
class BlobLocaliser {
 public:
  // input8u: CV_8UC1, the pyramid's input level. halvings: how many to make (0..2), enough for
  // the widest blob to be located.
  BlobLocaliser(const cv::Mat& input8u, int halvings);
  // How many halvings a blob of `sigma` input pixels needs (0..2).
  static int halvingsFor(double sigma);

  // The maximum of det(Hessian) of the image smoothed to `sigma` input pixels (3 sigma wide,
  // borders reflected as BORDER_REFLECT_101) nearest to `start` (input pixels): a quadratic fit
  // to the response at the 3x3 pixels around the nearest pixel, stepping one pixel towards the
  // vertex while the vertex lies outside that pixel, at most a few steps. nullopt when the
  // response there has no cap (not a maximum), or when the vertex lies further than maxDistance
  // (input pixels) from start. Plain float arithmetic in a fixed order: the same bits at every
  // SIMD level. Safe to call from several threads.
  std::optional<cv::Point2d> relocalise(const cv::Point2d& start, double sigma, double maxDistance) const;

 private:
  std::vector<cv::Mat> octaves_;
};

}  // namespace mdbrief::detail
