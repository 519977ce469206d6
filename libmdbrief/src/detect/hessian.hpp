#pragma once
// The scale-space blob detector (DetectorMethod::Hessian): the determinant of the Hessian on
// every level of the shared ImagePyramid, at a fixed smoothing in level pixels, so responses
// are scale-normalised and compare across levels (Lindeberg; SURF's and AKAZE's response).
// Maxima over space and over the two neighbouring levels, refined to sub-pixel position and
// sub-level scale by fitting parabolas to the response.
#include <functional>
#include <optional>
#include <tuple>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/gaussian_smoothing.hpp"
#include "mdbrief/detect/image_pyramid.hpp"

namespace mdbrief::detail {

// hessianLevel's response at single pixels, the same bits, from the level's pixels around them:
// for the finest level, on which no maximum is searched and which only the next level's
// candidates read, 3x3 pixels each (a few thousand of its half million).
class PointResponse {
 public:
  // Throws std::invalid_argument for what hessianLevel refuses. The level must outlive it.
  PointResponse(const cv::Mat& level8u, double sigma);
  // Whether `value` exceeds the response at every pixel of the 3x3 neighbourhood of (cx, cy),
  // and the largest of them in `largest`: -inf, and no pixel read, when (cx, cy) is on the
  // border or outside.
  bool exceedsNeighbourhood(int cx, int cy, float value, float& largest) const;
  // Asks the cache for what exceedsNeighbourhood(cx, cy, ...) reads.
  void prefetch(int cx, int cy) const { smoother_.prefetch(cx, cy); }

 private:
  GaussianBlockSmoother smoother_;
  float scale_;
};

// One level of the detector, from a single top-to-bottom pass: each row smoothed, differentiated
// and searched while it is in the cache, without the level-sized float image that was written
// and read back. Or, for a level read at a few pixels only (hessianPoints), its response there.
struct HessianLevel {
  cv::Mat bytes;     // CV_8U: the smoothed level (gaussian_smoothing.hpp), what the descriptors sample
  cv::Mat response;  // CV_32F: det(Hessian) * sigma^4, borders reflected as BORDER_REFLECT_101
  // Pixels at least `margin` from the border whose response exceeds the threshold and each of
  // its 8 neighbours, in scan order (with findCandidates).
  std::vector<cv::Point> candidates;
  std::optional<PointResponse> points;  // instead of the three above (hessianPoints)
};

// level8u smoothed by a Gaussian of `sigma` level pixels (hessianTaps wide; the intensities in
// [0, 1]), then the determinant of the Hessian from central second differences, scaled by sigma^4
// so that responses compare across levels.
HessianLevel hessianLevel(const cv::Mat& level8u, double sigma, bool findCandidates, float threshold, int margin);
// The same level's response pixel by pixel, as the next level's maxima read it (PointResponse).
HessianLevel hessianPoints(const cv::Mat& level8u, double sigma);

// The smoothing width of the Hessian detector's sigma: truncated at 3 sigma. OpenCV's default
// for float images reaches 4 sigma, a third more taps for weights below 0.3 % of the total.
int hessianTaps(double sigma);

struct Blob {
  int level = 0;
  int x = 0, y = 0;         // integer maximum, level pixels
  float dx = 0.f, dy = 0.f;  // sub-pixel offset, level pixels, in [-0.5, 0.5]
  float dlevel = 0.f;        // sub-level offset in [-0.5, 0.5]
  float response = 0.f;
};

// Strict order: stronger first, then level, y, x (output independent of the scan order). Inline:
// the budget's selection calls it for every comparison.
inline bool strongerBlob(const Blob& a, const Blob& b) {
  if (a.response != b.response) return a.response > b.response;
  return std::tie(a.level, a.y, a.x) < std::tie(b.level, b.y, b.x);
}

// Of the candidates of levels[k], 0 < k < levels - 1, those that also exceed the 3x3
// neighbourhoods around their position on levels k - 1 and k + 1 (grids[k]: where level k's
// pixels lie in the input) and for which allowed(level, x, y) holds, refined. Level 0 may be
// hessianPoints'.
std::vector<Blob> hessianMaxima(const std::vector<HessianLevel>& levels, const std::vector<LevelGrid>& grids,
                                const std::function<bool(int, int, int)>& allowed);

}  // namespace mdbrief::detail
