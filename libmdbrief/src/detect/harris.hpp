#pragma once
// Harris corner score at one pixel, as ORB ranks its FAST corners.
#include <opencv2/core.hpp>

namespace mdbrief::detail {

// Harris response det(M) - k trace(M)^2 of the structure tensor M summed over a
// blockSize x blockSize window centred on (x, y), with 3x3 Sobel gradients normalised to
// [-1, 1] and M averaged over the window, so scores do not depend on the window's area.
// Gradients are computed per window: whole-level gradient images measured slower (mostly
// their allocation). blockSize: odd, 3..15. The caller guarantees blockSize / 2 + 1 pixels
// of image around (x, y).
float harrisResponse(const cv::Mat& image, int x, int y, int blockSize, double k);

}  // namespace mdbrief::detail
