#pragma once
// The scale-space blob detector (DetectorMethod::Hessian): the determinant of the Hessian on
// every level of the shared ImagePyramid, at a fixed smoothing in level pixels, so responses
// are scale-normalised and compare across levels (Lindeberg; SURF's and AKAZE's response).
// Maxima over space and over the two neighbouring levels, refined to sub-pixel position and
// sub-level scale by fitting parabolas to the response.
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/detect/image_pyramid.hpp"

namespace mdbrief::detail {

// det(Hessian) * sigma^4 of a level already smoothed by a Gaussian of `sigma` level pixels
// (CV_32F intensities in [0, 1]): CV_32F of the level's size.
cv::Mat hessianResponse(const cv::Mat& smoothed, double sigma);

// A level (8UC1) smoothed by a Gaussian of `sigma` level pixels truncated at 3 sigma, as CV_32F
// intensities in [0, 1]: what hessianResponse takes when the pyramid's own smoothing differs.
cv::Mat gaussianSmoothed(const cv::Mat& level, double sigma);

struct Blob {
  int level = 0;
  int x = 0, y = 0;         // integer maximum, level pixels
  float dx = 0.f, dy = 0.f;  // sub-pixel offset, level pixels, in [-0.5, 0.5]
  float dlevel = 0.f;        // sub-level offset in [-0.5, 0.5]
  float response = 0.f;
};

// Strict order: stronger first, then level, y, x (output independent of the scan order).
bool strongerBlob(const Blob& a, const Blob& b);

// Maxima of responses[k], 0 < k < levels - 1, that exceed `threshold`, every 3x3 neighbour on
// their level and the 3x3 neighbourhoods around their position on levels k - 1 and k + 1 (grids[k]:
// where level k's pixels lie in the input). Only positions at least `margin` level pixels from
// the level's border for which allowed(level, x, y) holds are considered.
std::vector<Blob> hessianMaxima(const std::vector<cv::Mat>& responses, const std::vector<LevelGrid>& grids,
                                float threshold, int margin,
                                const std::function<bool(int, int, int)>& allowed);

}  // namespace mdbrief::detail
